//! Interval location in constant time, and the 1-D kernels (linear, Catmull-Rom/Hermite).

/// Maps a coordinate to the interval of a sorted angle array containing it, in O(1): a uniform
/// bin table whose bins are no wider than the smallest interval (capped at [`MAX_BINS`] bins),
/// so that at most a step or two of linear search follows the table lookup.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct IntervalTable {
    start: f64,
    inv_width: f64,
    first: Vec<u32>,
}

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
        let bins = if bins_f.is_finite() {
            (bins_f as usize).clamp(1, MAX_BINS)
        } else {
            MAX_BINS
        };
        let width = range / bins as f64;
        let mut first = Vec::with_capacity(bins);
        let mut i = 0usize;
        for b in 0..bins {
            let x = a[0] + b as f64 * width;
            while i + 2 < n && a[i + 1] <= x {
                i += 1;
            }
            first.push(i as u32);
        }
        IntervalTable {
            start: a[0],
            inv_width: if width > 0.0 { 1.0 / width } else { 0.0 },
            first,
        }
    }

    /// The index `i ∈ [0, n − 2]` with `a[i] ≤ x ≤ a[i + 1]` for `x` within `[a[0], a[n−1]]`.
    #[inline(always)]
    pub fn find(&self, a: &[f64], x: f64) -> usize {
        let b = ((x - self.start) * self.inv_width) as usize;
        let b = if b >= self.first.len() {
            self.first.len() - 1
        } else {
            b
        };
        let mut i = self.first[b] as usize;
        let last = a.len() - 2;
        while i < last && x >= a[i + 1] {
            i += 1;
        }
        i
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
#[inline(always)]
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
