//! Render settings: what a render depends on besides the scene ([`RenderOptions`], from the
//! CLI or an API caller), resolved against the stage's `UsdRenderSettings` and its first
//! `UsdRenderProduct` into the camera, the resolution, the pixel aspect ratio, the data window
//! and the crop ([`resolve`]).
//!
//! Precedence: an option given explicitly, then the product's value, then the settings' value,
//! then usdrecord's default (the render camera or the first camera; 960 pixels wide at the
//! camera's aspect).

use crate::RenderError;
use crate::camera::Camera;
use crate::conformance::ResolvedProfile;
use crate::light::LightSelection;
use glam::DVec4;
use lux_usd::Scene;

/// Largest image side accepted (pixels).
pub const MAX_RESOLUTION: u32 = 65_536;
pub use crate::adaptive::{AdaptiveSampling, MAX_ADAPTIVE_FACTOR, NoiseMeasure};
pub use crate::integrator::{IntegratorKind, SamplingMode};
pub use crate::material::SurfaceModel;
pub use crate::sampler::MAX_SPP;
pub use crate::visibility::VisibilityMode;

/// Largest path depth ([`RenderOptions::max_depth`]; the sample dimensions name 128 bounces).
pub const MAX_DEPTH: u32 = 128;

/// Paths continued from each camera sample's first vertex by default
/// ([`RenderOptions::path_splits`]): time × variance 9–23 % lower than with one on the
/// Cornell box, three clutter scenes and the StandardShaderBall; 4 within 6 % of 2 either way,
/// 8 worse than 1 on a clutter scene (BENCHMARKS.md, issue 39).
pub const PATH_SPLITS: u32 = 2;

/// Largest [`RenderOptions::path_splits`].
pub const MAX_PATH_SPLITS: u32 = 64;

/// Shadow rays a path vertex past the camera's shares among its light samples
/// ([`RenderOptions::shadow_rays`]): one. With several lights, one shadow ray resampled from
/// their unshadowed contributions is cheaper for its noise than one per light (time ×
/// variance on clutter_mix seeds 1 / 2 −17 / −10 %, on the StandardShaderBall's five
/// RectLights −8 %; two rays gained less; at the camera's vertex, where the light's noise is
/// not yet drowned in the path's, it lost: BENCHMARKS.md, issue 39).
pub const VERTEX_SHADOW_RAYS: u32 = 1;

/// Largest number of light samples per shading point ([`RenderOptions::light_samples`]).
pub const MAX_LIGHT_SAMPLES: u32 = 64;

/// Everything a render depends on besides the scene.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Samples per pixel (≥ 1); with adaptive sampling, the least a pixel takes.
    pub spp: u32,
    /// Output resolution; `None` = the RenderSettings' (or its product's) resolution.
    pub resolution: Option<[u32; 2]>,
    /// Only render pixels `[x0, y0, x1, y1)` (y from the top); others stay 0 with alpha 0.
    pub crop: Option<[u32; 4]>,
    /// Camera prim path; `None` = the RenderSettings' camera, else the first camera.
    pub camera: Option<String>,
    /// The conformance profile (resolved by [`crate::conformance::resolve_profile`]).
    pub profile: ResolvedProfile,
    /// Sampling techniques.
    pub sampling: SamplingMode,
    /// Light selection strategy.
    pub selection: LightSelection,
    /// Light transport: direct lighting or path tracing.
    pub integrator: IntegratorKind,
    /// Most surface vertices a path lights (1 to [`MAX_DEPTH`]; `path` only).
    pub max_depth: u32,
    /// Paths continued from each camera sample's first vertex (1 to [`MAX_PATH_SPLITS`];
    /// `path` only): they share its camera ray, first hit and direct light, which a camera
    /// sample of its own would trace again. Default [`PATH_SPLITS`].
    pub path_splits: u32,
    /// How surfaces scatter: the UsdPreviewSurface or Lambertian `diffuseColor`.
    pub surfaces: SurfaceModel,
    /// Light samples per light (or per light choice) at each shading point (1 to
    /// [`MAX_LIGHT_SAMPLES`]), stratified over the pixel with the camera samples; `None`:
    /// [`RenderOptions::light_samples`] chooses.
    pub light_samples: Option<u32>,
    /// Light samples per light in shadowed pixels, as a factor on
    /// [`RenderOptions::light_samples`] (1 to [`MAX_LIGHT_SAMPLES`]; 1 turns the pass off): from
    /// 8 spp, a pilot camera sample per pixel (not part of the estimate) traces shadow rays, and
    /// a pixel where one was blocked takes this many times the light samples per light in all
    /// its samples ([`crate::adaptive::PenumbraPilot`]).
    pub penumbra_samples: u32,
    /// Shadow rays each path vertex past the camera's traces for its light samples (0 to
    /// [`MAX_LIGHT_SAMPLES`]; `path` only): when it has more light samples with opaque plain
    /// shadows than this, this many are picked by systematic resampling in proportion to
    /// their unshadowed contributions and weighted by the inverse of their share (unbiased;
    /// exact where every pick is unblocked); 0: a shadow ray for every light sample. Default
    /// [`VERTEX_SHADOW_RAYS`].
    pub shadow_rays: u32,
    /// Sample shaped rect and cylinder lights only where their emission cone reaches the
    /// receiver (default); `false` for A/B measurements ([`crate::light::LightOptions`]).
    pub cone_clipping: bool,
    /// How what a point sees of a light is found (`--visibility`): [`VisibilityMode::Exact`]
    /// (default) adds closed forms where nothing can block a rect, disk or sphere light of
    /// uniform radiance seen from a Lambertian point, exact penumbrae behind a few triangles,
    /// the shadow BVH of card outlines and per-tile short lists (`visibility/`);
    /// [`VisibilityMode::Rays`] is the plain renderer, shadow rays through the scene's BVH,
    /// for A/B measurements and to compare instanced stages with their flattened twins sample
    /// for sample.
    pub visibility: VisibilityMode,
    /// Adaptive sampling: after its `spp` samples, a pixel whose neighbourhood is noisy (or,
    /// by the perceived measure, crosses an edge) takes more ([`AdaptiveSampling`];
    /// [`AdaptiveSampling::OFF`]: every pixel takes `spp`); `None`: [`RenderOptions::adaptive`]
    /// chooses by integrator.
    pub adaptive: Option<AdaptiveSampling>,
    /// Subdivision surfaces' refinement level (`lux_usd::subdiv`): `None` follows the
    /// profile — `spec` refines each surface by its size on screen
    /// ([`lux_usd::subdiv::screen_level`], at most [`SCREEN_LEVEL_CAP`]), `hdembree` keeps the
    /// cages' polygons as hdEmbree draws them at usdrecord's default complexity (its
    /// `mesh.cpp`: "If the refine level is 0, triangulate instead of subdividing");
    /// `Some(n)` refines every surface at level `n` (0: the cages' polygons).
    pub subdiv_level: Option<u32>,
    /// Seed of every random number.
    pub seed: u64,
    /// An IES profile or texture that does not resolve or cannot be read is an error instead
    /// of a warning with a fallback (the light without it, the texture's `inputs:fallback`).
    pub strict: bool,
}

impl RenderOptions {
    /// 16 spp, the scene's resolution and camera, the profile's integrator (path in `spec`,
    /// direct in `hdembree`, depth 8) and surfaces (UsdPreviewSurface in `spec`, Lambertian in
    /// `hdembree`), lux sampling, seed 0.
    pub fn new(profile: ResolvedProfile) -> RenderOptions {
        let integrator = IntegratorKind::default_for(profile.profile);
        let surfaces = SurfaceModel::default_for(profile.profile);
        RenderOptions {
            spp: 16,
            resolution: None,
            crop: None,
            camera: None,
            profile,
            sampling: SamplingMode::Lux,
            selection: LightSelection::Auto,
            integrator,
            max_depth: 8,
            path_splits: PATH_SPLITS,
            surfaces,
            light_samples: None,
            penumbra_samples: 1,
            shadow_rays: VERTEX_SHADOW_RAYS,
            cone_clipping: true,
            visibility: VisibilityMode::Exact,
            adaptive: None,
            subdiv_level: None,
            seed: 0,
            strict: false,
        }
    }
}

/// The deepest level the `spec` profile's screen rule refines a subdivision surface to
/// ([`RenderOptions::subdiv_level`]): `2^6` segments along a cage edge.
pub const SCREEN_LEVEL_CAP: u32 = 6;

impl RenderOptions {
    /// How subdivision surfaces are refined for `camera` at an image `width` pixels wide
    /// ([`RenderOptions::subdiv_level`]).
    pub fn level_rule<'c>(
        &self,
        camera: &'c lux_usd::Camera,
        width: u32,
    ) -> lux_usd::subdiv::LevelRule<'c> {
        use lux_usd::subdiv::LevelRule;
        match (self.subdiv_level, self.profile.profile) {
            (Some(n), _) => LevelRule::Fixed(n),
            (None, lux_math::Profile::HdEmbree) => LevelRule::Fixed(0),
            (None, lux_math::Profile::Spec) => LevelRule::Screen {
                camera,
                width,
                max_level: SCREEN_LEVEL_CAP,
            },
        }
    }
}

impl RenderOptions {
    /// Adaptive sampling: the asked one, else, with lux sampling, [`AdaptiveSampling::DEFAULT`]
    /// (the perceived noise measure) for the direct integrator and [`AdaptiveSampling::PATH`]
    /// (the linear one) for the path tracer, and [`AdaptiveSampling::OFF`] otherwise (the
    /// reference estimator is for A/B comparisons at a fixed sample count; the light tracer
    /// takes `spp` particles a pixel whatever is asked).
    ///
    /// Why the path takes another measure: its noise is everywhere, so by the perceived one
    /// nearly every pixel of a path-traced Cornell box took the 16 × cap (a uniform multiplier
    /// rather than an allocation), while by the linear one the samples go where most of the
    /// image's squared error is (on the clutter scenes, a tenth of the pixels holds 90 % of it).
    pub fn adaptive(&self) -> AdaptiveSampling {
        self.adaptive
            .unwrap_or(match (self.sampling, self.integrator) {
                (SamplingMode::Lux, IntegratorKind::Direct) => AdaptiveSampling::DEFAULT,
                (SamplingMode::Lux, IntegratorKind::Path) => AdaptiveSampling::PATH,
                _ => AdaptiveSampling::OFF,
            })
    }
}

/// Light samples per shading point when none are asked for, with lux sampling and the
/// direct integrator, where every light is sampled ([`RenderOptions::light_samples_per_light`]).
pub const AUTO_LIGHT_SAMPLES: u32 = 4;

/// Light choices per shading point when none are asked for, with lux sampling and the direct
/// integrator, where a selector (the light BVH of a scene of many lights) chooses them
/// ([`RenderOptions::light_samples_per_light`]`(None)`).
pub const AUTO_LIGHT_CHOICES: u32 = 16;

impl RenderOptions {
    /// Light samples per light (or light choice) at each shading point of a scene with one
    /// light: [`RenderOptions::light_samples_per_light`]`(Some(1))`.
    pub fn light_samples(&self) -> u32 {
        self.light_samples_per_light(Some(1))
    }

    /// Light samples per light at each shading point where `sampled` lights are each sampled,
    /// or light choices where a selector chooses them (`None`): the asked number, else for lux
    /// sampling with the direct integrator ⌈[`AUTO_LIGHT_SAMPLES`] / sampled⌉ — about
    /// [`AUTO_LIGHT_SAMPLES`] light samples a point in all — or [`AUTO_LIGHT_CHOICES`], and 1
    /// otherwise.
    ///
    /// Why 4: a light sample (its point and shadow ray) costs 0.28–0.42 of a whole camera
    /// sample (callgrind, luxtest disk/sphere/cylinder frame 1), and where shadows fall its
    /// noise dominates the pixel's; 4 per camera sample reached a given error 1.45–8 × sooner
    /// than 1 on the luxtest frames, 8 was slower again (BENCHMARKS.md). Several lights share
    /// the 4: each sample of each light already spreads the camera sample's cost, and four
    /// lights of four samples each made the cheapest render of the four-light clutter scene
    /// twice as expensive for no gain (BENCHMARKS.md, issue 39). Why 16 choices: among many
    /// lights a few choices a point leave most of the lights that matter there unsampled, and
    /// the choices share the camera sample and the top of the light BVH; on the 64-light
    /// clutter scenes 16 reached a given error about twice as soon as 4 (BENCHMARKS.md,
    /// issue 39). A path takes 1 at each vertex (its indirect light, not the light samples, is
    /// the noise there), and the reference estimator 1 (hdEmbree's: one sample per light per
    /// camera sample).
    pub fn light_samples_per_light(&self, sampled: Option<usize>) -> u32 {
        self.light_samples.unwrap_or(
            if self.sampling == SamplingMode::Lux && self.integrator == IntegratorKind::Direct {
                match sampled {
                    Some(n) => AUTO_LIGHT_SAMPLES.div_ceil(n.max(1) as u32),
                    None => AUTO_LIGHT_CHOICES,
                }
            } else {
                1
            },
        )
    }
}

/// The settings of one render, resolved.
#[derive(Clone, Debug)]
pub struct Resolved {
    /// The camera's ray generator at the output resolution.
    pub camera: Camera,
    /// The pixels to render: crop ∩ data window, `[x0, y0, x1, y1)`.
    pub window: [u32; 4],
    /// The camera's UsdGeomCamera linear exposure scale (1 with the schema defaults).
    pub exposure_scale: f64,
}

/// The USD camera `options` render through: the one at `options.camera`, else the scene's
/// render camera.
fn usd_camera<'s>(
    scene: &'s Scene,
    options: &RenderOptions,
) -> Result<&'s lux_usd::Camera, RenderError> {
    match &options.camera {
        Some(p) => scene.cameras.iter().find(|c| &c.path == p).ok_or_else(|| {
            RenderError::NoCamera(format!("no camera at <{p}> in {}", scene.source.display()))
        }),
        None => scene.render_camera().ok_or_else(|| {
            RenderError::NoCamera(format!("{} has no Camera prim", scene.source.display()))
        }),
    }
}

/// Refines `scene`'s subdivision surfaces as a render with `options` draws them
/// ([`RenderOptions::level_rule`] for its camera and image width; `Scene::refine_subdivision`),
/// in place: [`crate::render::Renderer::new`] does it on a copy of a scene that still holds
/// cages, so a caller that owns its scene saves the copy by refining first. Returns the
/// surfaces refined and their levels; the scene's warnings say what could not be refined as
/// authored.
pub fn refine_subdivision(
    scene: &mut Scene,
    options: &RenderOptions,
) -> Result<Vec<lux_usd::subdiv::Refinement>, RenderError> {
    if !scene.meshes.iter().any(|m| m.subdivision.is_some()) {
        return Ok(Vec::new());
    }
    let camera = usd_camera(scene, options)?.clone();
    let width = options
        .resolution
        .unwrap_or_else(|| scene.default_resolution(&camera))[0];
    Ok(scene.refine_subdivision(&options.level_rule(&camera, width)))
}

/// Resolves `options` against `scene`: the camera (by path, else the render camera), the
/// resolution, pixel aspect ratio and data window (product, then settings), and the crop.
/// Invalid sample counts, resolutions, crops and cameras are errors naming the value.
pub fn resolve(scene: &Scene, options: &RenderOptions) -> Result<Resolved, RenderError> {
    for (what, v, max) in [
        ("samples per pixel", options.spp, MAX_SPP),
        ("light samples", options.light_samples(), MAX_LIGHT_SAMPLES),
        ("path splits", options.path_splits, MAX_PATH_SPLITS),
        (
            "penumbra samples",
            options.penumbra_samples,
            MAX_LIGHT_SAMPLES,
        ),
        ("max depth", options.max_depth, MAX_DEPTH),
    ] {
        if v == 0 || v > max {
            return Err(RenderError::Settings(format!(
                "{what} {v}: expected 1 to {max}"
            )));
        }
    }
    if options.shadow_rays > MAX_LIGHT_SAMPLES {
        return Err(RenderError::Settings(format!(
            "shadow rays {}: expected 0 to {MAX_LIGHT_SAMPLES}",
            options.shadow_rays
        )));
    }
    {
        let a = options.adaptive();
        if !(a.threshold.is_finite() && a.threshold > 0.0) {
            return Err(RenderError::Settings(format!(
                "adaptive threshold {}: expected a finite number > 0",
                a.threshold
            )));
        }
        if a.max_factor == 0 || a.max_factor > MAX_ADAPTIVE_FACTOR {
            return Err(RenderError::Settings(format!(
                "adaptive max factor {}: expected 1 to {MAX_ADAPTIVE_FACTOR}",
                a.max_factor
            )));
        }
        if a.max_splits == 0 || a.max_splits > MAX_PATH_SPLITS {
            return Err(RenderError::Settings(format!(
                "adaptive splits {}: expected 1 to {MAX_PATH_SPLITS}",
                a.max_splits
            )));
        }
    }
    if let Some(l) = options.subdiv_level
        && l > lux_usd::subdiv::MAX_LEVEL
    {
        return Err(RenderError::Settings(format!(
            "subdivision level {l}: expected 0 to {}",
            lux_usd::subdiv::MAX_LEVEL
        )));
    }
    let camera = usd_camera(scene, options)?;
    let settings = scene.render_settings.first();
    let product = settings.and_then(|s| s.products.first());
    let resolution = options
        .resolution
        .unwrap_or_else(|| scene.default_resolution(camera));
    if resolution[0] == 0
        || resolution[1] == 0
        || resolution[0] > MAX_RESOLUTION
        || resolution[1] > MAX_RESOLUTION
    {
        return Err(RenderError::Settings(format!(
            "resolution {}×{}: expected 1 to {MAX_RESOLUTION} pixels per side",
            resolution[0], resolution[1]
        )));
    }
    let par = product
        .and_then(|p| p.base.pixel_aspect_ratio)
        .or_else(|| settings.map(|s| s.pixel_aspect_ratio()))
        .unwrap_or(1.0);
    let ndc = product
        .and_then(|p| p.base.data_window_ndc)
        .or_else(|| settings.map(|s| s.data_window_ndc()))
        .unwrap_or(DVec4::new(0.0, 0.0, 1.0, 1.0));
    let view = Camera::new(camera, resolution, par, ndc)?;
    let mut window = view.pixel_window;
    if let Some([x0, y0, x1, y1]) = options.crop {
        if x0 >= x1 || y0 >= y1 || x1 > resolution[0] || y1 > resolution[1] {
            return Err(RenderError::Settings(format!(
                "crop {x0},{y0},{x1},{y1}: expected x0 < x1 ≤ {}, y0 < y1 ≤ {}",
                resolution[0], resolution[1]
            )));
        }
        window = [
            window[0].max(x0),
            window[1].max(y0),
            window[2].min(x1),
            window[3].min(y1),
        ];
        window[2] = window[2].max(window[0]);
        window[3] = window[3].max(window[1]);
    }
    Ok(Resolved {
        camera: view,
        window,
        exposure_scale: camera.linear_exposure_scale(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use lux_math::Profile;

    /// Automatic light samples: about 4 a point in all, shared by the lights sampled there, or
    /// 16 choices where a selector chooses; an asked number, a path or the reference
    /// estimator as documented.
    #[test]
    fn automatic_light_samples_share_four_between_the_lights_or_choose_sixteen() {
        let mut o = RenderOptions::new(ResolvedProfile {
            profile: Profile::Spec,
            source: crate::conformance::ProfileSource::CommandLine,
        });
        o.integrator = IntegratorKind::Direct;
        let per = |o: &RenderOptions| {
            [Some(1), Some(2), Some(3), Some(4), Some(8), Some(64), None]
                .map(|n| o.light_samples_per_light(n))
        };
        assert_eq!(per(&o), [4, 2, 2, 1, 1, 1, 16]);
        assert_eq!(o.light_samples(), AUTO_LIGHT_SAMPLES);
        o.light_samples = Some(3);
        assert_eq!(per(&o), [3; 7]);
        o.light_samples = None;
        o.integrator = IntegratorKind::Path;
        assert_eq!(per(&o), [1; 7]);
        o.integrator = IntegratorKind::Direct;
        o.sampling = SamplingMode::Reference;
        assert_eq!(per(&o), [1; 7]);
    }
}
