//! Integrators: what a camera ray brings back, `(radiance, alpha)`, from the prepared scene
//! ([`World`]). The closed set is [`Integrator`]; `direct.rs` is the direct-lighting estimator
//! (the reference renderer's light transport with lux's sampling), `path.rs` the path tracer
//! built on it.
//!
//! Shared here: the shadow-ray transmission of `ShadowAPI` ([`visibility`]) and the power
//! heuristic of multiple importance sampling.

mod direct;
mod path;
mod shadow;
mod trace;

pub use direct::DirectIntegrator;
pub use path::{PathIntegrator, ROULETTE_DEPTH};
pub use shadow::{first_shadow_occluder, shadow_ray};
pub use trace::closest;

use crate::film::Counters;
use crate::geometry::Geometry;
use crate::light::LightSet;
use crate::material::Materials;
use crate::sampler::SampleStream;
use glam::DVec3;
use lux_usd::Scene;

/// The prepared scene an integrator reads: geometry (with the area lights' BVH), lights and
/// materials.
#[derive(Clone, Copy)]
pub struct World<'a> {
    /// The stage the rest was prepared from (mesh attributes for shading).
    pub scene: &'a Scene,
    /// Triangles, instances and the analytic lights' BVH.
    pub geometry: &'a Geometry,
    /// The shadow rays' BVH of flat cards' outlines and the searches of shadow regions.
    pub shadows: crate::visibility::Shadows<'a>,
    /// The lights and their selection.
    pub lights: &'a LightSet,
    /// Surfaces' BSDFs.
    pub materials: &'a Materials,
    /// Whether some surface lets rays through ([`Materials::any_transparent`]).
    pub transparent: bool,
    /// Whether some surface glows from a texture ([`Materials::emission`]), which only camera
    /// and BSDF rays find.
    pub textured_emission: bool,
}

/// A camera ray: origin, unit direction and the clipping range `(tmin, tmax)`.
#[derive(Clone, Copy, Debug)]
pub struct CameraRay {
    /// Origin (world).
    pub o: DVec3,
    /// Unit direction (world).
    pub d: DVec3,
    /// Near clipping distance along `d`.
    pub tmin: f64,
    /// Far clipping distance along `d`.
    pub tmax: f64,
}

/// Every light-transport estimator lux has.
#[derive(Clone, Copy)]
pub enum Integrator<'a> {
    /// Direct lighting (light sampling, MIS with BSDF sampling).
    Direct(DirectIntegrator<'a>),
    /// Path tracing over the direct estimate at every vertex.
    Path(PathIntegrator<'a>),
}

/// Most triangles a tile's camera rays test as a list ([`Integrator::tile_rays`]): beyond that
/// the BVH's traversal costs less.
pub const TILE_TRIANGLES: usize = 12;

/// What the camera rays through one tile of pixels can meet ([`Integrator::tile_rays`]), for
/// every sample of the tile ([`Counters::tile`](crate::film::Counters::tile)).
#[derive(Clone, Debug, Default)]
pub struct TileRays {
    /// The world triangles the rays can hit, when few; `None`: they take the BVH.
    pub triangles: Option<Box<[u32]>>,
    /// Nothing at all: no triangle, no camera-visible analytic light and no background, so
    /// every ray ends black with alpha 0 ([`DirectIntegrator::li`]'s answer for a ray that meets
    /// nothing), which the film takes without tracing it.
    pub empty: bool,
}

impl Integrator<'_> {
    /// What the camera rays through pixels `[x0, y0, x1, y1)` can meet, from the camera's
    /// [`Camera::frustum`] of the tile: the world triangles in it ([`Geometry::triangles_in`];
    /// `None`, the BVH, with more than [`TILE_TRIANGLES`], with instances or partly transparent
    /// surfaces, whose rays go on past a hit), and whether it holds nothing at all — no
    /// triangle, no camera-visible light at infinity, and no camera-visible analytic light
    /// whose box reaches the frustum ([`Geometry::no_light_in`]).
    ///
    /// [`Camera::frustum`]: crate::camera::Camera::frustum
    pub fn tile_rays(&self, camera: &crate::camera::Camera, rect: [u32; 4]) -> TileRays {
        let w = match self {
            Integrator::Direct(i) => &i.world,
            Integrator::Path(i) => i.world(),
        };
        let Some((lo, hi)) = w.geometry.world_bounds().filter(|_| !w.transparent) else {
            return TileRays::default();
        };
        let Some(frustum) = crate::visibility::RayFrustum::of_tile(
            camera,
            rect,
            lo.abs().max(hi.abs()).max_element(),
        ) else {
            return TileRays::default();
        };
        let triangles = w.shadows.triangles_in(&frustum, TILE_TRIANGLES);
        let lights = &w.lights.lights;
        let empty = triangles.as_ref().is_some_and(|t| t.is_empty())
            && w.lights.background.is_empty()
            && w.lights.shapes.none_in(
                lights,
                |lo, hi| frustum.misses_box(lo, hi),
                |l| l.base().camera_visible,
            );
        TileRays { triangles, empty }
    }

    /// Radiance (RGB) and alpha (coverage) along a camera ray, drawing its random numbers
    /// from `st`.
    #[inline]
    pub fn li(&self, ray: &CameraRay, st: &SampleStream, c: &mut Counters) -> (DVec3, f64) {
        match self {
            Integrator::Direct(i) => i.li(ray, st, c),
            Integrator::Path(i) => i.li(ray, st, c),
        }
    }
}

/// Power heuristic, β = 2.
#[inline]
pub fn power_heuristic(a: f64, b: f64) -> f64 {
    let (a2, b2) = (a * a, b * b);
    if a2.is_infinite() {
        return 1.0;
    }
    if a2 + b2 > 0.0 { a2 / (a2 + b2) } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_heuristic_values() {
        assert_eq!(power_heuristic(1.0, 1.0), 0.5);
        assert_eq!(power_heuristic(3.0, 1.0), 0.9);
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
        assert_eq!(power_heuristic(f64::INFINITY, 1.0), 1.0);
        assert!((power_heuristic(1.0, 3.0) + power_heuristic(3.0, 1.0) - 1.0).abs() < 1e-15);
    }
}
