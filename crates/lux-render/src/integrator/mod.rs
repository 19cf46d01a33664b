//! Integrators: what a camera sample brings back, `(radiance, alpha)` along its ray, and the
//! splats it adds elsewhere on the film, from the prepared scene ([`World`]).
//!
//! pbrt-v4's shape: every integrator implements [`Integrator`] (one file each), and the closed
//! set is [`AnyIntegrator`], generated with [`IntegratorKind`] (the `--integrator` names) from
//! the one registration list at the foot of this file. What they share lives beside them:
//!
//! | file | what |
//! |---|---|
//! | `camera_vertex.rs` | what a camera ray meets first: a visible light, the background, or a surface and its glow |
//! | `nee.rs` | next-event estimation: light sampling with MIS against BSDF sampling, written once |
//! | `shadow.rs` | shadow rays (`ShadowAPI`, shadow linking) through [`Visibility`] |
//! | `trace.rs` | rays through partly transparent surfaces |
//! | `direct.rs` | [`DirectIntegrator`]: next-event estimation at the first surface |
//! | `path.rs` | [`PathIntegrator`]: next-event estimation at every vertex of a BSDF-sampled path |
//! | `light_tracer.rs` | [`LightTracer`]: particles from the lights, splatted to the camera |
//!
//! Adding an integrator: a file here with a type that has `new(&Setup) -> Self` and implements
//! [`Integrator`], and one line in the `integrators!` list below.

mod camera_vertex;
mod direct;
mod light_tracer;
mod nee;
mod path;
mod shadow;
mod trace;

pub use direct::DirectIntegrator;
pub use light_tracer::LightTracer;
pub use nee::ShadowPool;
pub use path::{PathIntegrator, ROULETTE_DEPTH, ROULETTE_SCALE};
pub use shadow::{first_shadow_occluder, shadow_ray};
pub use trace::closest;

use crate::camera::Camera;
use crate::film::Splat;
use crate::sampler::SampleStream;
use crate::stats::Counters;
use crate::visibility::{Scratch, Visibility};
use crate::world::World;
use glam::DVec3;

/// Which sampling techniques the renderer uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SamplingMode {
    /// lux's importance sampling (solid-angle techniques, textured dome) with MIS against
    /// BSDF sampling.
    #[default]
    Lux,
    /// hdEmbree's strategies, for A/B comparison: every area light sampled uniformly by area,
    /// the dome uniformly over the hemisphere around the normal, light sampling only (no
    /// MIS). Same expectation, more noise.
    Reference,
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

/// What one worker carries from sample to sample: its counters, the visibility's scratch
/// (patch answers, the current tile's hint) and the splats of the current tile.
#[derive(Clone, Debug, Default)]
pub struct Ctx {
    /// Rays, shadow rays, light samples … ([`Counters`]).
    pub counters: Counters,
    /// The visibility's per-worker state ([`Scratch`]).
    pub vis: Scratch,
    /// Splats to other pixels ([`Integrator::splats`]), which the tile loop hands to the film.
    pub splats: Vec<Splat>,
    /// The path tracer's continuations since the tile loop last cleared it, at the start of
    /// each run of a pixel's samples ([`SplitSums`]).
    pub split: SplitSums,
    /// Next-event estimation's buffer of light samples whose shadow rays are resampled
    /// together (`nee.rs`).
    pub pool: ShadowPool,
}

/// Sums over camera samples that split into path continuations (the path tracer's, with
/// `k ≥ 2`), which adaptive splitting reads from a pixel's first samples
/// (`AdaptiveSampling::max_splits`). A camera sample's estimate is `A + (1/k)·Σⱼ cⱼ`, `A` the
/// camera vertex's light and `cⱼ` what continuation `j` brings back.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SplitSums {
    /// Σ over samples of `Σⱼ (Y(cⱼ) − Ȳ)² / (k − 1)`, `Y` the luminance: each term is an
    /// unbiased estimate of the variance of one continuation's luminance given the camera
    /// sample.
    pub spread: f64,
    /// Rays (closest-hit and shadow) traced by the continuations.
    pub continuation_rays: u64,
}

/// Everything an integrator is built from: the scene, how it sees, the camera and the
/// transport settings (`RenderOptions`).
#[derive(Clone, Copy)]
pub struct Setup<'a> {
    /// The prepared scene.
    pub world: World<'a>,
    /// How shadow rays and camera rays are answered (`--visibility`).
    pub vis: &'a Visibility,
    /// The camera (splatting integrators project onto it).
    pub camera: &'a Camera,
    /// Sampling techniques.
    pub sampling: SamplingMode,
    /// Light samples per light (or light choice) at each shading point (≥ 1).
    pub light_samples: u32,
    /// Most surface vertices a path lights (≥ 1).
    pub max_depth: u32,
    /// Paths continued from each camera sample's first vertex (`path`, ≥ 1).
    pub splits: u32,
    /// Shadow rays a path vertex past the camera's shares among its light samples (0: one
    /// each; `RenderOptions::shadow_rays`).
    pub shadow_rays: u32,
}

/// A light-transport estimator: pbrt-v4's `Integrator::Li` for one camera sample.
pub trait Integrator: Sync {
    /// Radiance (RGB) and alpha (coverage) along the camera ray `ray`, drawing its random
    /// numbers from `st`; a splatting integrator also adds splats to `ctx.splats`.
    fn li(&self, ray: &CameraRay, st: &SampleStream, ctx: &mut Ctx) -> (DVec3, f64);

    /// Whether [`Integrator::li`] adds splats: the film then divides their sum by the number
    /// of camera samples of the render, and the render takes no adaptive or penumbra samples
    /// (each camera sample must be one particle of the same estimator).
    fn splats(&self) -> bool {
        false
    }

    /// Path continuations each camera sample splits into at its first surface (1: none), as
    /// [`Ctx::split`] counts them; a camera sample asking for another count
    /// ([`SampleStream::splits`]) takes it.
    fn splits(&self) -> u32 {
        1
    }

    /// What this integrator cannot do as the scene says (each names the prim and what was
    /// approximated), reported with the render's warnings.
    fn warnings(&self) -> Vec<String> {
        Vec::new()
    }
}

/// The BSDF sample of path vertex `bounce`: its 2D direction numbers `Dim::Bsdf`, and for a
/// MaterialX closure tree the 1D closure choice `Dim::Lobe` (drawn only then).
#[inline]
pub(crate) fn sample_bsdf(
    bsdf: &crate::material::Bsdf,
    st: &crate::sampler::SampleStream,
    bounce: u32,
) -> Option<crate::material::BsdfSample> {
    BsdfPoint::draw(bsdf, st, bounce).sample(bsdf)
}

/// The random numbers of [`sample_bsdf`], drawn apart from the sample: a path draws its
/// vertex's before the vertex's light samples, so that hashing them (a chain of some forty
/// integer multiplications) runs while the shadow rays are traced instead of before the
/// continuation's ray (render time −6 % on the Cornell box, −4 % on clutter_one; the same
/// numbers, so the same bits).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BsdfPoint {
    u: [f64; 2],
    lobe: f64,
}

impl BsdfPoint {
    /// The numbers of vertex `bounce`'s BSDF sample of `bsdf` in `st`.
    #[inline(always)]
    pub(crate) fn draw(
        bsdf: &crate::material::Bsdf,
        st: &crate::sampler::SampleStream,
        bounce: u32,
    ) -> BsdfPoint {
        use crate::sampler::Dim;
        let lobe = if bsdf.chooses_lobes() {
            st.get1(Dim::Lobe { bounce })
        } else {
            0.0
        };
        BsdfPoint {
            u: st.get2(Dim::Bsdf { bounce }),
            lobe,
        }
    }

    /// The BSDF sample of `bsdf` (the one [`BsdfPoint::draw`] was given) at these numbers.
    #[inline(always)]
    pub(crate) fn sample(
        &self,
        bsdf: &crate::material::Bsdf,
    ) -> Option<crate::material::BsdfSample> {
        bsdf.sample(self.u, self.lobe)
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

/// Generates [`IntegratorKind`] (the names), [`AnyIntegrator`] (the closed set) and its
/// dispatch from the registration list.
macro_rules! integrators {
    ($( $(#[doc = $doc:literal])* $kind:ident = $name:literal => $ty:ident, )+) => {
        /// The light transport of a render (`--integrator`; one per registered integrator).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum IntegratorKind {
            $( $(#[doc = $doc])* $kind, )+
        }

        impl IntegratorKind {
            /// Every registered integrator, in registration order.
            pub const ALL: &'static [IntegratorKind] = &[$(IntegratorKind::$kind),+];

            /// Its `--integrator` name.
            pub fn name(self) -> &'static str {
                match self {
                    $( IntegratorKind::$kind => $name, )+
                }
            }

            /// The integrator named `name` ([`IntegratorKind::name`]).
            pub fn from_name(name: &str) -> Option<IntegratorKind> {
                IntegratorKind::ALL.iter().copied().find(|k| k.name() == name)
            }
        }

        /// Any registered integrator, ready to render.
        pub enum AnyIntegrator<'a> {
            $( $(#[doc = $doc])* $kind($ty<'a>), )+
        }

        impl<'a> AnyIntegrator<'a> {
            /// The integrator of `kind` over `setup`.
            pub fn new(kind: IntegratorKind, setup: &Setup<'a>) -> AnyIntegrator<'a> {
                match kind {
                    $( IntegratorKind::$kind => AnyIntegrator::$kind($ty::new(setup)), )+
                }
            }
        }

        impl Integrator for AnyIntegrator<'_> {
            #[inline]
            fn li(&self, ray: &CameraRay, st: &SampleStream, ctx: &mut Ctx) -> (DVec3, f64) {
                match self {
                    $( AnyIntegrator::$kind(i) => i.li(ray, st, ctx), )+
                }
            }

            fn splats(&self) -> bool {
                match self {
                    $( AnyIntegrator::$kind(i) => i.splats(), )+
                }
            }

            fn splits(&self) -> u32 {
                match self {
                    $( AnyIntegrator::$kind(i) => i.splits(), )+
                }
            }

            fn warnings(&self) -> Vec<String> {
                match self {
                    $( AnyIntegrator::$kind(i) => i.warnings(), )+
                }
            }
        }
    };
}

// The registration list: one line per integrator.
integrators! {
    /// Direct lighting (what the reference renderer computes).
    Direct = "direct" => DirectIntegrator,
    /// Path tracing: next-event estimation at every vertex of a BSDF-sampled path.
    Path = "path" => PathIntegrator,
    /// Light tracing: particles from the lights, splatted to the camera at every vertex.
    Light = "light" => LightTracer,
}

impl IntegratorKind {
    /// The default of a conformance profile: path tracing in `Spec`, direct lighting in
    /// `HdEmbree` (the reference renderer lights surfaces directly).
    pub fn default_for(profile: lux_math::Profile) -> IntegratorKind {
        match profile {
            lux_math::Profile::HdEmbree => IntegratorKind::Direct,
            _ => IntegratorKind::Path,
        }
    }
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

    /// Every registered integrator answers to its name, and names are distinct.
    #[test]
    fn kinds_round_trip_their_names() {
        for &k in IntegratorKind::ALL {
            assert_eq!(IntegratorKind::from_name(k.name()), Some(k));
        }
        assert_eq!(IntegratorKind::from_name("bdpt"), None);
        assert_eq!(IntegratorKind::ALL.len(), 3);
    }
}
