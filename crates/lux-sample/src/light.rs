//! The closed set of UsdLux light kinds as one enum, dispatching `sample` and `pdf`.

use crate::{
    CylinderLight, CylinderTechnique, DiskLight, DiskTechnique, DistantLight, DomeLight,
    LightSample, LightTransform, MeshLight, MeshTechnique, RectLight, RectTechnique, Reference,
    SampleError, SphereLight, SphereTechnique, Strategy,
};
use glam::DVec3;
use lux_math::LightShape;

/// Any sampleable UsdLux light (enum over the closed set rather than trait objects).
#[derive(Clone, Debug)]
pub enum Light {
    /// `RectLight`.
    Rect(RectLight),
    /// `DiskLight`.
    Disk(DiskLight),
    /// `SphereLight`.
    Sphere(SphereLight),
    /// `CylinderLight`.
    Cylinder(CylinderLight),
    /// A gprim with `MeshLightAPI`.
    Mesh(MeshLight),
    /// `DistantLight`.
    Distant(DistantLight),
    /// `DomeLight`.
    Dome(DomeLight),
}

impl Light {
    /// The sampler of the light described by its UsdLux shape (lux-math's [`LightShape`]: the
    /// schema's `inputs:width`, `inputs:height`, `inputs:radius`, `inputs:length`,
    /// `inputs:angle`, a mesh's local triangles) placed by its light-to-world transform, with
    /// each kind's default technique (the table of the crate README: spherical rectangle,
    /// elliptic cone, sphere cone, cylinder solid angle, spherical triangle, uniform dome). The
    /// same `shape` and transform give lux-math's `size_factor`/`emitted_radiance` and
    /// lux-spectral's `LightGeometry::from_shape`, so one light is described once.
    ///
    /// A mesh's triangles are one-sided (UsdGeom `doubleSided` false, emitting on the side of
    /// `(v1 − v0) × (v2 − v0)` in world space) and weighted by area; a dome has no texture here
    /// (build [`DomeLight::new`] with its [`crate::LatLongMap`] for one). To choose other
    /// techniques, build the kind's own type (`RectLight::new(…, technique)`): the technique is
    /// chosen once, at construction (see [`Strategy`]).
    ///
    /// Errors: the sizes' [`SampleError::NonFinite`]/[`SampleError::NonPositive`], a mesh
    /// without triangles, and [`SampleError::NotSampled`] for a `PortalLight`.
    pub fn from_shape(shape: &LightShape, xf: &LightTransform) -> Result<Light, SampleError> {
        let xf = *xf;
        Ok(match shape {
            LightShape::Rect { width, height } => Light::Rect(RectLight::new(
                *width,
                *height,
                xf,
                RectTechnique::default(),
            )?),
            LightShape::Disk { radius } => {
                Light::Disk(DiskLight::new(*radius, xf, DiskTechnique::default())?)
            }
            LightShape::Sphere { radius } => {
                Light::Sphere(SphereLight::new(*radius, xf, SphereTechnique::default())?)
            }
            LightShape::Cylinder { radius, length } => Light::Cylinder(CylinderLight::new(
                *radius,
                *length,
                xf,
                CylinderTechnique::default(),
            )?),
            LightShape::Distant { angle_deg } => {
                Light::Distant(DistantLight::new(*angle_deg, &xf)?)
            }
            LightShape::Dome => Light::Dome(DomeLight::uniform(xf)),
            LightShape::Mesh { triangles } => {
                // MeshLight::new refuses more than MAX_ENTRIES triangles: refuse them before
                // allocating (3·MAX_ENTRIES indices fit in u32)
                if triangles.len() > crate::MAX_ENTRIES {
                    return Err(SampleError::BadSize {
                        field: "triangles",
                        expected: format!("at most {} triangles", crate::MAX_ENTRIES),
                        got: triangles.len(),
                    });
                }
                let points: Vec<DVec3> = triangles.iter().flatten().map(|&p| xf.point(p)).collect();
                let indices: Vec<[u32; 3]> = (0..triangles.len() as u32)
                    .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
                    .collect();
                Light::Mesh(MeshLight::new(
                    &points,
                    &indices,
                    None,
                    false,
                    MeshTechnique::default(),
                )?)
            }
            LightShape::Portal { .. } => {
                return Err(SampleError::NotSampled {
                    light: "PortalLight",
                });
            }
        })
    }

    /// The one-sided projected solid angle `Π = ∫ max(0, n·ω) dω` of a rect, disk or sphere
    /// light from the receiver `r` ([`RectLight::projected_solid_angle`],
    /// [`DiskLight::projected_solid_angle`], [`SphereLight::projected_solid_angle`]): the
    /// unshadowed irradiance `E = L·Π` of a uniform radiance `L`, what the estimator
    /// `L·cos θ / pdf` of [`Light::sample`] averages to. `None` for the other kinds, for a
    /// reference without a normal, and where no closed form applies (a disk or sphere under a
    /// non-uniform scale or shear).
    pub fn projected_solid_angle(&self, r: &Reference) -> Option<f64> {
        match self {
            Self::Rect(l) => l.projected_solid_angle(r),
            Self::Disk(l) => l.projected_solid_angle(r),
            Self::Sphere(l) => l.projected_solid_angle(r),
            Self::Cylinder(_) | Self::Mesh(_) | Self::Distant(_) | Self::Dome(_) => None,
        }
    }

    /// Samples the light from `r` with `u ∈ [0,1)²`.
    #[inline]
    pub fn sample(&self, r: &Reference, u: [f64; 2]) -> Option<LightSample> {
        match self {
            Self::Rect(l) => l.sample(r, u),
            Self::Disk(l) => l.sample(r, u),
            Self::Sphere(l) => l.sample(r, u),
            Self::Cylinder(l) => l.sample(r, u),
            Self::Mesh(l) => l.sample(r, u),
            Self::Distant(l) => l.sample(r, u),
            Self::Dome(l) => l.sample(r, u),
        }
    }

    /// Solid-angle density with which `sample` produces the unit direction `wi` from `r`.
    #[inline]
    pub fn pdf(&self, r: &Reference, wi: DVec3) -> f64 {
        match self {
            Self::Rect(l) => l.pdf(r, wi),
            Self::Disk(l) => l.pdf(r, wi),
            Self::Sphere(l) => l.pdf(r, wi),
            Self::Cylinder(l) => l.pdf(r, wi),
            Self::Mesh(l) => l.pdf(r, wi),
            Self::Distant(l) => l.pdf(r, wi),
            Self::Dome(l) => l.pdf(r, wi),
        }
    }

    /// [`Self::sample`] with the techniques of `strategy` (see [`Strategy`]).
    #[inline]
    pub fn sample_with(
        &self,
        r: &Reference,
        u: [f64; 2],
        strategy: Strategy,
    ) -> Option<LightSample> {
        match self {
            Self::Rect(l) => l.sample_with(r, u, strategy),
            Self::Disk(l) => l.sample_with(r, u, strategy),
            Self::Sphere(l) => l.sample_with(r, u, strategy),
            Self::Cylinder(l) => l.sample_with(r, u, strategy),
            Self::Mesh(l) => l.sample_with(r, u, strategy),
            Self::Distant(l) => l.sample_with(r, u, strategy),
            Self::Dome(l) => l.sample_with(r, u, strategy),
        }
    }

    /// [`Self::pdf`] of the techniques of `strategy`.
    #[inline]
    pub fn pdf_with(&self, r: &Reference, wi: DVec3, strategy: Strategy) -> f64 {
        match self {
            Self::Rect(l) => l.pdf_with(r, wi, strategy),
            Self::Disk(l) => l.pdf_with(r, wi, strategy),
            Self::Sphere(l) => l.pdf_with(r, wi, strategy),
            Self::Cylinder(l) => l.pdf_with(r, wi, strategy),
            Self::Mesh(l) => l.pdf_with(r, wi, strategy),
            Self::Distant(l) => l.pdf_with(r, wi, strategy),
            Self::Dome(l) => l.pdf_with(r, wi, strategy),
        }
    }
}
