//! The closed set of UsdLux light kinds as one enum, dispatching `sample` and `pdf`.

use crate::{
    CylinderLight, DiskLight, DistantLight, DomeLight, LightSample, MeshLight, RectLight,
    Reference, SphereLight, Strategy,
};
use glam::DVec3;

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
