//! Mesh lights (UsdLux `MeshLightAPI` on a `UsdGeomMesh`, and emissive geometry): every
//! triangle of the world-space mesh emits from its front side (both sides when `doubleSided`).
//!
//! A mesh inside an instanced prototype emits once per instance: each instance's light holds
//! the prototype mesh mapped to the world by the instance transform (`M·v`, the winding
//! reversed when `det M < 0` so that the front stays the USD front side), exactly the
//! triangles flattening the instance would give, so areas, normals and the emitting side are
//! the world ones whatever the scale, shear or mirroring.

use super::{LiSample, LightBase, LightHit, Seen};
use glam::DVec3;
use lux_sample::{LightBounds, Reference, Strategy};
use lux_usd::Mesh;

/// A mesh light: the scene mesh it emits from and its sampler (triangle by area, then the
/// spherical triangle).
#[derive(Clone, Debug)]
pub struct MeshLight {
    /// What every light carries.
    pub base: LightBase,
    /// Index into `Scene::meshes` (for an instance, its prototype's mesh).
    pub mesh: usize,
    /// Index into `Scene::instances` of the instance the light emits from; `None` for a
    /// world-space mesh.
    pub instance: Option<usize>,
    /// What camera rays see on the mesh instead of the light's radiance: the bound material's
    /// UsdPreviewSurface `emissiveColor` under `materialSyncMode` `materialGlowTintsLight` or
    /// `independent` (geometry-lights proposal: "primary rays see the emissive/glow response as
    /// dictated by the bound Material"); `None`: the light's own radiance.
    pub glow: Option<DVec3>,
    /// World box of the mesh's points.
    world_box: (DVec3, DVec3),
    pub(super) sampler: lux_sample::MeshLight,
}

impl MeshLight {
    /// The world-space mesh `m` (index `mesh` in the scene); `Err` names what lux-sample
    /// refused (no triangles, bad indices).
    pub(super) fn new(base: LightBase, mesh: usize, m: &Mesh) -> Result<MeshLight, String> {
        MeshLight::from_world(base, mesh, None, &m.positions, &m.triangles, m.double_sided)
    }

    /// The light of scene mesh `mesh` drawn by `instance` (`None`: in the world) from its
    /// world-space `positions` and `triangles` (wound towards the front side).
    pub(super) fn from_world(
        base: LightBase,
        mesh: usize,
        instance: Option<usize>,
        positions: &[DVec3],
        triangles: &[[u32; 3]],
        double_sided: bool,
    ) -> Result<MeshLight, String> {
        let sampler = lux_sample::MeshLight::new(
            positions,
            triangles,
            None,
            double_sided,
            lux_sample::MeshTechnique::SphericalTriangle,
        )
        .map_err(|e| e.to_string())?;
        let world_box = positions.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        Ok(MeshLight {
            base,
            mesh,
            instance,
            glow: None,
            world_box,
            sampler,
        })
    }

    /// See [`super::Light::sample_li`].
    #[inline]
    pub fn sample_li(&self, r: &Reference, u: [f64; 2], strategy: Strategy) -> Option<LiSample> {
        let s = self.sampler.sample_with(r, u, strategy)?;
        Some(LiSample::new(s, self.le(DVec3::ZERO, -s.wi, Seen::Lit)))
    }

    /// Density of the direction `wi` over every triangle it crosses (O(triangles)); after a
    /// ray hit, use [`MeshLight::pdf_li_triangle`].
    #[inline]
    pub fn pdf_li(&self, r: &Reference, wi: DVec3) -> f64 {
        self.sampler.pdf(r, wi)
    }

    /// Density of sampling the direction `wi` through triangle `tri` (what a BSDF ray that hit
    /// that triangle needs for MIS).
    #[inline]
    pub fn pdf_li_triangle(&self, r: &Reference, tri: usize, wi: DVec3) -> f64 {
        self.sampler.pdf_triangle(r, tri, wi)
    }

    /// Radiance along the world direction `emit`: `base · shapingFactor` (the triangle's side
    /// is decided by the sampler and the hit).
    #[inline]
    pub fn le(&self, _local: DVec3, emit: DVec3, _seen: Seen) -> DVec3 {
        self.base.emitted(emit)
    }

    /// A finite light: nothing arrives from infinity.
    #[inline]
    pub fn le_escape(&self, _wi: DVec3) -> DVec3 {
        DVec3::ZERO
    }

    /// See [`super::Light::uniform_area`]: not one of its kinds.
    #[inline]
    pub fn uniform_area(&self) -> bool {
        false
    }

    /// No analytic surface: found by rays only through the scene's triangle BVH, as the mesh it emits from.
    #[inline]
    pub fn intersect(&self, _o: DVec3, _d: DVec3, _tmin: f64, _tmax: f64) -> Option<LightHit> {
        None
    }

    /// No analytic surface.
    pub fn surface_box(&self) -> Option<(DVec3, DVec3)> {
        None
    }

    /// See [`super::Light::bounds`]: normals in every direction, both sides.
    pub fn bounds(&self) -> Option<LightBounds> {
        let half_pi = std::f64::consts::FRAC_PI_2;
        self.base
            .bounds(self.world_box, std::f64::consts::PI, half_pi, true)
    }

    /// Power estimate: `Y(base) · area · π · max shaping factor`.
    pub(super) fn power(&self, area: f64) -> f64 {
        lux_math::luminance(self.base.radiance).max(0.0)
            * area
            * std::f64::consts::PI
            * self.base.shaping.max_factor()
    }
}
