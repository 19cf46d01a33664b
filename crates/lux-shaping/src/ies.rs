//! The IES part of the shaping: angle map, normalization, precomputed bounds and the
//! φ-integrated profile.

use crate::angle::AngleMap;
use crate::grid::EvenGrid;
use core::f64::consts::{FRAC_PI_2, PI, TAU};
use lux_ies::{Interpolation, PhotometricType, PhotometricWeb, Symmetry};

/// How a candela sample becomes a factor (three cases, so a chain of comparisons rather than a
/// jump table): `ies:normalize` off is `Mul(1)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Scale {
    /// Multiply by 1 / normalizer (or by 1: raw candela).
    Mul(f64),
    /// Divide by the normalizer (only when its reciprocal overflows).
    Div(f64),
    /// The normalizer is 0 (or not finite): the IES factor is 0.
    Zero,
}

impl Scale {
    #[inline(always)]
    pub(crate) fn apply(self, cd: f64) -> f64 {
        match self {
            Scale::Mul(s) => cd * s,
            Scale::Div(m) => cd / m,
            Scale::Zero => 0.0,
        }
    }
}

/// The prepared IES profile.
#[derive(Clone, Debug)]
pub(crate) struct IesPart {
    pub web: PhotometricWeb,
    pub interp: Interpolation,
    pub map: AngleMap,
    pub scale: Scale,
    /// The `ies:normalize` divisor when normalize is on.
    pub normalizer: Option<f64>,
    /// Type C: vertical angle = θ, horizontal = φ.
    pub type_c: bool,
    /// Type C with one horizontal angle: rotationally symmetric about the light axis.
    pub axial_c: bool,
    /// Per vertical interval i: an upper bound of the interpolant (candela) over
    /// `[v_i, v_{i+1}]` × every horizontal angle.
    pub band_bound: Vec<f64>,
    /// Upper bound at the last vertical angle, every horizontal angle (θies ≥ π rule).
    pub last_bound: f64,
    /// Upper bound over every direction (candela).
    pub global_bound: f64,
    /// Type C, bilinear: `∫_0^{2π} I(v_i, φ) dφ` per vertical angle (exact for the bilinear
    /// interpolant: the trapezoid rule in φ).
    pub phi_integral: Option<Vec<f64>>,
    /// Type C, bilinear, evenly spaced angles, a finite scale: the lookup of `factor`.
    pub grid: Option<EvenGrid>,
}

impl IesPart {
    pub(crate) fn new(
        web: PhotometricWeb,
        interp: Interpolation,
        map: AngleMap,
        normalize: bool,
    ) -> IesPart {
        let normalizer = normalize.then(|| web.mean_intensity());
        let scale = match normalizer {
            None => Scale::Mul(1.0),
            Some(m) if m > 0.0 && m.is_finite() => {
                let inv = 1.0 / m;
                if inv.is_finite() {
                    Scale::Mul(inv)
                } else {
                    Scale::Div(m)
                }
            }
            Some(_) => Scale::Zero,
        };
        let type_c = web.photometric_type() == PhotometricType::C;
        let axial_c = type_c && web.symmetry() == Symmetry::Axial;
        let (band_bound, last_bound) = match interp {
            Interpolation::Bilinear => bilinear_bounds(&web),
            Interpolation::Bicubic => bicubic_bounds(&web),
        };
        let global_bound = band_bound.iter().fold(last_bound, |m, &b| m.max(b));
        let phi_integral =
            (type_c && interp == Interpolation::Bilinear).then(|| phi_integral(&web));
        let grid = match scale {
            Scale::Mul(s) if interp == Interpolation::Bilinear => EvenGrid::new(&web, s),
            _ => None,
        };
        IesPart {
            web,
            interp,
            map,
            scale,
            normalizer,
            type_c,
            axial_c,
            band_bound,
            last_bound,
            global_bound,
            phi_integral,
            grid,
        }
    }

    /// The IES factor (candela, scaled) towards light-space (θ, φ).
    #[inline(always)]
    pub(crate) fn sample(&self, theta: f64, phi: f64) -> f64 {
        let t = self.map.apply(theta);
        self.scale
            .apply(self.web.intensity_with(t, phi, self.interp))
    }

    /// [`sample`](Self::sample) for `Shaping::factor`: on the profile's [`EvenGrid`] (type C,
    /// bilinear, evenly spaced angles; the normalize scale folded into its table) except for
    /// θies ≥ π beyond the last vertical angle, else `sample` itself. The two agree to
    /// `4ε·(nv + nh + 2)` of the largest value (see `grid.rs`).
    #[inline(always)]
    pub(crate) fn sample_for_factor(&self, theta: f64, phi: f64) -> f64 {
        if let Some(g) = &self.grid
            && let Some(i) = g.eval(self.map.apply(theta), phi)
        {
            return i;
        }
        self.sample(theta, phi)
    }

    /// An upper bound of the unscaled candela over light polar angles `[lo, hi]` and every φ.
    pub(crate) fn bound_theta_range(&self, lo: f64, hi: f64) -> f64 {
        if !self.type_c {
            return self.global_bound;
        }
        let (a, b) = (self.map.apply(lo), self.map.apply(hi));
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        if !(a <= b) {
            return self.global_bound;
        }
        let v = self.web.vertical_angles();
        let nv = v.len();
        let mut m: f64 = 0.0;
        if b >= PI {
            m = self.last_bound;
        }
        let lo_t = a.max(v[0]).max(0.0);
        let hi_t = b.min(v[nv - 1]);
        if lo_t <= hi_t {
            let i0 = interval(v, lo_t);
            let i1 = interval(v, hi_t);
            for &bb in &self.band_bound[i0..=i1] {
                m = m.max(bb);
            }
        }
        m
    }

    /// Pushes the light polar angles θ where the φ-integrated factor has kinks: the vertical
    /// grid angles (type C) or the tangencies of θies-circles with the native grid lines
    /// (types A/B), mapped back through the angle scale, and the θ of θies = 0, π/2, π.
    pub(crate) fn theta_kinks(&self, out: &mut Vec<f64>) {
        let mut ts: Vec<f64> = vec![0.0, FRAC_PI_2, PI];
        if self.type_c {
            ts.extend_from_slice(self.web.vertical_angles());
        } else {
            // a θies-circle (about the light axis) touches the native V = const circle (about
            // the native pole, 90° away) at t = |V| and π − |V|, and the H = const great circle
            // (whose closest approach to the axis is |H|) at t = |H| and π − |H|
            for &a in self
                .web
                .vertical_angles()
                .iter()
                .chain(self.web.horizontal_angles())
            {
                ts.push(a.abs());
                ts.push(PI - a.abs());
            }
        }
        // θies = map(θ) for θ ∈ [0, π] may leave [0, π] (types A/B then wrap periodically,
        // type C clamps by its edge rules): add the periodic images that fall in range
        let (t0, t1) = (self.map.apply(0.0), self.map.apply(PI));
        let (lo, hi) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        let periodic = !self.type_c && (lo < 0.0 || hi > PI);
        let k_lo = if periodic {
            ((lo - PI) / TAU).floor().max(-64.0) as i64
        } else {
            0
        };
        let k_hi = if periodic {
            (hi / TAU).ceil().min(64.0) as i64
        } else {
            0
        };
        for &t in &ts {
            for k in k_lo..=k_hi {
                let shift = TAU * k as f64;
                for cand in [t + shift, -t + shift] {
                    if cand >= lo && cand <= hi {
                        out.push(self.map.inverse(cand));
                    }
                }
            }
            if !periodic {
                out.push(self.map.inverse(t));
            }
        }
    }

    /// Pushes the azimuths φ where the slice at light polar angle θ crosses a grid line: the
    /// expanded horizontal angles (type C), or, for types A/B, the solutions of
    /// `V(t, φ) = V_k` and `H(t, φ) = H_j` with t = θies. Type B (light → native
    /// `x = sin t cos φ, y = −sin t sin φ, z = cos t`, `V = asin y`, `H = atan2(x, z)`):
    /// `sin φ = −sin V_k / sin t`, `cos φ = cos t · tan H_j / sin t`; type A swaps the roles of
    /// sin φ and cos φ. Spurious roots (wrong sign of the atan2) only add harmless breaks.
    pub(crate) fn phi_kinks(&self, theta: f64, out: &mut Vec<f64>) {
        if self.type_c {
            if !self.axial_c {
                out.extend_from_slice(self.web.horizontal_angles());
            }
            return;
        }
        let t = self.map.apply(theta);
        let (st, ct) = t.sin_cos();
        if !(st.abs() > 1e-300) {
            return;
        }
        let type_b = self.web.photometric_type() == PhotometricType::B;
        let mut push = |sin_eq: bool, a: f64| {
            if !(a.abs() <= 1.0) {
                return;
            }
            let (p, q) = if sin_eq {
                let p = a.asin();
                (p, PI - p)
            } else {
                let p = a.acos();
                (p, TAU - p)
            };
            out.push(p.rem_euclid(TAU));
            out.push(q.rem_euclid(TAU));
        };
        for &v in self.web.vertical_angles() {
            push(type_b, -v.sin() / st);
        }
        for &h in self.web.horizontal_angles() {
            let ch = h.cos();
            if ch.abs() > 1e-12 {
                push(!type_b, ct * h.sin() / ch / st);
            }
        }
    }

    /// `∫_0^{2π} I(t, φ) dφ` (unscaled candela · rad) at lookup angle `t` with the edge rules of
    /// `PhotometricWeb::intensity_with` (type C, bilinear only).
    pub(crate) fn phi_integrated(&self, t: f64) -> f64 {
        let m = self
            .phi_integral
            .as_ref()
            .expect("phi integral only for type C bilinear");
        let v = self.web.vertical_angles();
        let nv = v.len();
        if !(t >= 0.0) {
            return 0.0;
        }
        if t >= PI {
            return m[nv - 1];
        }
        if t < v[0] || t > v[nv - 1] {
            return 0.0;
        }
        let i = interval(v, t);
        let u = (t - v[i]) / (v[i + 1] - v[i]);
        m[i] + u * (m[i + 1] - m[i])
    }
}

/// Index `i ∈ [0, n − 2]` of the interval of the sorted `v` that contains `x`.
fn interval(v: &[f64], x: f64) -> usize {
    v.partition_point(|&a| a <= x)
        .saturating_sub(1)
        .min(v.len() - 2)
}

/// Row `k` (expanded horizontal plane) of the web's values.
fn row(web: &PhotometricWeb, k: usize) -> &[f64] {
    let nv = web.vertical_angles().len();
    &web.values()[k * nv..(k + 1) * nv]
}

fn bilinear_bounds(web: &PhotometricWeb) -> (Vec<f64>, f64) {
    let nv = web.vertical_angles().len();
    let nh = web.horizontal_angles().len();
    let mut band = vec![0.0f64; nv - 1];
    let mut last: f64 = 0.0;
    for k in 0..nh {
        let r = row(web, k);
        for i in 0..nv - 1 {
            band[i] = band[i].max(r[i]).max(r[i + 1]);
        }
        last = last.max(r[nv - 1]);
    }
    (band, last)
}

/// Bounds `|d·m1|` and `|d·m2|` of the cubic Hermite segment on `[xs[1], xs[2]]` with the
/// tangents lux-ies uses (Catmull-Rom generalised to uneven spacing, three-point one-sided
/// tangents at open ends, the secant with two points), for values with `|p_a − p_b| ≤ dp(a, b)`.
fn tangent_bounds(xs: [f64; 4], dp: impl Fn(usize, usize) -> f64) -> (f64, f64) {
    let d = xs[2] - xs[1];
    let has_left = xs[0] < xs[1];
    let has_right = xs[3] > xs[2];
    let m1 = if has_left {
        d / (xs[2] - xs[0]) * dp(2, 0)
    } else if has_right {
        let d2 = xs[3] - xs[2];
        dp(2, 1) * (1.0 + d / (d + d2)) + dp(3, 2) * d * d / (d2 * (d + d2))
    } else {
        dp(2, 1)
    };
    let m2 = if has_right {
        d / (xs[3] - xs[1]) * dp(3, 1)
    } else if has_left {
        let d0 = xs[1] - xs[0];
        dp(2, 1) * (1.0 + d / (d + d0)) + dp(1, 0) * d * d / (d0 * (d + d0))
    } else {
        dp(2, 1)
    };
    (m1, m2)
}

/// `max |t(1 − t)²|` = `max |t²(t − 1)|` on \[0, 1\]: the Hermite tangent basis functions.
const H_TANGENT_MAX: f64 = 4.0 / 27.0;

/// Bounds for the bicubic interpolant (which may overshoot the tabulated values).
///
/// A cubic Hermite segment `h00·p1 + h01·p2 + h10·d·m1 + h11·d·m2` is at most
/// `max(p1, p2) + 4/27·(|d·m1| + |d·m2|)` (h00, h01 ≥ 0 with sum 1; |h10|, |h11| ≤ 4/27). In the
/// vertical direction the tangents are known from the values; in the horizontal direction the
/// four row values are only known to lie in `[0, P_k]` (each row is clamped at 0 and bounded
/// above), so `|p_a − p_b| ≤ max(P_a, P_b)`.
fn bicubic_bounds(web: &PhotometricWeb) -> (Vec<f64>, f64) {
    let v = web.vertical_angles();
    let h = web.horizontal_angles();
    let nv = v.len();
    let nh = h.len();
    // vertical bound of each row on each interval
    let vb: Vec<Vec<f64>> = (0..nh)
        .map(|k| {
            let r = row(web, k);
            (0..nv - 1)
                .map(|i| {
                    let idx = [i.saturating_sub(1), i, i + 1, (i + 2).min(nv - 1)];
                    let xs = idx.map(|j| v[j]);
                    let ps = idx.map(|j| r[j]);
                    let (m1, m2) = tangent_bounds(xs, |a, b| (ps[a] - ps[b]).abs());
                    (ps[1].max(ps[2]) + H_TANGENT_MAX * (m1 + m2)).max(0.0)
                })
                .collect()
        })
        .collect();
    let last_vals: Vec<f64> = (0..nh).map(|k| row(web, k)[nv - 1].max(0.0)).collect();
    let constant_h = web.symmetry() == Symmetry::Axial;
    if constant_h {
        return (vb[0].clone(), last_vals[0]);
    }
    let periodic = web.photometric_type() == PhotometricType::C;
    // bound over horizontal interval j for per-row bounds p
    let hbound = |p: &dyn Fn(usize) -> f64, j: usize| -> f64 {
        let (i0, x0) = if j > 0 {
            (j - 1, h[j - 1])
        } else if periodic && nh > 2 {
            (nh - 2, h[nh - 2] - TAU)
        } else {
            (j, h[j])
        };
        let (i3, x3) = if j + 2 < nh {
            (j + 2, h[j + 2])
        } else if periodic && nh > 2 {
            (1, h[1] + TAU)
        } else {
            (j + 1, h[j + 1])
        };
        let ks = [i0, j, j + 1, i3];
        let xs = [x0, h[j], h[j + 1], x3];
        let pk = ks.map(p);
        let (m1, m2) = tangent_bounds(xs, |a, b| pk[a].max(pk[b]));
        pk[1].max(pk[2]) + H_TANGENT_MAX * (m1 + m2)
    };
    let band: Vec<f64> = (0..nv - 1)
        .map(|i| {
            (0..nh - 1)
                .map(|j| hbound(&|k| vb[k][i], j))
                .fold(0.0, f64::max)
        })
        .collect();
    let last = (0..nh - 1)
        .map(|j| hbound(&|k| last_vals[k], j))
        .fold(0.0, f64::max);
    (band, last)
}

/// `∫_0^{2π} I(v_i, φ) dφ` per vertical angle for the bilinear interpolant of a type C web.
fn phi_integral(web: &PhotometricWeb) -> Vec<f64> {
    let h = web.horizontal_angles();
    let nv = web.vertical_angles().len();
    let nh = h.len();
    let mut m = vec![0.0; nv];
    for j in 0..nh - 1 {
        let half = 0.5 * (h[j + 1] - h[j]);
        let (r0, r1) = (row(web, j), row(web, j + 1));
        for i in 0..nv {
            m[i] += half * (r0[i] + r1[i]);
        }
    }
    m
}
