//! Globally adaptive Gauss–Kronrod (7/15-point) quadrature of vector-valued functions.
//!
//! The integration interval is first split at caller-supplied break points (the kinks and jumps
//! of the integrand: cone edges, the smoothstep start, the IES grid lines, π/2 for `|cos θ|`);
//! every sub-interval gets the 15-point Kronrod rule and the embedded 7-point Gauss rule, whose
//! difference is the error estimate. The interval with the largest (scaled) error is bisected
//! until every component meets `err ≤ rel · |integral|` (components below 10⁻⁶ of the largest
//! are held to the absolute accuracy `rel · 10⁻⁶ · max`), or the interval budget is spent.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Kronrod abscissae on \[−1, 1\] (non-negative half, descending; the last one is 0).
/// Odd indices are the 7-point Gauss abscissae.
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
/// Kronrod weights for [`XGK`].
const WGK: [f64; 8] = [
    0.022_935_322_010_529_225,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_18,
    0.140_653_259_715_525_92,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_83,
];
/// 7-point Gauss weights for `XGK[1], XGK[3], XGK[5], XGK[7]`.
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// One GK15 panel: the Kronrod value and the per-component |Kronrod − Gauss|.
fn gk15<const N: usize>(f: &mut impl FnMut(f64) -> [f64; N], a: f64, b: f64) -> Panel<N> {
    let c = 0.5 * (a + b);
    let h = 0.5 * (b - a);
    let mut k = [0.0; N];
    let mut g = [0.0; N];
    let mut add = |x: f64, wk: f64, wg: f64| {
        let v = f(x);
        for i in 0..N {
            let v = if v[i].is_finite() { v[i] } else { 0.0 };
            k[i] += wk * v;
            g[i] += wg * v;
        }
    };
    add(c, WGK[7], WG[3]);
    for j in 0..7 {
        let wg = if j % 2 == 1 { WG[j / 2] } else { 0.0 };
        let dx = h * XGK[j];
        add(c - dx, WGK[j], wg);
        add(c + dx, WGK[j], wg);
    }
    let mut err = [0.0; N];
    for i in 0..N {
        k[i] *= h;
        err[i] = (k[i] - g[i] * h).abs();
    }
    Panel {
        a,
        b,
        value: k,
        err,
        priority: 0.0,
    }
}

struct Panel<const N: usize> {
    a: f64,
    b: f64,
    value: [f64; N],
    err: [f64; N],
    priority: f64,
}

impl<const N: usize> PartialEq for Panel<N> {
    fn eq(&self, other: &Self) -> bool {
        self.priority.total_cmp(&other.priority) == Ordering::Equal
    }
}
impl<const N: usize> Eq for Panel<N> {}
impl<const N: usize> PartialOrd for Panel<N> {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl<const N: usize> Ord for Panel<N> {
    fn cmp(&self, other: &Self) -> Ordering {
        self.priority.total_cmp(&other.priority)
    }
}

/// ∫ f over \[breaks\[0\], breaks\[last\]\] (breaks sorted ascending; empty or reversed pieces are
/// skipped), globally adaptive, to relative accuracy `rel` per component, with at most
/// `max_panels` panels.
pub(crate) fn integrate<const N: usize>(
    mut f: impl FnMut(f64) -> [f64; N],
    breaks: &[f64],
    rel: f64,
    max_panels: usize,
) -> [f64; N] {
    let mut panels: Vec<Panel<N>> = breaks
        .windows(2)
        .filter(|w| w[1] > w[0])
        .map(|w| gk15(&mut f, w[0], w[1]))
        .collect();
    if panels.is_empty() {
        return [0.0; N];
    }
    let sum = |ps: &[Panel<N>]| {
        let mut t = [0.0; N];
        let mut e = [0.0; N];
        for p in ps {
            for i in 0..N {
                t[i] += p.value[i];
                e[i] += p.err[i];
            }
        }
        (t, e)
    };
    let (mut total, mut err) = sum(&panels);
    // Per-component scale for the priorities, fixed after the first pass.
    let big = total.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let scale = total.map(|t| t.abs().max(1e-6 * big).max(f64::MIN_POSITIVE));
    let prio = |p: &Panel<N>| (0..N).map(|i| p.err[i] / scale[i]).fold(0.0, f64::max);
    for p in &mut panels {
        p.priority = prio(p);
    }
    let mut heap: BinaryHeap<Panel<N>> = panels.into_iter().collect();
    let converged = |total: &[f64; N], err: &[f64; N]| {
        let big = total.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        (0..N).all(|i| err[i] <= rel * total[i].abs().max(1e-6 * big))
    };
    while !converged(&total, &err) && heap.len() < max_panels {
        if total.iter().chain(err.iter()).any(|v| !v.is_finite()) {
            // overflow: refining cannot help
            break;
        }
        let Some(worst) = heap.pop() else { break };
        let m = 0.5 * (worst.a + worst.b);
        if worst.priority < 0.0 || !(m > worst.a && m < worst.b) {
            // every remaining panel is too narrow to split (or this one is): stop here
            let mut w = worst;
            w.priority = -1.0;
            let stop = heap.peek().is_none_or(|p| p.priority < 0.0);
            heap.push(w);
            if stop {
                break;
            }
            continue;
        }
        let mut l = gk15(&mut f, worst.a, m);
        let mut r = gk15(&mut f, m, worst.b);
        for i in 0..N {
            total[i] += l.value[i] + r.value[i] - worst.value[i];
            err[i] += l.err[i] + r.err[i] - worst.err[i];
        }
        l.priority = prio(&l);
        r.priority = prio(&r);
        heap.push(l);
        heap.push(r);
    }
    // re-sum from the panels (the running sums accumulate rounding)
    let panels = heap.into_vec();
    sum(&panels).0
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::PI;

    #[test]
    fn rules_integrate_polynomials_exactly() {
        // Gauss-7 is exact to degree 13, Kronrod-15 to degree 22.
        for deg in 0..=22 {
            let p = gk15(&mut |x: f64| [x.powi(deg)], -1.0, 1.0);
            let exact = if deg % 2 == 1 {
                0.0
            } else {
                2.0 / (deg as f64 + 1.0)
            };
            assert!((p.value[0] - exact).abs() < 1e-14, "K deg {deg}");
            if deg <= 13 {
                assert!(p.err[0] < 1e-14, "G deg {deg}: {}", p.err[0]);
            }
        }
        assert!(
            (WGK.iter().sum::<f64>() * 2.0 - WGK[7] - 2.0).abs() < 1e-15,
            "Kronrod weights sum to 2"
        );
        assert!((WG.iter().sum::<f64>() * 2.0 - WG[3] - 2.0).abs() < 1e-15);
    }

    #[test]
    fn adaptive_handles_smooth_singular_and_vector_integrands() {
        // ∫_0^π sin = 2, ∫_0^1 sqrt(x) = 2/3 (endpoint singularity), ∫_0^1 x^0.01 = 1/1.01
        let v = integrate(
            |x: f64| [x.sin(), 0.0, (x / PI).powf(0.01)],
            &[0.0, PI],
            1e-12,
            1000,
        );
        assert!((v[0] - 2.0).abs() < 1e-13);
        assert_eq!(v[1], 0.0);
        assert!((v[2] / PI - 1.0 / 1.01).abs() < 1e-10, "{}", v[2] / PI);
        let v = integrate(|x: f64| [x.sqrt()], &[0.0, 0.5, 1.0], 1e-12, 1000);
        assert!((v[0] - 2.0 / 3.0).abs() < 1e-11);
        // a jump that is not a break point still converges (by bisection)
        let v = integrate(
            |x: f64| [if x < 0.3 { 1.0 } else { 0.0 }],
            &[0.0, 1.0],
            1e-9,
            5000,
        );
        assert!((v[0] - 0.3).abs() < 1e-8, "{}", v[0]);
        // empty / degenerate input
        assert_eq!(integrate(|_| [1.0], &[1.0, 1.0], 1e-9, 10), [0.0]);
        assert_eq!(integrate(|_| [1.0], &[], 1e-9, 10), [0.0]);
    }
}
