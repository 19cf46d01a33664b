//! `BasisCurves` and `NurbsCurves` drawn as triangles: every curve is evaluated along its length
//! ([`basis`], [`nurbs`]) and swept into a round tube of its width, or into a ribbon facing its
//! authored normals ([`sweep`]), in the prim's own space.
//!
//! ## What is read
//!
//! `curveVertexCounts` and `points` (their sum must equal the point count, or the prim is not
//! drawn); BasisCurves `type`, `basis`, `wrap` (unknown tokens: the schema fallbacks `cubic`,
//! `bezier`, `nonperiodic`, with a warning; `hermite` and `power` are no longer schema tokens);
//! NurbsCurves `order`, `knots`, `ranges`, `pointWeights`; `widths` / `primvars:widths` (the
//! diameter, in object space; `primvars:widths` wins; interpolation `constant`, `uniform`,
//! `varying` or `vertex`, fallback `vertex` for `widths`; unauthored: Hydra's fallback width
//! [`FALLBACK_WIDTH`]); `normals` / `primvars:normals` (ribbons); `primvars:displayColor`
//! (constant, uniform, varying or vertex, with `:indices`) as per-corner colours. A single value
//! under any interpolation is read as constant, as Storm does. Vertex values of a cubic curve
//! are interpolated with its basis, varying values linearly between segment ends.
//!
//! ## Tessellation
//!
//! - **Along the curve**: each cubic segment (a NURBS knot span) is cut into `n` equal
//!   parameter steps, `n` the smallest for which the chords stay within [`FLATNESS`] (0.1 %) of
//!   the span's control-polygon length from the curve: `n = ⌈√(M / (8·tol))⌉` with `M` a bound
//!   on `|C''|` (from the segment's Bézier control points: `6·max|Bᵢ − 2Bᵢ₊₁ + Bᵢ₊₂|`;
//!   for NURBS, from second differences of 9 evaluated points), at most
//!   [`MAX_SPAN_SAMPLES`]. A quarter circle gets 15 steps (6° each), a straight segment 1.
//!   Linear segments are 1 step.
//! - **Around the curve**: tubes have [`TUBE_SIDES`]`[0]` = 12 sides (the polygon reaches
//!   within 3.4 % of the radius; the smooth normals hide the facets) and flat end caps.
//! - **Budget**: a prim is drawn with at most [`TRIANGLE_BUDGET`] triangles (2²⁰, some 180 MB
//!   with colours): past it, tubes lose sides (12 → 8 → 6 → 4 → 3), then spans lose
//!   steps (down to 1), with a warning saying what was cut; a prim needing more even then is
//!   drawn at that minimum, with a warning.
//!
//! Curves that cannot be drawn as authored — vertex counts the basis does not allow, non-finite
//! points, zero length or zero width, bad NURBS knots — are reported in one warning per kind
//! naming the prim, the first such curve and what was done.

pub mod basis;
pub mod nurbs;
pub mod primvar;
pub mod sweep;

use crate::error::{LoadError, WarningKind};
use crate::reader::Reader;
use basis::{Basis, CurveLayout, CurveType, Segment, Wrap};
use glam::{DVec2, DVec3, DVec4};
use openusd::usd::Prim;
use primvar::{CurvePrimvar, Interpolation, Sizes, Value};
use std::collections::BTreeMap;
use sweep::{CurvePath, Tessellation};

/// The width (diameter) of curves and points whose `widths` are unauthored or unusable:
/// Hydra's fallback, 1 in object space (the value Storm's curve primvar interpolation falls
/// back to for a float primvar of the wrong size). UsdGeom's extent computation pads by 0 when
/// `widths` is unauthored, so such tubes reach half a unit past usd-core's extent.
pub const FALLBACK_WIDTH: f64 = 1.0;

/// Largest distance of a chord from the curve, relative to the control-polygon length of its
/// span.
pub const FLATNESS: f64 = 1e-3;

/// Most steps along one span.
pub const MAX_SPAN_SAMPLES: usize = 64;

/// Tube sides at full detail, then as the [`TRIANGLE_BUDGET`] cuts them.
pub const TUBE_SIDES: [usize; 5] = [12, 8, 6, 4, 3];

/// Most triangles drawn for one curves or points prim before detail is cut.
pub const TRIANGLE_BUDGET: usize = 1 << 20;

/// Steps for a span whose second derivative (over a unit parameter) is at most `second` and
/// whose control polygon is `length` long: the chord error of `n` equal steps is at most
/// `second / (8·n²)`, kept within `FLATNESS·length`.
pub fn span_samples(second: f64, length: f64) -> usize {
    if !(second > 0.0 && length > 0.0 && second.is_finite() && length.is_finite()) {
        return 1;
    }
    let n = (second / (8.0 * FLATNESS * length)).sqrt().ceil();
    if n.is_finite() {
        (n as usize).clamp(1, MAX_SPAN_SAMPLES)
    } else {
        MAX_SPAN_SAMPLES
    }
}

/// [`span_samples`] for a cubic Bézier segment.
pub fn bezier_samples(b: [DVec3; 4]) -> usize {
    let second = 6.0
        * (b[0] - 2.0 * b[1] + b[2])
            .length()
            .max((b[1] - 2.0 * b[2] + b[3]).length());
    let length = (b[1] - b[0]).length() + (b[2] - b[1]).length() + (b[3] - b[2]).length();
    span_samples(second, length)
}

/// One point along a curve.
struct Sample {
    position: DVec3,
    width: f64,
    color: DVec3,
    normal: DVec3,
}

/// Curves ready to sample: per curve the full-detail step counts of its spans (empty when it is
/// not drawn) and whether it closes.
trait CurveSource {
    fn curves(&self) -> usize;
    fn spans(&self, c: usize) -> &[usize];
    fn closed(&self, c: usize) -> bool;
    fn sample(&mut self, c: usize, span: usize, t: f64) -> Sample;
}

/// `widths`, `primvars:displayColor` and the ribbon normals of a prim, checked.
struct Primvars {
    widths: CurvePrimvar<f64>,
    colors: Option<CurvePrimvar<DVec3>>,
    normals: Option<CurvePrimvar<DVec3>>,
}

/// Problems found curve by curve, reported as one warning per kind.
#[derive(Default)]
struct Problems(BTreeMap<&'static str, (usize, usize)>);

impl Problems {
    fn add(&mut self, curve: usize, what: &'static str) {
        self.0.entry(what).or_insert((curve, 0)).1 += 1;
    }

    fn report(self, r: &mut Reader<'_>, prim: &Prim, curves: usize) {
        for (what, (first, count)) in self.0 {
            let which = if count == 1 {
                format!("curve {first} of {curves}")
            } else {
                format!("{count} of {curves} curves (the first: {first})")
            };
            r.warn(
                prim,
                WarningKind::InvalidGeometry,
                format!("{which}: {what}"),
            );
        }
    }
}

/// `widths` values made drawable: non-finite ones become [`FALLBACK_WIDTH`], negative ones
/// their absolute value, each with one warning.
pub(crate) fn fix_widths(r: &mut Reader<'_>, prim: &Prim, name: &str, w: &mut [f64]) {
    let bad = w.iter().filter(|x| !x.is_finite()).count();
    let negative = w.iter().filter(|x| **x < 0.0).count();
    for x in w.iter_mut() {
        if !x.is_finite() {
            *x = FALLBACK_WIDTH;
        } else if *x < 0.0 {
            *x = -*x;
        }
    }
    if bad > 0 {
        r.warn(
            prim,
            WarningKind::InvalidValue,
            format!("{name}: {bad} values are not finite; drawn with the fallback width {FALLBACK_WIDTH}"),
        );
    }
    if negative > 0 {
        r.warn(
            prim,
            WarningKind::InvalidValue,
            format!("{name}: {negative} values are negative; their absolute values are used"),
        );
    }
}

/// Authored widths: the attribute read, its fallback interpolation and the values.
pub(crate) struct Widths {
    pub(crate) name: &'static str,
    pub(crate) interpolation: Interpolation,
    pub(crate) values: Vec<f64>,
}

/// The authored widths (`primvars:widths` first, fallback interpolation `constant` as for any
/// primvar; then `widths`, fallback `vertex`), made drawable by [`fix_widths`]; `None` when
/// unauthored or empty.
pub(crate) fn authored_widths(
    r: &mut Reader<'_>,
    prim: &Prim,
) -> Result<Option<Widths>, LoadError> {
    for (name, interp) in [
        ("primvars:widths", Interpolation::Constant),
        ("widths", Interpolation::Vertex),
    ] {
        if let Some(mut w) = r.f64_array(prim, name)?
            && !w.is_empty()
        {
            fix_widths(r, prim, name, &mut w);
            return Ok(Some(Widths {
                name,
                interpolation: interp,
                values: w,
            }));
        }
    }
    Ok(None)
}

fn read_primvars(r: &mut Reader<'_>, prim: &Prim, sizes: Sizes) -> Result<Primvars, LoadError> {
    let fallback_width = format!("drawn with the fallback width {FALLBACK_WIDTH}");
    let widths = match authored_widths(r, prim)? {
        Some(w) => primvar::read(
            r,
            prim,
            w.name,
            w.values,
            w.interpolation,
            sizes,
            &fallback_width,
        )?
        .unwrap_or(CurvePrimvar::constant(FALLBACK_WIDTH)),
        None => CurvePrimvar::constant(FALLBACK_WIDTH),
    };
    let colors = primvar::display_color(r, prim, sizes)?;
    let mut normals = None;
    for (name, interp) in [
        ("primvars:normals", Interpolation::Constant),
        ("normals", Interpolation::Vertex),
    ] {
        if let Some(n) = r.vec3_array(prim, name)?
            && !n.is_empty()
        {
            let fallback = "drawn as round tubes instead of ribbons";
            if n.iter().any(|v| !v.is_finite() || *v == DVec3::ZERO) {
                r.warn(
                    prim,
                    WarningKind::InvalidValue,
                    format!("{name}: zero or non-finite normals; {fallback}"),
                );
            } else {
                normals = primvar::read(r, prim, name, n, interp, sizes, fallback)?;
            }
            break;
        }
    }
    Ok(Primvars {
        widths,
        colors,
        normals,
    })
}

/// `curveVertexCounts` and `points`.
type CountsPoints = (Vec<usize>, Vec<DVec3>);

/// `curveVertexCounts` and `points`, or `None` (with a warning) when they do not describe
/// curves.
fn read_counts_points(
    r: &mut Reader<'_>,
    prim: &Prim,
    posed: Option<Vec<DVec3>>,
) -> Result<Option<CountsPoints>, LoadError> {
    let points = match posed {
        Some(p) => p,
        None => r.vec3_array(prim, "points")?.unwrap_or_default(),
    };
    let counts = r.int_array(prim, "curveVertexCounts")?.unwrap_or_default();
    if counts.is_empty() || points.is_empty() {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            "no curveVertexCounts or no points; nothing drawn",
        );
        return Ok(None);
    }
    let total = counts
        .iter()
        .fold(0i64, |acc, c| acc.saturating_add((*c).max(0)));
    if counts.iter().any(|c| *c < 0) || total != points.len() as i64 {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!(
                "curveVertexCounts sum to {total} (or hold a negative count) but points has {} \
                 entries; not drawn",
                points.len()
            ),
        );
        return Ok(None);
    }
    Ok(Some((
        counts.into_iter().map(|c| c as usize).collect(),
        points,
    )))
}

/// Offsets of each curve's first element for per-curve element counts.
fn offsets(counts: impl Iterator<Item = usize>) -> Vec<usize> {
    let mut acc = 0;
    counts
        .map(|c| {
            let o = acc;
            acc += c;
            o
        })
        .collect()
}

/// How much detail a prim is drawn with: tube sides and the fraction of each span's
/// full-detail steps.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Detail {
    sides: usize,
    scale: f64,
}

impl Detail {
    fn steps(self, full: usize) -> usize {
        ((full as f64 * self.scale).ceil() as usize).clamp(1, full.max(1))
    }

    fn triangles(self, src: &dyn CurveSource, ribbons: bool) -> usize {
        let mut total = 0usize;
        for c in 0..src.curves() {
            let spans = src.spans(c);
            if spans.is_empty() {
                continue;
            }
            let quads: usize = spans.iter().map(|&n| self.steps(n)).sum();
            total = total.saturating_add(if ribbons {
                2 * quads
            } else {
                let caps = if src.closed(c) {
                    0
                } else {
                    2 * (self.sides - 2)
                };
                2 * self.sides * quads + caps
            });
        }
        total
    }
}

/// The most detail within [`TRIANGLE_BUDGET`]; a warning when detail is cut.
fn choose_detail(
    r: &mut Reader<'_>,
    prim: &Prim,
    src: &dyn CurveSource,
    ribbons: bool,
) -> Result<Detail, LoadError> {
    let full = Detail {
        sides: TUBE_SIDES[0],
        scale: 1.0,
    };
    let need = full.triangles(src, ribbons);
    if need <= TRIANGLE_BUDGET {
        return Ok(full);
    }
    let ladder: &[usize] = if ribbons { &[3] } else { &TUBE_SIDES };
    let mut detail = ladder
        .iter()
        .map(|&sides| Detail { sides, scale: 1.0 })
        .find(|d| d.triangles(src, ribbons) <= TRIANGLE_BUDGET);
    if detail.is_none() {
        let min = Detail {
            sides: 3,
            scale: 0.0,
        };
        let least = min.triangles(src, ribbons);
        if least > r.limits.max_array_len {
            return Err(LoadError::TooLarge {
                file: r.file.clone(),
                prim: prim.path().to_string(),
                what: "curve tessellation",
                count: least,
                limit: r.limits.max_array_len,
            });
        }
        if least <= TRIANGLE_BUDGET {
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..40 {
                let mid = 0.5 * (lo + hi);
                let d = Detail {
                    sides: 3,
                    scale: mid,
                };
                if d.triangles(src, ribbons) <= TRIANGLE_BUDGET {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            detail = Some(Detail {
                sides: 3,
                scale: lo,
            });
        } else {
            r.warn(
                prim,
                WarningKind::Unsupported,
                format!(
                    "needs {least} triangles even at the least detail (3-sided tubes, one \
                     step per span), past the budget of {TRIANGLE_BUDGET} triangles per prim; \
                     drawn at the least detail"
                ),
            );
            return Ok(min);
        }
    }
    let d = detail.unwrap_or(full);
    let (at_full, drawn) = if ribbons {
        ("ribbons".to_owned(), "ribbons".to_owned())
    } else {
        (
            format!("{}-sided tubes", TUBE_SIDES[0]),
            format!("{}-sided tubes", d.sides),
        )
    };
    r.warn(
        prim,
        WarningKind::Unsupported,
        format!(
            "needs {need} triangles at full detail ({at_full}, chords within {FLATNESS} of each \
             span), past the budget of {TRIANGLE_BUDGET} triangles per prim: drawn as {drawn} \
             with {:.0} % of the steps along each span",
            100.0 * d.scale
        ),
    );
    Ok(d)
}

/// Samples every curve of `src` at the chosen detail and sweeps it; `None` when nothing is
/// left to draw.
fn tessellate(
    r: &mut Reader<'_>,
    prim: &Prim,
    src: &mut dyn CurveSource,
    (ribbons, colored): (bool, bool),
) -> Result<Option<Tessellation>, LoadError> {
    let detail = choose_detail(r, prim, src, ribbons)?;
    let mut out = Tessellation::new(colored);
    out.double_sided = ribbons;
    let mut degenerate = Problems::default();
    for c in 0..src.curves() {
        let spans = src.spans(c).to_vec();
        if spans.is_empty() {
            continue;
        }
        let closed = src.closed(c);
        let mut path = CurvePath {
            closed,
            ..CurvePath::default()
        };
        for (s, &full) in spans.iter().enumerate() {
            let m = detail.steps(full);
            let first = usize::from(s > 0);
            let last = if closed && s + 1 == spans.len() {
                m - 1
            } else {
                m
            };
            for j in first..=last {
                let q = src.sample(c, s, j as f64 / m as f64);
                path.points.push(q.position);
                path.widths.push(q.width.max(0.0));
                if colored {
                    path.colors.push(q.color);
                }
                if ribbons {
                    path.normals.push(q.normal);
                }
            }
        }
        let drawn = if ribbons {
            sweep::ribbon(&path, &mut out)
        } else {
            sweep::tube(&path, detail.sides, &mut out)
        };
        if !drawn {
            degenerate.add(c, "zero length or zero width; not drawn");
        }
    }
    degenerate.report(r, prim, src.curves());
    Ok((!out.triangles.is_empty()).then_some(out))
}

/// A BasisCurves prim's curves.
struct BasisSource {
    ty: CurveType,
    basis: Basis,
    points: Vec<DVec3>,
    first_vertex: Vec<usize>,
    first_varying: Vec<usize>,
    layouts: Vec<CurveLayout>,
    spans: Vec<Vec<usize>>,
    pv: Primvars,
}

impl BasisSource {
    fn value<T: Value>(&self, p: &CurvePrimvar<T>, c: usize, seg: &Segment, t: f64) -> T {
        match p.interpolation {
            Interpolation::Constant => p.values[0],
            Interpolation::Uniform => p.values[c],
            Interpolation::Varying => {
                let o = self.first_varying[c];
                let (a, b) = (p.values[o + seg.varying[0]], p.values[o + seg.varying[1]]);
                a + (b - a) * t
            }
            Interpolation::Vertex => basis::eval(
                self.ty,
                self.basis,
                seg,
                &p.values[self.first_vertex[c]..],
                t,
            ),
        }
    }
}

impl CurveSource for BasisSource {
    fn curves(&self) -> usize {
        self.layouts.len()
    }
    fn spans(&self, c: usize) -> &[usize] {
        &self.spans[c]
    }
    fn closed(&self, c: usize) -> bool {
        self.layouts[c].closed
    }
    fn sample(&mut self, c: usize, span: usize, t: f64) -> Sample {
        let seg = self.layouts[c].segments[span];
        let v = &self.points[self.first_vertex[c]..];
        Sample {
            position: basis::eval(self.ty, self.basis, &seg, v, t),
            width: self.value(&self.pv.widths, c, &seg, t),
            color: self
                .pv
                .colors
                .as_ref()
                .map_or(DVec3::ZERO, |p| self.value(p, c, &seg, t)),
            normal: self
                .pv
                .normals
                .as_ref()
                .map_or(DVec3::ZERO, |p| self.value(p, c, &seg, t)),
        }
    }
}

/// Reads a `BasisCurves` prim and tessellates it in its own space: tubes, or ribbons when
/// `normals` are authored. `None` (with warnings) when nothing can be drawn.
pub fn read_basis_curves(
    r: &mut Reader<'_>,
    prim: &Prim,
    posed: Option<Vec<DVec3>>,
) -> Result<Option<Tessellation>, LoadError> {
    let Some((counts, points)) = read_counts_points(r, prim, posed)? else {
        return Ok(None);
    };
    let ty = match r.text(prim, "type")?.as_deref() {
        None | Some("cubic") => CurveType::Cubic,
        Some("linear") => CurveType::Linear,
        Some(other) => {
            r.warn(
                prim,
                WarningKind::InvalidValue,
                format!("type {other:?} is not linear or cubic; drawn as the fallback cubic"),
            );
            CurveType::Cubic
        }
    };
    let basis = match r.text(prim, "basis")?.as_deref() {
        None | Some("bezier") => Basis::Bezier,
        Some("bspline") => Basis::Bspline,
        Some("catmullRom") => Basis::CatmullRom,
        Some(other) => {
            if ty == CurveType::Cubic {
                let why = if matches!(other, "hermite" | "power") {
                    " (removed from UsdGeomBasisCurves; HermiteCurves replaces hermite)"
                } else {
                    ""
                };
                r.warn(
                    prim,
                    WarningKind::Unsupported,
                    format!(
                        "basis {other:?} is not bezier, bspline or catmullRom{why}; drawn as \
                         the fallback bezier"
                    ),
                );
            }
            Basis::Bezier
        }
    };
    let wrap = match r.text(prim, "wrap")?.as_deref() {
        None | Some("nonperiodic") => Wrap::Nonperiodic,
        Some("periodic") => Wrap::Periodic,
        Some("pinned") => Wrap::Pinned,
        Some(other) => {
            r.warn(
                prim,
                WarningKind::InvalidValue,
                format!(
                    "wrap {other:?} is not nonperiodic, periodic or pinned; drawn as the \
                     fallback nonperiodic"
                ),
            );
            Wrap::Nonperiodic
        }
    };
    let mut problems = Problems::default();
    let first_vertex = offsets(counts.iter().copied());
    let mut layouts: Vec<CurveLayout> = counts
        .iter()
        .map(|&n| basis::layout(ty, basis, wrap, n))
        .collect();
    for (c, l) in layouts.iter_mut().enumerate() {
        if let Some(p) = l.problem {
            problems.add(c, p);
        }
        let v = &points[first_vertex[c]..first_vertex[c] + counts[c]];
        if !l.segments.is_empty() && v.iter().any(|p| !p.is_finite()) {
            problems.add(c, "a point is not finite; not drawn");
            l.segments.clear();
        }
    }
    problems.report(r, prim, counts.len());
    let first_varying = offsets(layouts.iter().map(|l| l.varying));
    let sizes = Sizes {
        curves: counts.len(),
        varying: layouts.iter().map(|l| l.varying).sum(),
        vertex: points.len(),
    };
    let pv = read_primvars(r, prim, sizes)?;
    let spans = layouts
        .iter()
        .enumerate()
        .map(|(c, l)| {
            let v = &points[first_vertex[c]..];
            l.segments
                .iter()
                .map(|s| match ty {
                    CurveType::Linear => 1,
                    CurveType::Cubic => bezier_samples(basis.to_bezier(s.cvs.map(|c| c.get(v)))),
                })
                .collect()
        })
        .collect();
    let flags = (pv.normals.is_some(), pv.colors.is_some());
    let mut src = BasisSource {
        ty,
        basis,
        points,
        first_vertex,
        first_varying,
        layouts,
        spans,
        pv,
    };
    tessellate(r, prim, &mut src, flags)
}

/// One drawable NURBS curve.
struct NurbsCurve {
    order: usize,
    first_knot: usize,
    spans: Vec<(usize, f64, f64)>,
}

/// A NurbsCurves prim's curves, with homogeneous control values `(w·v, w)`.
struct NurbsSource {
    curves: Vec<Option<NurbsCurve>>,
    knots: Vec<f64>,
    counts: Vec<usize>,
    first_vertex: Vec<usize>,
    first_varying: Vec<usize>,
    points: Vec<DVec4>,
    widths: (CurvePrimvar<f64>, Vec<DVec2>),
    colors: Option<(CurvePrimvar<DVec3>, Vec<DVec4>)>,
    normals: Option<(CurvePrimvar<DVec3>, Vec<DVec4>)>,
    steps: Vec<Vec<usize>>,
    scratch: Vec<DVec4>,
    scratch2: Vec<DVec2>,
}

impl NurbsSource {
    fn position(&mut self, c: usize, i: usize, u: f64) -> DVec3 {
        let curve = self.curves[c].as_ref().expect("drawn curve");
        let (n, k, fk) = (self.counts[c], curve.order, curve.first_knot);
        let q = nurbs::de_boor(
            &self.knots[fk..fk + n + k],
            k - 1,
            i,
            u,
            &self.points[self.first_vertex[c]..self.first_vertex[c] + n],
            &mut self.scratch,
        );
        q.truncate() / q.w
    }

    /// A DVec3 primvar (colours `which`, else normals) at `u` in span `i` of curve `c`.
    fn vec3(&mut self, which: bool, c: usize, i: usize, u: f64) -> DVec3 {
        let mut scratch = std::mem::take(&mut self.scratch);
        let pv = if which { &self.colors } else { &self.normals };
        let v = pv.as_ref().map_or(DVec3::ZERO, |(p, weighted)| {
            self.primvar_at(p, weighted, &mut scratch, [c, i], u)
        });
        self.scratch = scratch;
        v
    }

    fn width(&mut self, c: usize, i: usize, u: f64) -> f64 {
        let mut scratch = std::mem::take(&mut self.scratch2);
        let (p, weighted) = &self.widths;
        let v = self.primvar_at(p, weighted, &mut scratch, [c, i], u);
        self.scratch2 = scratch;
        v
    }

    /// Primvar `p` at `u` in span `i` of curve `c`: constant, per curve, linear between the
    /// span's knots (varying), or the rational curve of its homogeneous vertex values
    /// `weighted` (vertex).
    fn primvar_at<T: Value, H: Homogeneous<Plain = T>>(
        &self,
        p: &CurvePrimvar<T>,
        weighted: &[H],
        scratch: &mut Vec<H>,
        [c, i]: [usize; 2],
        u: f64,
    ) -> T {
        let curve = self.curves[c].as_ref().expect("drawn curve");
        let (n, k, fk) = (self.counts[c], curve.order, curve.first_knot);
        match p.interpolation {
            Interpolation::Constant => p.values[0],
            Interpolation::Uniform => p.values[c],
            Interpolation::Varying => {
                let knots = &self.knots[fk..];
                let j = self.first_varying[c] + i - (k - 1);
                let t = (u - knots[i]) / (knots[i + 1] - knots[i]);
                p.values[j] + (p.values[j + 1] - p.values[j]) * t
            }
            Interpolation::Vertex => nurbs::de_boor(
                &self.knots[fk..fk + n + k],
                k - 1,
                i,
                u,
                &weighted[self.first_vertex[c]..self.first_vertex[c] + n],
                scratch,
            )
            .project(),
        }
    }
}

/// A homogeneous control value `(w·v, w)` and the value it stands for, `v`.
trait Homogeneous: Value {
    /// The value's type.
    type Plain;
    /// `w·v / w`.
    fn project(self) -> Self::Plain;
}

impl Homogeneous for DVec4 {
    type Plain = DVec3;
    fn project(self) -> DVec3 {
        self.truncate() / self.w
    }
}

impl Homogeneous for DVec2 {
    type Plain = f64;
    fn project(self) -> f64 {
        self.x / self.y
    }
}

impl CurveSource for NurbsSource {
    fn curves(&self) -> usize {
        self.curves.len()
    }
    fn spans(&self, c: usize) -> &[usize] {
        &self.steps[c]
    }
    fn closed(&self, _: usize) -> bool {
        false
    }
    fn sample(&mut self, c: usize, span: usize, t: f64) -> Sample {
        let (i, a, b) = self.curves[c].as_ref().expect("drawn curve").spans[span];
        let u = if t >= 1.0 { b } else { a + (b - a) * t };
        Sample {
            position: self.position(c, i, u),
            width: self.width(c, i, u),
            color: self.vec3(true, c, i, u),
            normal: self.vec3(false, c, i, u),
        }
    }
}

/// `(w·v, w)` for every vertex value `v` with weight `w`.
fn weighted<T: Value, H>(values: &[T], weights: &[f64], make: impl Fn(T, f64) -> H) -> Vec<H> {
    values
        .iter()
        .zip(weights)
        .map(|(v, w)| make(*v * *w, *w))
        .collect()
}

/// Reads a `NurbsCurves` prim and tessellates it in its own space (de Boor's algorithm on the
/// rational curve): tubes, or ribbons when `normals` are authored. Varying values sit at the
/// knots `t[k − 1] … t[n]` (RenderMan's `RiNuCurves`: `n − k + 2` per curve). `None` (with
/// warnings) when nothing can be drawn.
pub fn read_nurbs_curves(
    r: &mut Reader<'_>,
    prim: &Prim,
    posed: Option<Vec<DVec3>>,
) -> Result<Option<Tessellation>, LoadError> {
    let Some((counts, points)) = read_counts_points(r, prim, posed)? else {
        return Ok(None);
    };
    let order = r.int_array(prim, "order")?.unwrap_or_default();
    if order.len() != counts.len() {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!(
                "order has {} entries for {} curves; not drawn",
                order.len(),
                counts.len()
            ),
        );
        return Ok(None);
    }
    let knots = r.f64_array(prim, "knots")?.unwrap_or_default();
    let need = counts.iter().zip(&order).fold(0i64, |acc, (n, k)| {
        acc.saturating_add(*n as i64 + (*k).max(0))
    });
    if need != knots.len() as i64 {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!(
                "knots has {} entries but the curves need {need} (vertex count + order each); \
                 not drawn",
                knots.len()
            ),
        );
        return Ok(None);
    }
    let mut ranges = r.vec2_array(prim, "ranges")?;
    if ranges.as_ref().is_some_and(|v| v.len() != counts.len()) {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!(
                "ranges has {} entries for {} curves; the knots' own ranges are drawn",
                ranges.as_ref().map_or(0, Vec::len),
                counts.len()
            ),
        );
        ranges = None;
    }
    let mut weights = r.f64_array(prim, "pointWeights")?;
    if let Some(w) = &weights
        && (w.len() != points.len() || w.iter().any(|w| !(w.is_finite() && *w > 0.0)))
    {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!(
                "pointWeights: {} values for {} points, or a weight that is not positive and \
                 finite; drawn as a polynomial curve (weights 1)",
                w.len(),
                points.len()
            ),
        );
        weights = None;
    }
    let weights = weights.unwrap_or_else(|| vec![1.0; points.len()]);
    let first_vertex = offsets(counts.iter().copied());
    let mut problems = Problems::default();
    let mut first_knot = 0usize;
    let mut curves = Vec::with_capacity(counts.len());
    let mut varying = Vec::with_capacity(counts.len());
    for (c, (&n, &k)) in counts.iter().zip(&order).enumerate() {
        let len = n + k.max(0) as usize;
        let kn = &knots[first_knot..first_knot + len];
        let range = ranges.as_ref().map(|v| v[c]);
        varying.push(if k >= 1 && k as usize <= n {
            n - k as usize + 2
        } else {
            0
        });
        let v = &points[first_vertex[c]..first_vertex[c] + n];
        curves.push(match nurbs::check(n, k, kn, range) {
            Err(e) => {
                problems.add(c, e);
                None
            }
            Ok(_) if v.iter().any(|p| !p.is_finite()) => {
                problems.add(c, "a point is not finite; not drawn");
                None
            }
            Ok((range, note)) => {
                if let Some(note) = note {
                    problems.add(c, note);
                }
                Some(NurbsCurve {
                    order: k as usize,
                    first_knot,
                    spans: nurbs::spans(k as usize, kn, range),
                })
            }
        });
        first_knot += len;
    }
    problems.report(r, prim, counts.len());
    let sizes = Sizes {
        curves: counts.len(),
        varying: varying.iter().sum(),
        vertex: points.len(),
    };
    let pv = read_primvars(r, prim, sizes)?;
    let homogeneous = weighted(&points, &weights, |p, w| p.extend(w));
    let widths_h = weighted(&pv.widths.values, &weights, DVec2::new);
    let vec_h = |p: CurvePrimvar<DVec3>| {
        let h = if p.interpolation == Interpolation::Vertex {
            weighted(&p.values, &weights, |v, w| v.extend(w))
        } else {
            Vec::new()
        };
        (p, h)
    };
    let flags = (pv.normals.is_some(), pv.colors.is_some());
    let mut src = NurbsSource {
        curves,
        knots,
        counts,
        first_vertex,
        first_varying: offsets(varying.into_iter()),
        points: homogeneous,
        widths: (pv.widths, widths_h),
        colors: pv.colors.map(vec_h),
        normals: pv.normals.map(vec_h),
        steps: Vec::new(),
        scratch: Vec::new(),
        scratch2: Vec::new(),
    };
    // Steps per span: second differences of 9 points evaluated over the span's unit parameter
    // (× 1.5 margin: they sample |C''| between the points, not its maximum).
    let mut steps = Vec::with_capacity(src.curves.len());
    for c in 0..src.curves.len() {
        let Some(curve) = &src.curves[c] else {
            steps.push(Vec::new());
            continue;
        };
        let (order, spans) = (curve.order, curve.spans.clone());
        let mut per = Vec::with_capacity(spans.len());
        for (i, a, b) in spans {
            if order <= 2 {
                per.push(1);
                continue;
            }
            let q: Vec<DVec3> = (0..=8)
                .map(|j| src.position(c, i, a + (b - a) * j as f64 / 8.0))
                .collect();
            let h2 = 1.0 / 64.0;
            let second = q
                .windows(3)
                .map(|w| (w[0] - 2.0 * w[1] + w[2]).length() / h2)
                .fold(0.0, f64::max);
            let length: f64 = q.windows(2).map(|w| (w[1] - w[0]).length()).sum();
            per.push(span_samples(1.5 * second, length));
        }
        steps.push(per);
    }
    src.steps = steps;
    tessellate(r, prim, &mut src, flags)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flatness_steps() {
        // A quarter circle of radius 1 as a cubic Bézier: 15 steps, 6° each.
        let k = 0.552_284_749_830_793_4;
        let b = [
            DVec3::X,
            DVec3::new(1.0, k, 0.0),
            DVec3::new(k, 1.0, 0.0),
            DVec3::Y,
        ];
        assert_eq!(bezier_samples(b), 15);
        // A straight segment: one step.
        assert_eq!(
            bezier_samples([DVec3::ZERO, DVec3::X, 2.0 * DVec3::X, 3.0 * DVec3::X]),
            1
        );
        assert_eq!(span_samples(f64::NAN, 1.0), 1);
        assert_eq!(span_samples(1e300, 1e-300), MAX_SPAN_SAMPLES);
    }
}
