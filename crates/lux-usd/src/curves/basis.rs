//! UsdGeomBasisCurves: how `curveVertexCounts`, `type`, `basis` and `wrap` cut each curve into
//! segments ("Segment Indexing"), how a segment is evaluated ("Cubic Vertex Interpolation",
//! "Linear Vertex Interpolation"), and where varying values sit ("Primvar Interpolation").
//!
//! A cubic segment is four control values `P0..P3` combined with the basis weights at
//! `t ∈ [0, 1]`:
//!
//! | basis | vstep | weights of `P0, P1, P2, P3` |
//! |---|---|---|
//! | `bezier` | 3 | `(1−t)³, 3t(1−t)², 3t²(1−t), t³` |
//! | `bspline` | 1 | `(1−t)³/6, (3t³−6t²+4)/6, (−3t³+3t²+3t+1)/6, t³/6` |
//! | `catmullRom` | 1 | `(−t³+2t²−t)/2, (3t³−5t²+2)/2, (−3t³+4t²+t)/2, (t³−t²)/2` |
//!
//! A linear segment is `P0·(1−t) + P1·t`.

use super::primvar::Value;
use glam::DVec3;

/// `type`: `linear` or `cubic` (the schema fallback).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveType {
    /// Straight segments between consecutive vertices.
    Linear,
    /// Four-vertex segments through the `basis`.
    Cubic,
}

/// `basis` of a cubic curve (ignored for linear ones). `bezier` is the schema fallback; the
/// `hermite` and `power` tokens were removed from the schema.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Basis {
    /// `bezier` (vstep 3).
    Bezier,
    /// `bspline` (uniform cubic B-spline, vstep 1).
    Bspline,
    /// `catmullRom` (vstep 1).
    CatmullRom,
}

/// `wrap`: `nonperiodic` (the schema fallback), `periodic` or `pinned`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    /// Open curves.
    Nonperiodic,
    /// Closed curves: the first `4 − vstep` vertices (one for linear curves) are repeated.
    Periodic,
    /// Open bspline / catmullRom curves from `P[0]` to `P[n−1]` through phantom points
    /// `P[−1] = 2·P[0] − P[1]` and `P[n] = 2·P[n−1] − P[n−2]`; nonperiodic for bezier and linear
    /// curves.
    Pinned,
}

impl Basis {
    /// The vertex step from one segment to the next.
    pub fn vstep(self) -> usize {
        match self {
            Basis::Bezier => 3,
            Basis::Bspline | Basis::CatmullRom => 1,
        }
    }

    /// The weights of `P0..P3` at `t` (the basis matrix of UsdGeomBasisCurves' "Cubic Vertex
    /// Interpolation" applied to `(t³, t², t, 1)`); they sum to 1.
    pub fn weights(self, t: f64) -> [f64; 4] {
        let (t2, t3) = (t * t, t * t * t);
        let s = 1.0 - t;
        match self {
            Basis::Bezier => [s * s * s, 3.0 * t * s * s, 3.0 * t2 * s, t3],
            Basis::Bspline => [
                s * s * s / 6.0,
                (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
                (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
                t3 / 6.0,
            ],
            Basis::CatmullRom => [
                (-t3 + 2.0 * t2 - t) / 2.0,
                (3.0 * t3 - 5.0 * t2 + 2.0) / 2.0,
                (-3.0 * t3 + 4.0 * t2 + t) / 2.0,
                (t3 - t2) / 2.0,
            ],
        }
    }

    /// The Bézier control points of the segment whose control values are `p` (the same cubic,
    /// written in the Bernstein basis): used to bound its flatness.
    pub fn to_bezier(self, p: [DVec3; 4]) -> [DVec3; 4] {
        match self {
            Basis::Bezier => p,
            Basis::Bspline => [
                (p[0] + 4.0 * p[1] + p[2]) / 6.0,
                (2.0 * p[1] + p[2]) / 3.0,
                (p[1] + 2.0 * p[2]) / 3.0,
                (p[1] + 4.0 * p[2] + p[3]) / 6.0,
            ],
            Basis::CatmullRom => [
                p[1],
                p[1] + (p[2] - p[0]) / 6.0,
                p[2] - (p[3] - p[1]) / 6.0,
                p[2],
            ],
        }
    }
}

/// One control value of a segment, relative to its curve's first vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cv {
    /// The authored vertex.
    At(usize),
    /// A pinned curve's phantom point `2·v[end] − v[next]`.
    Phantom {
        /// `P[0]` or `P[n−1]`.
        end: usize,
        /// `P[1]` or `P[n−2]`.
        next: usize,
    },
}

impl Cv {
    /// This control value of a curve whose per-vertex values are `v`.
    pub fn get<T: Value>(self, v: &[T]) -> T {
        match self {
            Cv::At(i) => v[i],
            Cv::Phantom { end, next } => v[end] * 2.0 - v[next],
        }
    }
}

/// One segment of a curve: its control values (a linear segment uses the first two) and the
/// indices, within the curve's varying values, of its start and end values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Segment {
    /// `P0..P3`.
    pub cvs: [Cv; 4],
    /// The varying values at `t = 0` and `t = 1`.
    pub varying: [usize; 2],
}

/// How one curve is drawn: its segments, whether it closes, how many varying values it takes,
/// and what in its vertex count does not fit the schema (drawn as said).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CurveLayout {
    /// The segments, in order.
    pub segments: Vec<Segment>,
    /// Whether the last segment ends where the first starts.
    pub closed: bool,
    /// Varying values of the curve, from the schema's segment count ([`segment_count`]):
    /// segments + 1, or segments when periodic.
    pub varying: usize,
    /// A vertex count the schema does not allow, and what is drawn instead.
    pub problem: Option<&'static str>,
}

/// UsdGeomBasisCurves' segment count of one curve of `n` vertices (the "curve segment count"
/// table): linear `n − 1` (periodic `n`); cubic nonperiodic `(n − 4) / vstep + 1`, periodic
/// `n / vstep`, pinned bspline/catmullRom `n − 1`; 0 for a curve too short for any segment.
pub fn segment_count(ty: CurveType, basis: Basis, wrap: Wrap, n: usize) -> usize {
    let vs = basis.vstep();
    match (ty, wrap) {
        (CurveType::Linear, Wrap::Periodic) => n,
        (CurveType::Linear, _) => n.saturating_sub(1),
        (CurveType::Cubic, Wrap::Periodic) => n / vs,
        (CurveType::Cubic, Wrap::Pinned) if basis != Basis::Bezier => n.saturating_sub(1),
        (CurveType::Cubic, _) if n >= 4 => (n - 4) / vs + 1,
        (CurveType::Cubic, _) => 0,
    }
}

/// The segments of one curve of `n` vertices, as the schema's "Segment Indexing" defines them:
/// nonperiodic cubic segment `i` is vertices `i·vstep .. i·vstep + 3`; periodic ones wrap
/// modulo `n`; pinned bspline/catmullRom segment `i` is `P[i−1] .. P[i+2]` with the phantom
/// points; linear segment `i` is `i, i + 1`.
///
/// Vertex counts the schema does not allow are drawn as far as they go and reported in
/// [`CurveLayout::problem`]: trailing vertices that do not complete a segment are left out; a
/// nonperiodic cubic curve of 2 or 3 vertices is one segment with the last vertex repeated (as
/// Storm draws it); a curve with fewer vertices than any segment needs has no segment.
pub fn layout(ty: CurveType, basis: Basis, wrap: Wrap, n: usize) -> CurveLayout {
    let vs = basis.vstep();
    let periodic = wrap == Wrap::Periodic;
    let mut problem = None;
    let mut segments = Vec::new();
    match ty {
        CurveType::Linear => {
            let min = if periodic { 3 } else { 2 };
            if n < min {
                problem = Some("too few vertices for a linear segment; not drawn");
            } else {
                for i in 0..segment_count(ty, basis, wrap, n) {
                    let b = Cv::At((i + 1) % n);
                    segments.push([Cv::At(i), b, b, b]);
                }
            }
        }
        CurveType::Cubic if periodic => {
            let count = n / vs;
            if n < 3 || count == 0 {
                problem = Some("too few vertices for a periodic cubic curve; not drawn");
            } else {
                if !n.is_multiple_of(vs) {
                    problem = Some(
                        "vertex count is not a multiple of the basis' vstep; the trailing vertices are left out",
                    );
                }
                for i in 0..count {
                    segments.push([0, 1, 2, 3].map(|k| Cv::At((i * vs + k) % n)));
                }
            }
        }
        CurveType::Cubic if wrap == Wrap::Pinned && basis != Basis::Bezier => {
            if n < 2 {
                problem = Some("a pinned curve needs 2 vertices; not drawn");
            } else {
                let ext = |j: isize| -> Cv {
                    if j < 0 {
                        Cv::Phantom { end: 0, next: 1 }
                    } else if j as usize >= n {
                        Cv::Phantom {
                            end: n - 1,
                            next: n - 2,
                        }
                    } else {
                        Cv::At(j as usize)
                    }
                };
                for i in 0..n - 1 {
                    let i = i as isize;
                    segments.push([ext(i - 1), ext(i), ext(i + 1), ext(i + 2)]);
                }
            }
        }
        CurveType::Cubic => {
            if n < 2 {
                problem = Some("too few vertices for a cubic segment; not drawn");
            } else if n < 4 {
                problem = Some(
                    "fewer than 4 vertices: drawn as one segment with the last vertex repeated (as Storm draws it)",
                );
                segments.push([0, 1, 2, 3].map(|k| Cv::At(k.min(n - 1))));
            } else {
                if !(n - 4).is_multiple_of(vs) {
                    problem = Some(
                        "vertex count does not fit the basis' vstep; the trailing vertices are left out",
                    );
                }
                for i in 0..segment_count(ty, basis, wrap, n) {
                    segments.push([0, 1, 2, 3].map(|k| Cv::At(i * vs + k)));
                }
            }
        }
    }
    let count = segments.len();
    let closed = periodic && count > 0;
    let schema = segment_count(ty, basis, wrap, n);
    let varying = if periodic { schema } else { schema + 1 };
    let last = varying.saturating_sub(1);
    let segments = segments
        .into_iter()
        .enumerate()
        .map(|(i, cvs)| Segment {
            cvs,
            varying: if closed {
                [i, (i + 1) % count]
            } else {
                [i.min(last), (i + 1).min(last)]
            },
        })
        .collect();
    CurveLayout {
        segments,
        closed,
        varying,
        problem,
    }
}

/// The value at `t ∈ [0, 1]` of `segment` of a curve whose per-vertex values are `v`.
pub fn eval<T: Value>(ty: CurveType, basis: Basis, segment: &Segment, v: &[T], t: f64) -> T {
    match ty {
        CurveType::Linear => {
            let (a, b) = (segment.cvs[0].get(v), segment.cvs[1].get(v));
            a + (b - a) * t
        }
        CurveType::Cubic => {
            let w = basis.weights(t);
            let p = segment.cvs.map(|c| c.get(v));
            p[0] * w[0] + p[1] * w[1] + p[2] * w[2] + p[3] * w[3]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counts(ty: CurveType, basis: Basis, wrap: Wrap, n: &[usize]) -> (Vec<usize>, Vec<usize>) {
        n.iter()
            .map(|&n| {
                let l = layout(ty, basis, wrap, n);
                (l.segments.len(), l.varying)
            })
            .unzip()
    }

    /// The schema's worked example table (UsdGeomBasisCurves, "Primvar Interpolation"), and
    /// pinned curves: usd-core 26.11's `ComputeSegmentCounts` gives the same segment counts
    /// (pinned bspline and catmullRom [2, 3, 5] → [1, 2, 4]; pinned bezier [4, 7] → [1, 2]).
    #[test]
    fn segment_and_varying_counts_match_the_schema_table() {
        use {Basis::*, CurveType::*, Wrap::*};
        assert_eq!(
            counts(Linear, Bezier, Nonperiodic, &[2, 3, 2, 5]),
            (vec![1, 2, 1, 4], vec![2, 3, 2, 5])
        );
        assert_eq!(
            counts(Cubic, Bezier, Nonperiodic, &[4, 7, 10, 4, 7]),
            (vec![1, 2, 3, 1, 2], vec![2, 3, 4, 2, 3])
        );
        assert_eq!(
            counts(Cubic, Bspline, Nonperiodic, &[5, 4, 6, 7]),
            (vec![2, 1, 3, 4], vec![3, 2, 4, 5])
        );
        assert_eq!(
            counts(Cubic, Bezier, Periodic, &[6, 9, 6]),
            (vec![2, 3, 2], vec![2, 3, 2])
        );
        assert_eq!(
            counts(Linear, Bezier, Periodic, &[3, 7]),
            (vec![3, 7], vec![3, 7])
        );
        for b in [Bspline, CatmullRom] {
            assert_eq!(
                counts(Cubic, b, Pinned, &[2, 3, 5]),
                (vec![1, 2, 4], vec![2, 3, 5])
            );
        }
        assert_eq!(counts(Cubic, Bezier, Pinned, &[4, 7]).0, vec![1, 2]);
        for (ty, b, w, n) in [
            (Linear, Bezier, Nonperiodic, 5),
            (Linear, Bezier, Periodic, 7),
            (Cubic, Bezier, Nonperiodic, 10),
            (Cubic, Bspline, Nonperiodic, 7),
            (Cubic, Bspline, Periodic, 7),
            (Cubic, CatmullRom, Pinned, 5),
        ] {
            assert_eq!(
                layout(ty, b, w, n).segments.len(),
                segment_count(ty, b, w, n)
            );
            assert_eq!(layout(ty, b, w, n).problem, None);
        }
    }

    #[test]
    fn segment_indexing() {
        use {Basis::*, CurveType::*, Wrap::*};
        let at = |s: &Segment| s.cvs.map(|c| if let Cv::At(i) = c { i } else { 99 });
        let l = layout(Cubic, Bezier, Nonperiodic, 7);
        assert_eq!(at(&l.segments[1]), [3, 4, 5, 6]);
        let l = layout(Cubic, Bspline, Nonperiodic, 5);
        assert_eq!(at(&l.segments[1]), [1, 2, 3, 4]);
        let l = layout(Cubic, Bezier, Periodic, 6);
        assert_eq!(at(&l.segments[1]), [3, 4, 5, 0]);
        assert_eq!(l.segments[1].varying, [1, 0]);
        let l = layout(Cubic, Bspline, Periodic, 4);
        assert_eq!(at(&l.segments[3]), [3, 0, 1, 2]);
        let l = layout(Cubic, Bspline, Pinned, 3);
        assert_eq!(l.segments[0].cvs[0], Cv::Phantom { end: 0, next: 1 });
        assert_eq!(l.segments[1].cvs[3], Cv::Phantom { end: 2, next: 1 });
        // Counts the schema does not allow: drawn as far as they go, reported.
        let l = layout(Cubic, Bezier, Nonperiodic, 8);
        assert_eq!(l.segments.len(), 2);
        assert!(l.problem.is_some());
        let l = layout(Cubic, Bezier, Nonperiodic, 2);
        assert_eq!(at(&l.segments[0]), [0, 1, 1, 1]);
        assert!(l.problem.is_some());
        assert!(layout(Linear, Bezier, Nonperiodic, 1).segments.is_empty());
        assert!(layout(Cubic, Bspline, Pinned, 1).segments.is_empty());
    }

    #[test]
    fn weights_partition_unity_and_bezier_form_is_the_same_cubic() {
        let p = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.5),
            DVec3::new(3.0, -1.0, 2.0),
            DVec3::new(4.0, 1.0, -1.0),
        ];
        for basis in [Basis::Bezier, Basis::Bspline, Basis::CatmullRom] {
            let b = basis.to_bezier(p);
            for k in 0..=10 {
                let t = k as f64 / 10.0;
                let w = basis.weights(t);
                assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-15);
                let x: DVec3 = (0..4).map(|i| p[i] * w[i]).sum();
                let bw = Basis::Bezier.weights(t);
                let y: DVec3 = (0..4).map(|i| b[i] * bw[i]).sum();
                assert!((x - y).length() < 1e-13, "{basis:?} {t}");
            }
        }
        // Catmull-Rom interpolates P1 and P2; the B-spline starts at (P0 + 4 P1 + P2) / 6.
        let s = Segment {
            cvs: [Cv::At(0), Cv::At(1), Cv::At(2), Cv::At(3)],
            varying: [0, 1],
        };
        assert_eq!(eval(CurveType::Cubic, Basis::CatmullRom, &s, &p, 0.0), p[1]);
        assert_eq!(eval(CurveType::Cubic, Basis::CatmullRom, &s, &p, 1.0), p[2]);
        let b0 = eval(CurveType::Cubic, Basis::Bspline, &s, &p, 0.0);
        assert!((b0 - (p[0] + 4.0 * p[1] + p[2]) / 6.0).length() < 1e-15);
    }

    #[test]
    fn pinned_curves_start_and_end_at_their_end_points() {
        let p = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(2.0, 0.0, 1.0),
        ];
        for basis in [Basis::Bspline, Basis::CatmullRom] {
            let l = layout(CurveType::Cubic, basis, Wrap::Pinned, 3);
            let first = eval(CurveType::Cubic, basis, &l.segments[0], &p, 0.0);
            let last = eval(CurveType::Cubic, basis, &l.segments[1], &p, 1.0);
            assert!((first - p[0]).length() < 1e-15 && (last - p[2]).length() < 1e-15);
        }
    }
}
