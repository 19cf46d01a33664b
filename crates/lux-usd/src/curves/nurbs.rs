//! UsdGeomNurbsCurves: `order`, `knots`, `ranges` and `pointWeights` checked against the schema,
//! the knot spans a curve is drawn over, and de Boor's algorithm.
//!
//! A curve of `n` control points and order `k` (degree `p = k − 1`) has `n + k` knots
//! `t[0] ≤ … ≤ t[n + k − 1]`; it is defined over `[t[k − 1], t[n]]`, or the authored `ranges`
//! entry within it, as the rational B-spline
//! `C(u) = Σ N_{i,p}(u)·w_i·P_i / Σ N_{i,p}(u)·w_i` (`w_i` = `pointWeights`, 1 when unauthored;
//! the points are not pre-weighted). It is evaluated by de Boor's algorithm on the homogeneous
//! points `(w·P, w)`; vertex-interpolated primvars (widths, colours) go through the same
//! rational basis.

use super::primvar::Value;
use glam::DVec2;

/// One curve's checked parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NurbsParams {
    /// `order[i]`: degree + 1.
    pub order: usize,
    /// Index of the curve's first knot in `knots`.
    pub first_knot: usize,
    /// The parameter range drawn.
    pub range: [f64; 2],
}

/// Checks one curve of `n` control points: `order` in `1..=n`, its `n + order` knots (starting
/// at `knots[0]`) finite and non-decreasing, and the authored `range` (`None` when `ranges` is
/// not authored) within `[t[k − 1], t[n]]` with min < max.
///
/// `Err` when the curve cannot be drawn; else the range to draw, with a note when the authored
/// range was clamped or replaced by the knots' own.
pub fn check(
    n: usize,
    order: i64,
    knots: &[f64],
    range: Option<DVec2>,
) -> Result<([f64; 2], Option<&'static str>), &'static str> {
    let k = usize::try_from(order).map_err(|_| "order is not positive")?;
    if k == 0 {
        return Err("order is not positive");
    }
    if k > n {
        return Err("order is larger than the vertex count");
    }
    if knots.len() != n + k {
        return Err("knots has the wrong length for the vertex count and order");
    }
    if knots.iter().any(|t| !t.is_finite()) || knots.windows(2).any(|w| w[1] < w[0]) {
        return Err("knots are not finite and non-decreasing");
    }
    let (lo, hi) = (knots[k - 1], knots[n]);
    if lo >= hi {
        return Err("the knots leave an empty parameter range");
    }
    match range {
        None => Ok(([lo, hi], None)),
        Some(r) if r.x.is_finite() && r.y.is_finite() && r.x < r.y && r.x >= lo && r.y <= hi => {
            Ok(([r.x, r.y], None))
        }
        Some(r) if r.x < r.y && r.x < hi && r.y > lo => Ok((
            [r.x.max(lo), r.y.min(hi)],
            Some("range reaches outside the knots' [t[order − 1], t[n]]; clamped to it"),
        )),
        Some(_) => Ok((
            [lo, hi],
            Some("range is empty or outside the knots; the knots' own range is drawn"),
        )),
    }
}

/// The non-empty knot spans of a curve (`knots` is its own `n + k` knots) within `range`:
/// `(i, a, b)` with `t[i] ≤ a < b ≤ t[i + 1]`, `i` in `k − 1 .. n`.
pub fn spans(order: usize, knots: &[f64], range: [f64; 2]) -> Vec<(usize, f64, f64)> {
    let n = knots.len() - order;
    (order - 1..n)
        .filter_map(|i| {
            let a = knots[i].max(range[0]);
            let b = knots[i + 1].min(range[1]);
            (a < b).then_some((i, a, b))
        })
        .collect()
}

/// de Boor's algorithm: the value at `u` (in knot span `i`, `t[i] ≤ u ≤ t[i + 1]`) of the
/// degree-`p` B-spline with `knots` and control values `cvs`. `scratch` is reused between calls.
pub fn de_boor<T: Value>(
    knots: &[f64],
    p: usize,
    i: usize,
    u: f64,
    cvs: &[T],
    scratch: &mut Vec<T>,
) -> T {
    scratch.clear();
    scratch.extend_from_slice(&cvs[i - p..=i]);
    for r in 1..=p {
        for j in (r..=p).rev() {
            let left = knots[j + i - p];
            let right = knots[j + 1 + i - r];
            let alpha = if right > left {
                (u - left) / (right - left)
            } else {
                0.0
            };
            scratch[j] = scratch[j - 1] * (1.0 - alpha) + scratch[j] * alpha;
        }
    }
    scratch[p]
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec3, DVec4};

    #[test]
    fn rational_quadratic_circle_is_exact() {
        // The nine-point circle of radius 2: quadratic, knots 0 0 0 ¼ ¼ ½ ½ ¾ ¾ 1 1 1,
        // corner weights √2/2.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let r = 2.0;
        let pts = [
            (1.0, 0.0, 1.0),
            (1.0, 1.0, h),
            (0.0, 1.0, 1.0),
            (-1.0, 1.0, h),
            (-1.0, 0.0, 1.0),
            (-1.0, -1.0, h),
            (0.0, -1.0, 1.0),
            (1.0, -1.0, h),
            (1.0, 0.0, 1.0),
        ];
        let cvs: Vec<DVec4> = pts
            .iter()
            .map(|&(x, y, w)| DVec4::new(x * r * w, y * r * w, 0.0, w))
            .collect();
        let knots = [
            0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
        ];
        let (range, note) = check(9, 3, &knots, None).unwrap();
        assert_eq!((range, note), ([0.0, 1.0], None));
        let s = spans(3, &knots, range);
        assert_eq!(s.len(), 4);
        let mut scratch = Vec::new();
        for &(i, a, b) in &s {
            for k in 0..=16 {
                let u = a + (b - a) * k as f64 / 16.0;
                let q = de_boor(&knots, 2, i, u, &cvs, &mut scratch);
                let p = DVec3::new(q.x, q.y, q.z) / q.w;
                assert!((p.length() - r).abs() < 1e-14, "{u} {p}");
            }
        }
    }

    #[test]
    fn checks() {
        let k = [0.0, 0.0, 1.0, 2.0, 2.0];
        assert!(check(3, 2, &k, None).is_ok());
        assert!(check(3, 0, &k, None).is_err());
        assert!(check(3, 4, &k, None).is_err());
        assert!(check(3, 3, &k, None).is_err());
        assert!(check(3, 2, &[0.0, 1.0, 0.5, 2.0, 2.0], None).is_err());
        let (r, note) = check(3, 2, &k, Some(DVec2::new(-1.0, 1.5))).unwrap();
        assert_eq!(r, [0.0, 1.5]);
        assert!(note.is_some());
        let (r, note) = check(3, 2, &k, Some(DVec2::new(1.0, 1.0))).unwrap();
        assert_eq!(r, [0.0, 2.0]);
        assert!(note.is_some());
        assert_eq!(spans(2, &k, [0.5, 2.0]), vec![(1, 0.5, 1.0), (2, 1.0, 2.0)]);
    }

    #[test]
    fn de_boor_of_a_clamped_cubic_is_the_bezier_curve() {
        let p = [0.0, 3.0, -1.0, 2.0];
        let knots = [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        let mut scratch = Vec::new();
        for k in 0..=8 {
            let t: f64 = k as f64 / 8.0;
            let s = 1.0 - t;
            let want = s * s * s * p[0]
                + 3.0 * t * s * s * p[1]
                + 3.0 * t * t * s * p[2]
                + t * t * t * p[3];
            let got = de_boor(&knots, 3, 3, t, &p, &mut scratch);
            assert!((got - want).abs() < 1e-14);
        }
    }
}
