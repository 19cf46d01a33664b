//! Interval location in constant time, and the 1-D kernels (linear, Catmull-Rom/Hermite).

/// Maps a coordinate to the interval of a sorted angle array containing it, in O(1): a uniform
/// bin table whose bins are narrower than the smallest interval (capped at [`MAX_BINS`] bins).
/// Each bin stores the interval containing its start and the next knot, so when the bins are
/// that narrow ("tight") a lookup is one load, one comparison and no branch; a capped table
/// finishes with a short linear walk.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct IntervalTable {
    /// `1 / width` and `−start / width − 1/2`: `x · scale + offset` is the bin coordinate minus
    /// one half, whose rounding to nearest is the bin index.
    scale: f64,
    offset: f64,
    bins: Vec<Bin>,
    /// Every bin holds at most one knot: one step at most after the bin.
    tight: bool,
}

/// One bin of an [`IntervalTable`]: the interval `first` containing the bin's start, and
/// `split = a[first + 1]` (+∞ for the last interval), where the next interval begins.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Bin {
    split: f64,
    first: u32,
}

/// Adding 1.5·2⁵² to a value in \[0, 2⁵¹) rounds it to an integer, in the low bits of the sum.
const ROUND: f64 = 6_755_399_441_055_744.0;

/// Largest deviation of the knots of a uniform [`Axis`] from `a0 + i·step`, relative to the
/// step. Angles converted from degrees deviate by a few ulps of 2π, 10⁻¹³ of a 0.5° step.
const UNIFORM_TOLERANCE: f64 = 1e-12;

/// Bias (in steps) of the interval index of a uniform [`Axis`]: above [`UNIFORM_TOLERANCE`] and
/// the rounding of `(x − a0)/step` (a few ulps of the number of steps, < 2⁻⁴⁰ up to 2¹² steps).
const BIAS: f64 = 1e-9;

/// Upper bound on the number of bins of an [`IntervalTable`].
pub(crate) const MAX_BINS: usize = 1 << 14;

impl IntervalTable {
    /// Builds the table for `a` (strictly increasing, at least 2 values).
    pub fn new(a: &[f64]) -> Self {
        let n = a.len();
        debug_assert!(n >= 2);
        let range = a[n - 1] - a[0];
        let min_gap = a
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min);
        let bins_f = (range / min_gap).ceil() + 1.0;
        let (bins, tight) = if bins_f.is_finite() && bins_f <= MAX_BINS as f64 {
            ((bins_f as usize).max(1), true)
        } else {
            (MAX_BINS, false)
        };
        let width = range / bins as f64;
        let mut first = Vec::with_capacity(bins);
        let mut i = 0usize;
        for b in 0..bins {
            let x = a[0] + b as f64 * width;
            while i + 2 < n && a[i + 1] <= x {
                i += 1;
            }
            let split = if i + 2 < n { a[i + 1] } else { f64::INFINITY };
            first.push(Bin {
                split,
                first: i as u32,
            });
        }
        let scale = if width > 0.0 { 1.0 / width } else { 0.0 };
        IntervalTable {
            scale,
            offset: -a[0] * scale - 0.5,
            bins: first,
            tight,
        }
    }

    /// The index `i ∈ [0, n − 2]` with `a[i] ≤ x ≤ a[i + 1]` for `x` within `[a[0], a[n−1]]`
    /// (up to the rounding of the bin index: within an ulp of a knot the neighbouring interval
    /// may be returned, where both interpolate to the same value).
    #[inline(always)]
    pub fn find(&self, a: &[f64], x: f64) -> usize {
        let b = floor_index(x * self.scale + self.offset, self.bins.len() - 1);
        let bin = self.bins[b];
        let mut i = bin.first as usize + (x >= bin.split) as usize;
        if !self.tight {
            let last = a.len() - 2;
            while i < last && x >= a[i + 1] {
                i += 1;
            }
        }
        i
    }
}

/// `min(round(max(y, 0)), max)` (ties to even) for `y` < 2⁵¹, by adding 1.5·2⁵², which leaves
/// the integer in the low bits of the sum: no saturating float-to-integer conversion, no
/// branch. With `y = q − 1/2` it is `floor(q)`, or one less when `q` is an odd integer.
#[inline(always)]
fn floor_index(y: f64, max: usize) -> usize {
    let r = y.max(0.0) + ROUND;
    (r.to_bits() as u32 as usize).min(max)
}

/// A sorted angle axis prepared for constant-time evaluation: the interval table, per interval
/// its lower knot and reciprocal width (so the fraction is a multiplication), and per interval
/// the Hermite weights of `hermite` folded into coefficients (see [`CubicSegment`]).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Axis {
    /// First and last knot.
    pub lo: f64,
    pub hi: f64,
    /// The cubic neighbours wrap around (type C horizontal axis: `a` spans one period, 2π).
    periodic: bool,
    /// Evenly spaced knots (to [`UNIFORM_TOLERANCE`] of the step): the interval is found by
    /// arithmetic, `x · scale + offset` being `(x − a0)/step − 1/2 + BIAS`, rounded (see
    /// [`locate`](Self::locate)).
    uniform: bool,
    scale: f64,
    offset: f64,
    /// For uneven knots.
    table: IntervalTable,
    /// `[a_i, 1 / (a_{i+1} − a_i), 1 / (a_i − a_{i−1})]` per interval (the last one 0 for the
    /// first interval).
    knots: Vec<[f64; 3]>,
    /// Hermite segment per interval.
    cubic: Vec<CubicSegment>,
}

impl Axis {
    /// `a` strictly increasing with at least 2 values; `period` (type C horizontal axis: 2π,
    /// `a` spanning exactly one period) makes the cubic neighbours wrap around.
    pub fn new(a: &[f64], period: Option<f64>) -> Axis {
        let n = a.len();
        let knots = (0..n - 1)
            .map(|i| {
                let prev = if i > 0 { 1.0 / (a[i] - a[i - 1]) } else { 0.0 };
                [a[i], 1.0 / (a[i + 1] - a[i]), prev]
            })
            .collect();
        let periodic = period.is_some() && n > 2;
        let p = period.unwrap_or(0.0);
        let cubic = (0..n - 1)
            .map(|i| {
                let [i0, _, _, i3] = neighbours(i, n, periodic);
                // a wrapped neighbour lies one period away
                let x0 = if periodic && i == 0 { a[i0] - p } else { a[i0] };
                let x3 = if periodic && i + 2 >= n {
                    a[i3] + p
                } else {
                    a[i3]
                };
                CubicSegment::new([x0, a[i], a[i + 1], x3])
            })
            .collect();
        let step = (a[n - 1] - a[0]) / (n - 1) as f64;
        let uniform = step > 0.0
            && a.iter()
                .enumerate()
                .all(|(i, &x)| (x - (a[0] + i as f64 * step)).abs() <= UNIFORM_TOLERANCE * step);
        let scale = if uniform { 1.0 / step } else { 0.0 };
        Axis {
            lo: a[0],
            hi: a[n - 1],
            periodic,
            uniform,
            scale,
            offset: -a[0] * scale - 0.5 + BIAS,
            table: IntervalTable::new(a),
            knots,
            cubic,
        }
    }

    /// The interval `i` containing `x` (within `[lo, hi]`, which the caller checks) and the
    /// fraction `(x − a_i) / (a_{i+1} − a_i)`, as `(x − a_i) · (1 / (a_{i+1} − a_i))` (clamped to
    /// \[0, 1\], which it leaves only by rounding).
    ///
    /// Uniform axis: `i = round((x − a0)/step − 1/2 + BIAS)`, which is never below the interval
    /// of `x` (the bias exceeds the knots' deviation from an exact grid and the rounding of the
    /// quotient) and above it only for `x` less than `BIAS` steps below a knot; there `x < a_i`
    /// and the fraction in interval `i − 1` is `1 + (x − a_i) / (a_i − a_{i−1})`. So one load
    /// and a branch that is almost never taken: no comparison with a table entry first.
    #[inline(always)]
    pub fn locate(&self, a: &[f64], x: f64) -> (usize, f64) {
        if self.uniform {
            let i = floor_index(x * self.scale + self.offset, self.knots.len() - 1);
            let [k, inv, inv_prev] = self.knots[i];
            let d = x - k;
            if d >= 0.0 || i == 0 {
                (i, (d * inv).clamp(0.0, 1.0))
            } else {
                (i - 1, (1.0 + d * inv_prev).clamp(0.0, 1.0))
            }
        } else {
            let i = self.table.find(a, x);
            let [k, inv, _] = self.knots[i];
            (i, ((x - k) * inv).clamp(0.0, 1.0))
        }
    }

    /// The knot spacing when the knots are evenly spaced (to [`UNIFORM_TOLERANCE`] of it).
    pub fn step(&self) -> Option<f64> {
        self.uniform
            .then(|| (self.hi - self.lo) / self.knots.len() as f64)
    }

    /// The Hermite segment of interval `i`.
    #[inline(always)]
    pub fn segment(&self, i: usize) -> &CubicSegment {
        &self.cubic[i]
    }

    /// The indices of the four values of interval `i`'s Hermite segment (each below `n`, the
    /// number of knots).
    #[inline(always)]
    pub fn neighbours(&self, i: usize) -> [usize; 4] {
        neighbours(i, self.knots.len() + 1, self.periodic)
    }
}

/// Indices `[i − 1, i, i + 1, i + 2]` of the values around interval `i` of `n` knots (`i` is
/// clamped to `n − 2`): a missing neighbour is the interval's own end (as `hermite` expects), or
/// with `periodic` (knots 0 and n − 1 the same point) the one on the far side of the seam.
#[inline(always)]
fn neighbours(i: usize, n: usize, periodic: bool) -> [usize; 4] {
    let i = i.min(n - 2);
    let i0 = if i > 0 {
        i - 1
    } else if periodic {
        n - 2
    } else {
        0
    };
    let i3 = if i + 2 < n {
        i + 2
    } else if periodic {
        1
    } else {
        n - 1
    };
    [i0, i, i + 1, i3]
}

/// `hermite` on one interval with its neighbours fixed, as weights: the value at fraction `t`
/// is `Σ_k w_k(t)·p[n_k]` over the neighbours `n` of [`Axis::neighbours`], with
/// `w = h00·e1 + h01·e2 + h10·dm1 + h11·dm2` (the cubic Hermite basis; `dm1`, `dm2` the interval
/// width times the tangents' coefficients). One cache line.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(align(64))]
pub(crate) struct CubicSegment {
    dm1: [f64; 4],
    dm2: [f64; 4],
}

impl CubicSegment {
    /// The segment on `[xs[1], xs[2]]`, with the tangent rules of `hermite` (missing
    /// neighbour: `xs[0] == xs[1]` or `xs[3] == xs[2]`).
    fn new(xs: [f64; 4]) -> CubicSegment {
        let d = xs[2] - xs[1];
        let has_left = xs[0] < xs[1];
        let has_right = xs[3] > xs[2];
        let secant = [0.0, -1.0 / d, 1.0 / d, 0.0];
        // m1 = secant + (secant − s2)·f = (1 + f)·secant − f·s2, s2 = (p3 − p2)/d2
        let m1 = if has_left {
            let e = 1.0 / (xs[2] - xs[0]);
            [-e, 0.0, e, 0.0]
        } else if has_right {
            let d2 = xs[3] - xs[2];
            let f = d / (d + d2);
            [0.0, -(1.0 + f) / d, (1.0 + f) / d + f / d2, -f / d2]
        } else {
            secant
        };
        // m2 = (1 + f)·secant − f·s0, s0 = (p1 − p0)/d0
        let m2 = if has_right {
            let e = 1.0 / (xs[3] - xs[1]);
            [0.0, -e, 0.0, e]
        } else if has_left {
            let d0 = xs[1] - xs[0];
            let f = d / (d + d0);
            [f / d0, -(1.0 + f) / d - f / d0, (1.0 + f) / d, 0.0]
        } else {
            secant
        };
        CubicSegment {
            dm1: m1.map(|c| c * d),
            dm2: m2.map(|c| c * d),
        }
    }

    /// The four weights at fraction `t`.
    #[inline(always)]
    pub fn weights(&self, t: f64) -> [f64; 4] {
        let t2 = t * t;
        let t3 = t2 * t;
        let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
        let h10 = t3 - 2.0 * t2 + t;
        let h01 = -2.0 * t3 + 3.0 * t2;
        let h11 = t3 - t2;
        let w = |k: usize| h10 * self.dm1[k] + h11 * self.dm2[k];
        [w(0), h00 + w(1), h01 + w(2), w(3)]
    }
}

/// Reference interval search by bisection (same contract as [`IntervalTable::find`]).
#[inline]
#[cfg(test)]
pub(crate) fn find_bisect(a: &[f64], x: f64) -> usize {
    let p = a.partition_point(|&v| v <= x);
    p.saturating_sub(1).min(a.len() - 2)
}

/// Cubic Hermite interpolation on `[xs[1], xs[2]]` with Catmull-Rom tangents generalised to
/// uneven spacing, `m_k = (p_{k+1} − p_{k−1}) / (x_{k+1} − x_{k−1})`. Where a neighbour is missing
/// (`xs[0] == xs[1]` or `xs[3] == xs[2]`, at the ends of a non-periodic axis) the tangent is the
/// three-point one-sided difference (derivative of the parabola through the three available
/// points), which keeps the end intervals second-order accurate; with only two points it is the
/// secant (linear interpolation).
#[cfg(test)]
pub(crate) fn hermite(x: f64, xs: [f64; 4], ps: [f64; 4]) -> f64 {
    let d = xs[2] - xs[1];
    let t = (x - xs[1]) / d;
    let secant = (ps[2] - ps[1]) / d;
    let has_left = xs[0] < xs[1];
    let has_right = xs[3] > xs[2];
    let m1 = if has_left {
        (ps[2] - ps[0]) / (xs[2] - xs[0])
    } else if has_right {
        let d2 = xs[3] - xs[2];
        let s2 = (ps[3] - ps[2]) / d2;
        secant + (secant - s2) * d / (d + d2)
    } else {
        secant
    };
    let m2 = if has_right {
        (ps[3] - ps[1]) / (xs[3] - xs[1])
    } else if has_left {
        let d0 = xs[1] - xs[0];
        let s0 = (ps[1] - ps[0]) / d0;
        secant + (secant - s0) * d / (d + d0)
    } else {
        secant
    };
    let t2 = t * t;
    let t3 = t2 * t;
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + t;
    let h01 = -2.0 * t3 + 3.0 * t2;
    let h11 = t3 - t2;
    h00 * ps[1] + h10 * d * m1 + h01 * ps[2] + h11 * d * m2
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn table_agrees_with_bisection(
            gaps in proptest::collection::vec(1e-3f64..10.0, 1..60),
            u in 0.0f64..=1.0,
        ) {
            let mut a = vec![0.0];
            for g in gaps { let l = *a.last().unwrap(); a.push(l + g); }
            let t = IntervalTable::new(&a);
            let x = a[0] + u * (a[a.len() - 1] - a[0]);
            let i = t.find(&a, x);
            prop_assert!(a[i] <= x && x <= a[i + 1]);
            prop_assert_eq!(i, find_bisect(&a, x));
            for (k, &ak) in a.iter().enumerate() {
                prop_assert_eq!(t.find(&a, ak), k.min(a.len() - 2));
            }
        }
    }

    /// Knots in radians from degrees: evenly spaced (`step` > 0) or with random gaps.
    fn knots(step: f64, gaps: &[f64], start: f64) -> Vec<f64> {
        let mut deg = vec![start];
        for g in gaps {
            let last = *deg.last().unwrap();
            deg.push(last + if step > 0.0 { step } else { *g });
        }
        deg.iter().map(|d| d.to_radians()).collect()
    }

    proptest! {
        #[test]
        fn axis_locate_agrees_with_bisection(
            step in prop_oneof![Just(0.0), Just(1.5), Just(2.5), Just(5.0), Just(22.5), 0.1f64..30.0],
            gaps in proptest::collection::vec(1e-3f64..10.0, 1..80),
            start in prop_oneof![Just(0.0), Just(-90.0), Just(90.0), -90.0f64..90.0],
            u in proptest::collection::vec(0.0f64..=1.0, 16),
        ) {
            let a = knots(step, &gaps, start);
            let n = a.len();
            let axis = Axis::new(&a, None);
            if step > 0.0 {
                prop_assert!(axis.uniform);
            }
            let mut xs: Vec<f64> = u.iter().map(|u| a[0] + u * (a[n - 1] - a[0])).collect();
            for &k in &a {
                xs.extend([k, k.next_up(), k.next_down()]);
            }
            for x in xs {
                if !(x >= a[0] && x <= a[n - 1]) {
                    continue;
                }
                let (i, t) = axis.locate(&a, x);
                let j = find_bisect(&a, x);
                let exact = (x - a[j]) / (a[j + 1] - a[j]);
                // the same interval, or at a shared knot the neighbouring one with t at the end
                if i == j {
                    prop_assert!((t - exact).abs() <= 4.0 * f64::EPSILON, "{x} {i} {t} {exact}");
                } else {
                    prop_assert!(i + 1 == j || j + 1 == i, "{x}: {i} vs {j}");
                    let (ti, tj) = if i < j { (1.0 - t, exact) } else { (t, 1.0 - exact) };
                    prop_assert!(ti.abs() <= 4.0 * f64::EPSILON && tj.abs() <= 4.0 * f64::EPSILON,
                        "{x}: ({i}, {t}) vs ({j}, {exact})");
                }
            }
        }

        #[test]
        fn cubic_segment_weights_reproduce_hermite(
            xs in proptest::array::uniform4(0.1f64..3.0),
            ps in proptest::array::uniform4(-5.0f64..5.0),
            t in 0.0f64..=1.0,
            left in any::<bool>(),
            right in any::<bool>(),
        ) {
            // knots x0 < x1 < x2 < x3, or a missing neighbour (x0 = x1, x3 = x2)
            let x1 = xs[0];
            let x2 = x1 + xs[1];
            let x0 = if left { x1 - xs[2] } else { x1 };
            let x3 = if right { x2 + xs[3] } else { x2 };
            let k = [x0, x1, x2, x3];
            let seg = CubicSegment::new(k);
            let w = seg.weights(t);
            let got: f64 = (0..4).map(|i| w[i] * ps[i]).sum();
            let want = hermite(x1 + t * (x2 - x1), k, ps);
            prop_assert!((got - want).abs() <= 1e-12 * (1.0 + want.abs()), "{got} vs {want}");
        }
    }

    #[test]
    fn hermite_reproduces_cubics_on_uniform_grids_and_lines_everywhere() {
        // A line is reproduced exactly on any grid.
        let xs = [0.0, 1.0, 3.0, 3.5];
        let ps = xs.map(|x| 2.0 * x - 1.0);
        for k in 0..=10 {
            let x = 1.0 + 2.0 * k as f64 / 10.0;
            assert!((hermite(x, xs, ps) - (2.0 * x - 1.0)).abs() < 1e-12);
        }
        // Interpolates the end points.
        let ps = [3.0, 1.0, 4.0, 1.5];
        assert_eq!(hermite(1.0, xs, ps), 1.0);
        assert!((hermite(3.0, xs, ps) - 4.0).abs() < 1e-12);
        // Catmull-Rom reproduces quadratics on a uniform grid.
        let xs = [0.0, 1.0, 2.0, 3.0];
        let ps = xs.map(|x| x * x);
        assert!((hermite(1.5, xs, ps) - 2.25).abs() < 1e-12);
    }
}
