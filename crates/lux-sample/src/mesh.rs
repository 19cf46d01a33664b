//! Mesh lights (UsdLux `MeshLightAPI` on a `UsdGeomMesh`): triangle selection by area or power
//! with an alias table, then a point on the triangle by spherical triangle sampling (Arvo 1995)
//! or by area.

use crate::alias::AliasTable;
use crate::error::{MAX_ENTRIES, SampleError};
use crate::spherical::{sample_spherical_triangle, spherical_triangle_area};
use crate::{AreaSample, LightSample, MIN_SOLID_ANGLE, Reference, Strategy};
use glam::DVec3;

/// Largest solid angle (sr) handed to the spherical-triangle sampler; above it (a triangle
/// covering almost a hemisphere, seen from very close) area sampling is steadier (pbrt-v4 uses
/// the same 6.22 sr bound).
const MAX_SPHERICAL_TRIANGLE: f64 = 6.22;

/// How a [`MeshLight`] samples within the chosen triangle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MeshTechnique {
    /// Uniform by area within the triangle.
    Area,
    /// Uniform in solid angle (Arvo), area for tiny (< [`MIN_SOLID_ANGLE`]) or huge triangles.
    #[default]
    SphericalTriangle,
}

#[derive(Clone, Copy, Debug)]
struct Triangle {
    v: [DVec3; 3],
    /// Unnormalised geometric normal (v1 − v0) × (v2 − v0); |n| = 2·area.
    n: DVec3,
    area: f64,
}

/// A gprim with UsdLux `MeshLightAPI` prepared for sampling: its triangles in **world** space
/// (the prim transform applied to the points — [`crate::Light::from_shape`] does it for a
/// `LightShape::Mesh`; affine maps keep triangles triangles, so densities stay exact), one
/// chosen by area × power (alias table), then a point by the built technique. Each triangle
/// emits from the side of `(v1 − v0) × (v2 − v0)`, or both with UsdGeom `doubleSided`.
#[derive(Clone, Debug)]
pub struct MeshLight {
    tris: Vec<Triangle>,
    table: AliasTable,
    two_sided: bool,
    technique: MeshTechnique,
}

impl MeshLight {
    /// Builds the light from world points and triangle indices. `power` (optional, one
    /// non-negative factor per triangle, e.g. luminance of its emission) multiplies the area in
    /// the selection weights. `two_sided` follows UsdGeom `doubleSided`; one-sided triangles
    /// emit on the side of (v1 − v0) × (v2 − v0) (right-handed orientation).
    pub fn new(
        points: &[DVec3],
        indices: &[[u32; 3]],
        power: Option<&[f64]>,
        two_sided: bool,
        technique: MeshTechnique,
    ) -> Result<Self, SampleError> {
        if indices.is_empty() || indices.len() > MAX_ENTRIES {
            return Err(SampleError::BadSize {
                field: "indices",
                expected: format!("1..={MAX_ENTRIES} triangles"),
                got: indices.len(),
            });
        }
        if let Some(p) = power
            && p.len() != indices.len()
        {
            return Err(SampleError::BadSize {
                field: "power",
                expected: format!("one value per triangle ({})", indices.len()),
                got: p.len(),
            });
        }
        for (i, p) in points.iter().enumerate() {
            if !p.is_finite() {
                return Err(SampleError::BadWeight {
                    field: "points",
                    index: i,
                    value: f64::NAN,
                });
            }
        }
        let mut tris = Vec::with_capacity(indices.len());
        let mut weights = Vec::with_capacity(indices.len());
        for (t, idx) in indices.iter().enumerate() {
            let mut v = [DVec3::ZERO; 3];
            for k in 0..3 {
                let i = idx[k];
                v[k] = *points.get(i as usize).ok_or(SampleError::BadIndex {
                    triangle: t,
                    index: i,
                    vertices: points.len(),
                })?;
            }
            let n = (v[1] - v[0]).cross(v[2] - v[0]);
            let area = 0.5 * n.length();
            let w = match power {
                Some(p) => {
                    let value = p[t];
                    if !(value.is_finite() && value >= 0.0) {
                        return Err(SampleError::BadWeight {
                            field: "power",
                            index: t,
                            value,
                        });
                    }
                    value * area
                }
                None => area,
            };
            tris.push(Triangle { v, n, area });
            weights.push(w);
        }
        let table =
            AliasTable::new(&weights).map_err(|_| SampleError::AllZero("triangle weights"))?;
        Ok(Self {
            tris,
            table,
            two_sided,
            technique,
        })
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }

    /// Σ world triangle areas (the mesh light's sizeFactor for `normalize`).
    pub fn area(&self) -> f64 {
        self.tris.iter().map(|t| t.area).sum()
    }

    /// Probability of selecting triangle `i`.
    pub fn triangle_pmf(&self, i: usize) -> f64 {
        self.table.pmf(i)
    }

    #[inline]
    fn facing(&self, t: &Triangle, p: DVec3) -> bool {
        self.two_sided || (p - t.v[0]).dot(t.n) > 0.0
    }

    #[inline]
    fn use_spherical(omega: f64, technique: MeshTechnique) -> bool {
        technique == MeshTechnique::SphericalTriangle
            && (MIN_SOLID_ANGLE..=MAX_SPHERICAL_TRIANGLE).contains(&omega)
    }

    /// Samples a triangle (by `u[0]`, whose leftover bits are reused) and a point on it.
    /// Returns the sample and the triangle index. `None` if the chosen triangle faces away.
    #[inline]
    pub fn sample_with_index(&self, r: &Reference, u: [f64; 2]) -> Option<(LightSample, usize)> {
        self.sample_by(r, u, self.technique)
    }

    /// The technique `strategy` stands for (`HdEmbree`: [`MeshTechnique::Area`]).
    #[inline]
    fn technique_of(&self, strategy: Strategy) -> MeshTechnique {
        match strategy {
            Strategy::Lux => self.technique,
            Strategy::HdEmbree => MeshTechnique::Area,
        }
    }

    #[inline]
    fn sample_by(
        &self,
        r: &Reference,
        u: [f64; 2],
        technique: MeshTechnique,
    ) -> Option<(LightSample, usize)> {
        let (i, pmf, u0) = self.table.sample_remap(u[0]);
        let t = &self.tris[i];
        let p = r.p;
        if !self.facing(t, p) {
            return None;
        }
        let a = (t.v[0] - p).normalize();
        let b = (t.v[1] - p).normalize();
        let c = (t.v[2] - p).normalize();
        let omega = spherical_triangle_area(a, b, c);
        let nn = t.n / (2.0 * t.area);
        let (q, pdf) = if Self::use_spherical(omega, technique) {
            let (w, pdf) = sample_spherical_triangle(a, b, c, [u0, u[1]])?;
            let den = w.dot(t.n);
            if den == 0.0 {
                return None;
            }
            let dist = (t.v[0] - p).dot(t.n) / den;
            (p + dist * w, pdf)
        } else {
            let s = u0.sqrt();
            let (b0, b1) = (1.0 - s, u[1] * s);
            let q = b0 * t.v[0] + b1 * t.v[1] + (1.0 - b0 - b1) * t.v[2];
            let d = q - p;
            let d2 = d.length_squared();
            let cos = nn.dot(d).abs() / d2.sqrt();
            (q, d2 / (cos * t.area))
        };
        let d = q - p;
        let distance = d.length();
        let wi = d / distance;
        let pdf = pdf * pmf;
        if !(distance > 0.0 && pdf.is_finite() && pdf > 0.0) {
            return None;
        }
        let normal = if nn.dot(wi) < 0.0 { nn } else { -nn };
        Some((
            LightSample {
                point: q,
                normal,
                wi,
                distance,
                pdf,
                delta: false,
            },
            i,
        ))
    }

    /// Samples a point; see [`Self::sample_with_index`].
    #[inline]
    pub fn sample(&self, r: &Reference, u: [f64; 2]) -> Option<LightSample> {
        self.sample_with_index(r, u).map(|(s, _)| s)
    }

    /// [`Self::sample`] with the techniques of `strategy` (`HdEmbree`: the triangle chosen as
    /// prepared, then [`MeshTechnique::Area`] within it).
    #[inline]
    pub fn sample_with(
        &self,
        r: &Reference,
        u: [f64; 2],
        strategy: Strategy,
    ) -> Option<LightSample> {
        self.sample_by(r, u, self.technique_of(strategy))
            .map(|(s, _)| s)
    }

    /// Density of producing direction `wi` **through triangle `i`** (selection × in-triangle
    /// density); 0 if the ray misses it or hits its back. This is what a renderer uses for MIS
    /// after its ray hit triangle `i`.
    #[inline]
    pub fn pdf_triangle(&self, r: &Reference, i: usize, wi: DVec3) -> f64 {
        self.pdf_triangle_by(r, i, wi, self.technique)
    }

    /// [`Self::pdf_triangle`] of the techniques of `strategy`.
    #[inline]
    pub fn pdf_triangle_with(&self, r: &Reference, i: usize, wi: DVec3, strategy: Strategy) -> f64 {
        self.pdf_triangle_by(r, i, wi, self.technique_of(strategy))
    }

    #[inline]
    fn pdf_triangle_by(&self, r: &Reference, i: usize, wi: DVec3, technique: MeshTechnique) -> f64 {
        let Some(t) = self.tris.get(i) else {
            return 0.0;
        };
        let p = r.p;
        if !p.is_finite() {
            return 0.0;
        }
        if !self.facing(t, p) {
            return 0.0;
        }
        let Some(dist) = ray_triangle(p, wi, t) else {
            return 0.0;
        };
        let a = (t.v[0] - p).normalize();
        let b = (t.v[1] - p).normalize();
        let c = (t.v[2] - p).normalize();
        let omega = spherical_triangle_area(a, b, c);
        let pdf = if Self::use_spherical(omega, technique) {
            1.0 / omega
        } else {
            let cos = (t.n / (2.0 * t.area)).dot(wi).abs();
            dist * dist / (cos * t.area)
        };
        pdf * self.table.pmf(i)
    }

    /// Whether both sides of every triangle emit (UsdGeom `doubleSided`).
    #[inline]
    pub fn two_sided(&self) -> bool {
        self.two_sided
    }

    /// A point on the light's surface for emission sampling (pbrt-v4's `SampleLe` position):
    /// a triangle chosen with the selection weights by `u[0]` (its leftover bits reused), then a
    /// point uniform on it. The density is per unit area, `pmf(i) / area(i)`; the normal is the
    /// front side's (`(v1 − v0) × (v2 − v0)`, unit). `None` for a degenerate triangle.
    #[inline]
    pub fn sample_area(&self, u: [f64; 2]) -> Option<AreaSample> {
        let (i, pmf, u0) = self.table.sample_remap(u[0]);
        let t = &self.tris[i];
        if t.area.is_nan() || t.area <= 0.0 {
            return None;
        }
        let s = u0.sqrt();
        let (b0, b1) = (1.0 - s, u[1] * s);
        let point = b0 * t.v[0] + b1 * t.v[1] + (1.0 - b0 - b1) * t.v[2];
        Some(AreaSample {
            point,
            normal: t.n / (2.0 * t.area),
            pdf: pmf / t.area,
        })
    }

    /// Total density of direction `wi` over all triangles it crosses (O(triangles); for tests and
    /// small meshes — renderers should call [`Self::pdf_triangle`] with the hit triangle).
    pub fn pdf(&self, r: &Reference, wi: DVec3) -> f64 {
        self.pdf_with(r, wi, Strategy::Lux)
    }

    /// [`Self::pdf`] of the techniques of `strategy`.
    pub fn pdf_with(&self, r: &Reference, wi: DVec3, strategy: Strategy) -> f64 {
        (0..self.tris.len())
            .map(|i| self.pdf_triangle_with(r, i, wi, strategy))
            .sum()
    }
}

/// Möller–Trumbore ray/triangle distance (t > 0), or `None`.
#[inline]
fn ray_triangle(p: DVec3, w: DVec3, t: &Triangle) -> Option<f64> {
    let e1 = t.v[1] - t.v[0];
    let e2 = t.v[2] - t.v[0];
    let pv = w.cross(e2);
    let det = e1.dot(pv);
    if det == 0.0 {
        return None;
    }
    let inv = 1.0 / det;
    let tv = p - t.v[0];
    let b1 = tv.dot(pv) * inv;
    if !(0.0..=1.0).contains(&b1) {
        return None;
    }
    let qv = tv.cross(e1);
    let b2 = w.dot(qv) * inv;
    if b2 < 0.0 || b1 + b2 > 1.0 {
        return None;
    }
    let dist = e2.dot(qv) * inv;
    (dist > 0.0).then_some(dist)
}
