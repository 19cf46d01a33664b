//! Curve primvars — `widths`, `normals`, `primvars:displayColor` — and how their values map
//! onto the curves of a prim: the `interpolation` metadata, `:indices`, and the sizes
//! UsdGeomBasisCurves ("Primvar Interpolation") and UsdGeomNurbsCurves define.

use crate::error::{LoadError, WarningKind};
use crate::reader::Reader;
use openusd::usd::Prim;
use std::ops::{Add, Mul, Sub};

/// What is interpolated along a curve (positions, widths, colours, normals, homogeneous
/// points): anything with `+`, `−` and scaling by an `f64`.
pub trait Value: Copy + Add<Output = Self> + Sub<Output = Self> + Mul<f64, Output = Self> {}

impl<T> Value for T where T: Copy + Add<Output = T> + Sub<Output = T> + Mul<f64, Output = T> {}

/// A curve primvar's `interpolation`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// One value for the prim.
    Constant,
    /// One value per curve.
    Uniform,
    /// Linear across each segment: one value per segment end (UsdGeomBasisCurves' varying
    /// count: segments + 1 per nonperiodic or pinned curve, segments per periodic curve).
    Varying,
    /// One value per control vertex, interpolated with the curve's own basis.
    Vertex,
}

impl Interpolation {
    /// Parses an `interpolation` token; `None` for `faceVarying` (not defined for curves) and
    /// anything unknown.
    pub fn parse(token: &str) -> Option<Interpolation> {
        Some(match token {
            "constant" => Interpolation::Constant,
            "uniform" => Interpolation::Uniform,
            "varying" => Interpolation::Varying,
            "vertex" => Interpolation::Vertex,
            _ => return None,
        })
    }

    /// The token.
    pub fn token(self) -> &'static str {
        match self {
            Interpolation::Constant => "constant",
            Interpolation::Uniform => "uniform",
            Interpolation::Varying => "varying",
            Interpolation::Vertex => "vertex",
        }
    }
}

/// The number of values each interpolation takes on one prim's curves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sizes {
    /// Curves (`uniform`).
    pub curves: usize,
    /// Segment ends summed over the curves (`varying`).
    pub varying: usize,
    /// Control vertices (`vertex`): the length of `points`.
    pub vertex: usize,
}

impl Sizes {
    /// The number of values `interpolation` takes.
    pub fn of(self, interpolation: Interpolation) -> usize {
        match interpolation {
            Interpolation::Constant => 1,
            Interpolation::Uniform => self.curves,
            Interpolation::Varying => self.varying,
            Interpolation::Vertex => self.vertex,
        }
    }
}

/// A curve primvar's values (already looked up through `:indices`) and interpolation.
#[derive(Clone, Debug, PartialEq)]
pub struct CurvePrimvar<T> {
    /// How the values map onto the curves.
    pub interpolation: Interpolation,
    /// The values: 1, one per curve, one per segment end or one per control vertex.
    pub values: Vec<T>,
}

impl<T: Copy> CurvePrimvar<T> {
    /// One value for the whole prim.
    pub fn constant(value: T) -> CurvePrimvar<T> {
        CurvePrimvar {
            interpolation: Interpolation::Constant,
            values: vec![value],
        }
    }

    /// `values` under `interpolation`, checked against `sizes`: the right count is kept; a
    /// single value under any interpolation is read as constant (as Storm does,
    /// `HdSt_BasisCurvesPrimvarInterpolaterComputation`: `widths = [0.22]` with the schema's
    /// default `vertex` interpolation is a common authoring); a constant with more values
    /// keeps the first. Any other count is an error message.
    pub fn new(
        values: Vec<T>,
        interpolation: Interpolation,
        sizes: Sizes,
    ) -> Result<CurvePrimvar<T>, String> {
        let want = sizes.of(interpolation);
        if values.len() == want {
            return Ok(CurvePrimvar {
                interpolation,
                values,
            });
        }
        if values.len() == 1 || (interpolation == Interpolation::Constant && !values.is_empty()) {
            return Ok(CurvePrimvar::constant(values[0]));
        }
        Err(format!(
            "{} values for {} interpolation ({want} expected)",
            values.len(),
            interpolation.token()
        ))
    }
}

/// `primvars:displayColor` of a curves or points prim (constant when its interpolation is
/// unauthored), or `None` (unauthored, empty, or — with a warning — inconsistent).
pub fn display_color(
    r: &mut Reader<'_>,
    prim: &Prim,
    sizes: Sizes,
) -> Result<Option<CurvePrimvar<glam::DVec3>>, LoadError> {
    match r.vec3_array(prim, "primvars:displayColor")? {
        Some(c) if !c.is_empty() => read(
            r,
            prim,
            "primvars:displayColor",
            c,
            Interpolation::Constant,
            sizes,
            "ignored",
        ),
        _ => Ok(None),
    }
}

/// Reads the `interpolation` (default `default_interp`) and `:indices` of the authored
/// `values` of `name` and checks them against `sizes` ([`CurvePrimvar::new`]). When they do not
/// fit, a warning naming the prim and the primvar ends with `fallback` (what is drawn instead)
/// and the result is `None`.
pub fn read<T: Copy>(
    r: &mut Reader<'_>,
    prim: &Prim,
    name: &str,
    values: Vec<T>,
    default_interp: Interpolation,
    sizes: Sizes,
    fallback: &str,
) -> Result<Option<CurvePrimvar<T>>, LoadError> {
    let token = r.attr_metadata_text(prim, name, "interpolation");
    let interpolation = match token.as_deref() {
        None => default_interp,
        Some(t) => match Interpolation::parse(t) {
            Some(i) => i,
            None => {
                r.warn(
                    prim,
                    WarningKind::Unsupported,
                    format!("{name}: interpolation {t:?} is not defined for curves; {fallback}"),
                );
                return Ok(None);
            }
        },
    };
    let idx_name = format!("{name}:indices");
    let values = match r.raw(prim, &idx_name)? {
        Some(v) => match crate::value::as_int_array(&v) {
            Some(ix) => {
                let mapped: Option<Vec<T>> = ix
                    .iter()
                    .map(|&i| usize::try_from(i).ok().and_then(|i| values.get(i).copied()))
                    .collect();
                match mapped {
                    Some(m) => m,
                    None => {
                        r.warn(
                            prim,
                            WarningKind::InvalidGeometry,
                            format!("{idx_name}: an index is out of range; {fallback}"),
                        );
                        return Ok(None);
                    }
                }
            }
            None => values,
        },
        None => values,
    };
    match CurvePrimvar::new(values, interpolation, sizes) {
        Ok(p) => Ok(Some(p)),
        Err(e) => {
            r.warn(
                prim,
                WarningKind::InvalidGeometry,
                format!("{name}: {e}; {fallback}"),
            );
            Ok(None)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_and_single_values() {
        let sizes = Sizes {
            curves: 2,
            varying: 5,
            vertex: 8,
        };
        let v = CurvePrimvar::new(vec![1.0; 5], Interpolation::Varying, sizes).unwrap();
        assert_eq!(v.interpolation, Interpolation::Varying);
        let c = CurvePrimvar::new(vec![0.22], Interpolation::Vertex, sizes).unwrap();
        assert_eq!(c, CurvePrimvar::constant(0.22));
        let c = CurvePrimvar::new(vec![3.0, 4.0], Interpolation::Constant, sizes).unwrap();
        assert_eq!(c, CurvePrimvar::constant(3.0));
        let e = CurvePrimvar::new(vec![1.0; 7], Interpolation::Vertex, sizes).unwrap_err();
        assert_eq!(e, "7 values for vertex interpolation (8 expected)");
        assert!(CurvePrimvar::<f64>::new(vec![], Interpolation::Uniform, sizes).is_err());
    }
}
