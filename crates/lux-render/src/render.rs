//! The renderer: prepare the scene (settings, lights, materials, geometry), then let the film
//! render it with the integrator.

use crate::RenderError;
use crate::camera::Camera;
use crate::film::{Counters, Film};
use crate::geometry::Geometry;
use crate::image_io::ImageRgba;
use crate::integrator::{DirectIntegrator, Integrator, PathIntegrator, World};
use crate::light::{LightOptions, LightSet};
use crate::material::Materials;
use crate::settings::{IntegratorKind, SamplingMode, resolve};
use glam::DVec4;
use lux_math::Profile;
use lux_usd::Scene;

pub use crate::film::{RenderStats, TILE};
pub use crate::settings::{MAX_RESOLUTION, MAX_SPP, RenderOptions};

/// A scene prepared for rendering: BVH, lights, materials and camera.
pub struct Renderer<'s> {
    scene: &'s Scene,
    geometry: Geometry,
    lights: LightSet,
    materials: Materials,
    camera: Camera,
    film: Film,
    options: RenderOptions,
}

impl<'s> Renderer<'s> {
    /// Prepares `scene` for rendering with `options`.
    pub fn new(scene: &'s Scene, options: RenderOptions) -> Result<Renderer<'s>, RenderError> {
        let resolved = resolve(scene, &options)?;
        let lights = LightSet::new(
            scene,
            LightOptions {
                profile: options.profile.profile,
                selection: options.selection,
                strict: options.strict,
                cone_clipping: options.cone_clipping,
            },
        )?;
        let materials = Materials::with_policy(scene, options.strict, options.surfaces)?;
        let geometry = Geometry::with_lights(scene, &lights.lights);
        let film = Film {
            width: resolved.camera.width,
            height: resolved.camera.height,
            window: resolved.window,
            frame_rows: [resolved.window[1], resolved.window[3]],
            spp: options.spp,
            adaptive: options.adaptive(),
            seed: options.seed,
            exposure_scale: resolved.exposure_scale,
            penumbra_samples: options.penumbra_samples,
        };
        Ok(Renderer {
            scene,
            geometry,
            lights,
            materials,
            camera: resolved.camera,
            film,
            options,
        })
    }

    /// The prepared lights (with the warnings met while preparing them).
    pub fn lights(&self) -> &LightSet {
        &self.lights
    }

    /// Everything the render set-up replaced or left out: lights that cannot emit, IES profiles
    /// and textures that could not be read (each named with the light or material using it).
    pub fn warnings(&self) -> impl Iterator<Item = &String> {
        self.lights.warnings.iter().chain(&self.materials.warnings)
    }

    /// Output image size.
    pub fn resolution(&self) -> [u32; 2] {
        [self.film.width, self.film.height]
    }

    /// The pixels that are rendered, `[x0, y0, x1, y1)`.
    pub fn window(&self) -> [u32; 4] {
        self.film.window
    }

    /// Renders only rows `y0..y1` of the window (a band of the frame, for splitting it over
    /// processes); pixels keep the seeds of the whole frame, so a band is bit-identical to the
    /// same rows of a full render. An empty intersection renders nothing.
    pub fn restrict_rows(&mut self, [y0, y1]: [u32; 2]) {
        let w = &mut self.film.window;
        w[1] = w[1].max(y0);
        w[3] = w[3].min(y1).max(w[1]);
    }

    /// The units of [`Renderer::render`]'s progress: every pixel of the window once per pass
    /// (two with adaptive sampling: first samples, then extra samples).
    pub fn progress_total(&self) -> u64 {
        let [x0, y0, x1, y1] = self.film.window;
        (x1 - x0) as u64 * (y1 - y0) as u64 * self.film.passes() as u64
    }

    /// Number of BVH triangles (each instanced prototype's once).
    pub fn triangle_count(&self) -> usize {
        self.geometry.triangle_count()
    }

    /// The scene's prepared geometry (BVHs, instances, world bounds).
    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    /// The conformance profile in use.
    pub fn profile(&self) -> Profile {
        self.options.profile.profile
    }

    /// The integrator of the options' sampling mode over the prepared scene.
    pub fn integrator(&self) -> Integrator<'_> {
        let world = World {
            scene: self.scene,
            geometry: &self.geometry,
            lights: &self.lights,
            materials: &self.materials,
            transparent: self.materials.any_transparent(),
            textured_emission: self.materials.any_textured_emission(),
        };
        let direct =
            DirectIntegrator::new(world, self.options.sampling, self.options.light_samples())
                .with_closed_forms(self.options.closed_forms);
        // Path tracing builds on lux sampling's MIS; the reference estimator is direct only.
        match self.options.integrator {
            IntegratorKind::Path if self.options.sampling == SamplingMode::Lux => {
                Integrator::Path(PathIntegrator::new(direct, self.options.max_depth))
            }
            _ => Integrator::Direct(direct),
        }
    }

    /// Renders the image. `progress` is called (from worker threads) with the number of
    /// pixels finished by each completed tile of each pass (summing to
    /// [`Renderer::progress_total`]).
    pub fn render(&self, progress: &(dyn Fn(u64) + Sync)) -> (ImageRgba, RenderStats) {
        self.film.render(&self.camera, &self.integrator(), progress)
    }

    /// The mean of the pixel's `spp` samples: RGB radiance and alpha (coverage by geometry or a
    /// visible light). Without adaptive sampling's extra samples: the estimator a pixel starts
    /// from, whose variance [`Renderer::pixel_moments`] gives.
    pub fn pixel_value(&self, x: u32, y: u32) -> DVec4 {
        let integrator = self.integrator();
        self.film.pixel(
            &self.camera,
            &integrator,
            x,
            y,
            &mut Counters::default(),
            &mut |_| {},
        )
    }

    /// The pixel's sample moments: the mean (RGB, alpha) and the mean of the squared Rec.709
    /// luminance of the samples, from which a caller estimates the variance of the pixel
    /// estimate (`(E[Y²] − E[Y]²) / (spp − 1)`), as the conformance tests do.
    pub fn pixel_moments(&self, x: u32, y: u32) -> (DVec4, f64) {
        let mut y2 = 0.0;
        let integrator = self.integrator();
        let mean = self.film.pixel(
            &self.camera,
            &integrator,
            x,
            y,
            &mut Counters::default(),
            &mut |rgb| {
                let l = lux_math::luminance(rgb);
                y2 += l * l;
            },
        );
        (mean, y2 / self.options.spp as f64)
    }
}
