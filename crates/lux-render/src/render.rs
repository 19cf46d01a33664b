//! The renderer: prepare the scene (settings, lights, materials, geometry, visibility), then
//! render it tile by tile (`tiles.rs`) with the integrator of the options.

use crate::RenderError;
use crate::adaptive::PenumbraPilot;
use crate::camera::Camera;
use crate::geometry::Geometry;
use crate::image_io::ImageRgba;
use crate::integrator::{AnyIntegrator, Ctx, Integrator, IntegratorKind, Setup};
use crate::light::{LightOptions, LightSet};
use crate::material::{Materials, TextureDecoding};
use crate::settings::resolve;
use crate::tiles::{Frame, Scene as TileScene};
use crate::visibility::Visibility;
use crate::world::World;
use glam::DVec4;
use lux_math::Profile;
use lux_usd::Scene;

pub use crate::settings::{MAX_RESOLUTION, MAX_SPP, RenderOptions};
pub use crate::stats::RenderStats;
pub use crate::tiles::TILE;

/// A scene prepared for rendering: BVH, lights, materials and camera.
pub struct Renderer<'s> {
    /// The scene as drawn: `scene` itself, or a copy with its subdivision surfaces refined.
    scene: std::borrow::Cow<'s, Scene>,
    /// What refining the subdivision surfaces of the copy replaced or left out.
    refine_warnings: Vec<String>,
    /// What the integrator cannot do as the scene says.
    integrator_warnings: Vec<String>,
    geometry: Geometry,
    /// How shadow rays and camera rays are answered (`RenderOptions::visibility`).
    visibility: Visibility,
    lights: LightSet,
    materials: Materials,
    camera: Camera,
    frame: Frame,
    options: RenderOptions,
}

impl<'s> Renderer<'s> {
    /// Prepares `scene` for rendering with `options`.
    ///
    /// Subdivision surfaces still holding their cages are refined on a copy of the scene
    /// ([`crate::settings::refine_subdivision`], which a caller owning its scene can call
    /// first to save the copy).
    pub fn new(scene: &'s Scene, options: RenderOptions) -> Result<Renderer<'s>, RenderError> {
        let resolved = resolve(scene, &options)?;
        let mut refine_warnings = Vec::new();
        let scene = if scene.meshes.iter().any(|m| m.subdivision.is_some()) {
            let mut copy = scene.clone();
            let before = copy.warnings.len();
            crate::settings::refine_subdivision(&mut copy, &options)?;
            refine_warnings = copy.warnings[before..]
                .iter()
                .map(|w| w.to_string())
                .collect();
            std::borrow::Cow::Owned(copy)
        } else {
            std::borrow::Cow::Borrowed(scene)
        };
        let scene_ref: &Scene = &scene;
        let lights = LightSet::new(
            scene_ref,
            LightOptions {
                profile: options.profile.profile,
                selection: options.selection,
                strict: options.strict,
                cone_clipping: options.cone_clipping,
            },
        )?;
        // A direct-lit frame shades only what the camera sees: its textures are decoded
        // when first read (a textured wall behind the camera never is).
        let decoding = match options.integrator {
            IntegratorKind::Direct => TextureDecoding::OnFirstUse,
            IntegratorKind::Path | IntegratorKind::Light => TextureDecoding::UpFront,
        };
        let materials = Materials::prepare(scene_ref, options.strict, options.surfaces, decoding)?;
        let geometry = Geometry::new(scene_ref);
        let visibility = Visibility::new(options.visibility, scene_ref, &geometry);
        let frame = Frame {
            width: resolved.camera.width,
            height: resolved.camera.height,
            window: resolved.window,
            frame_rows: [resolved.window[1], resolved.window[3]],
            spp: options.spp,
            adaptive: options.adaptive(),
            seed: options.seed,
            exposure_scale: resolved.exposure_scale,
            pilot: PenumbraPilot {
                samples: options.penumbra_samples,
            },
        };
        let mut r = Renderer {
            scene,
            refine_warnings,
            integrator_warnings: Vec::new(),
            geometry,
            visibility,
            lights,
            materials,
            camera: resolved.camera,
            frame,
            options,
        };
        r.integrator_warnings = r.integrator().warnings();
        Ok(r)
    }

    /// The prepared lights (with the warnings met while preparing them).
    pub fn lights(&self) -> &LightSet {
        &self.lights
    }

    /// Everything the render set-up replaced or left out: lights that cannot emit, IES profiles
    /// and textures that could not be read (each named with the light or material using it).
    pub fn warnings(&self) -> impl Iterator<Item = &String> {
        self.refine_warnings
            .iter()
            .chain(&self.lights.warnings)
            .chain(&self.materials.warnings)
            .chain(&self.integrator_warnings)
    }

    /// What a render replaced that only it could find: texture files decoded on first use
    /// whose data turned out unreadable (each use took the fallback a file failing up front
    /// gets, in the words of [`Renderer::warnings`]). Empty before a render.
    pub fn late_warnings(&self) -> impl Iterator<Item = String> + '_ {
        self.materials.late_warnings()
    }

    /// Output image size.
    pub fn resolution(&self) -> [u32; 2] {
        [self.frame.width, self.frame.height]
    }

    /// The pixels that are rendered, `[x0, y0, x1, y1)`.
    pub fn window(&self) -> [u32; 4] {
        self.frame.window
    }

    /// Renders only rows `y0..y1` of the window (a band of the frame, for splitting it over
    /// processes); pixels keep the seeds of the whole frame, so a band is bit-identical to the
    /// same rows of a full render. An empty intersection renders nothing. (A splatting
    /// integrator, the light tracer, traces the whole frame's particles for each band and
    /// keeps the band's rows: the same bits, none of the time saved.)
    pub fn restrict_rows(&mut self, [y0, y1]: [u32; 2]) {
        let w = &mut self.frame.window;
        w[1] = w[1].max(y0);
        w[3] = w[3].min(y1).max(w[1]);
    }

    /// The units of [`Renderer::render`]'s progress: every pixel of the window once per pass
    /// (two with adaptive sampling: first samples, then extra samples).
    pub fn progress_total(&self) -> u64 {
        let [x0, y0, x1, y1] = self.frame.window;
        (x1 - x0) as u64 * (y1 - y0) as u64 * self.frame.passes() as u64
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

    /// The prepared scene an integrator reads.
    pub fn world(&self) -> World<'_> {
        World {
            scene: &self.scene,
            geometry: &self.geometry,
            lights: &self.lights,
            materials: &self.materials,
            transparent: self.materials.any_transparent(),
            textured_emission: self.materials.any_textured_emission(),
        }
    }

    /// How shadow rays and camera rays are answered (`RenderOptions::visibility`).
    pub fn visibility(&self) -> &Visibility {
        &self.visibility
    }

    /// The integrator of the options over the prepared scene.
    pub fn integrator(&self) -> AnyIntegrator<'_> {
        let setup = Setup {
            world: self.world(),
            vis: &self.visibility,
            camera: &self.camera,
            sampling: self.options.sampling,
            light_samples: {
                // (every light sampled at each point, unless a selector chooses them)
                let lights = &self.lights;
                let sampled = match lights.selector {
                    Some(_) => None,
                    None => Some(lights.lights.len()),
                };
                self.options.light_samples_per_light(sampled)
            },
            max_depth: self.options.max_depth,
            splits: self.options.path_splits,
            shadow_rays: self.options.shadow_rays,
        };
        AnyIntegrator::new(self.options.integrator, &setup)
    }

    /// Renders the image. `progress` is called (from worker threads) with the number of
    /// pixels finished by each completed tile of each pass (summing to
    /// [`Renderer::progress_total`]).
    pub fn render(&self, progress: &(dyn Fn(u64) + Sync)) -> (ImageRgba, RenderStats) {
        let integrator = self.integrator();
        self.frame.render(&self.tile_scene(&integrator), progress)
    }

    /// What the tile loop reads, with `integrator`.
    fn tile_scene<'a, I: Integrator>(&'a self, integrator: &'a I) -> TileScene<'a, I> {
        TileScene {
            camera: &self.camera,
            world: self.world(),
            vis: &self.visibility,
            integrator,
        }
    }

    /// The mean of the pixel's `spp` samples: RGB radiance and alpha (coverage by geometry or a
    /// visible light). Without adaptive sampling's extra samples (and without the splats of a
    /// light tracer): the estimator a pixel starts from, whose variance
    /// [`Renderer::pixel_moments`] gives.
    pub fn pixel_value(&self, x: u32, y: u32) -> DVec4 {
        let integrator = self.integrator();
        let scene = self.tile_scene(&integrator);
        self.frame
            .pixel(&scene, x, y, &mut Ctx::default(), &mut |_| {})
    }

    /// The pixel's sample moments: the mean (RGB, alpha) and the mean of the squared Rec.709
    /// luminance of the samples, from which a caller estimates the variance of the pixel
    /// estimate (`(E[Y²] − E[Y]²) / (spp − 1)`), as the conformance tests do.
    pub fn pixel_moments(&self, x: u32, y: u32) -> (DVec4, f64) {
        let mut y2 = 0.0;
        let integrator = self.integrator();
        let scene = self.tile_scene(&integrator);
        let mean = self
            .frame
            .pixel(&scene, x, y, &mut Ctx::default(), &mut |rgb| {
                let l = lux_math::luminance(rgb);
                y2 += l * l;
            });
        (mean, y2 / self.options.spp as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::conformance::{ProfileSource, ResolvedProfile};
    use crate::settings::AdaptiveSampling;
    use glam::{DMat4, DVec3};
    use lux_math::LightShape;
    use lux_usd::{Camera as UsdCamera, Light, Mesh};

    /// A 6 × 6 floor in the middle of the frame of a camera 30 above it looking down (the
    /// luxtest camera: about ±6.3 across at the floor), a camera-visible sphere light beside the
    /// floor on the right and one the camera does not see on the left.
    fn scene(visible: bool, dome: bool) -> Scene {
        let mut s = Scene::empty("code.usda");
        s.meshes.push(Mesh::new(
            "/Floor",
            vec![
                DVec3::new(-3.0, 0.0, -3.0),
                DVec3::new(-3.0, 0.0, 3.0),
                DVec3::new(3.0, 0.0, 3.0),
                DVec3::new(3.0, 0.0, -3.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        ));
        let mut c = UsdCamera::with_defaults(
            "/Camera",
            DMat4::from_cols_array(&[
                1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 30.0, 0.0, 1.0,
            ]),
        );
        c.focal_length = 0.5;
        c.horizontal_aperture = 0.20955;
        c.vertical_aperture = 0.20955;
        s.cameras.push(c);
        for (x, seen) in [(4.5, visible), (-4.5, false)] {
            let mut l = Light::with_defaults(
                format!("/L{x}"),
                LightShape::Sphere { radius: 0.6 },
                DMat4::from_translation(DVec3::new(x, 1.0, 0.0)),
            );
            l.visible_to_camera = seen;
            s.lights.push(l);
        }
        if dome {
            s.lights.push(Light::with_defaults(
                "/Dome",
                LightShape::Dome,
                DMat4::IDENTITY,
            ));
        }
        s
    }

    fn options(adaptive: AdaptiveSampling) -> RenderOptions {
        let mut o = RenderOptions::new(ResolvedProfile {
            profile: Profile::Spec,
            source: ProfileSource::CommandLine,
        });
        o.spp = 2;
        o.resolution = Some([96, 96]);
        o.adaptive = Some(adaptive);
        o
    }

    /// The tiles the visibility finds empty: (tiles, empty ones, ones without triangles that
    /// are not empty).
    fn empties(r: &Renderer) -> (u32, u32, u32) {
        let (mut tiles, mut empty, mut lit) = (0, 0, 0);
        for y in (0..96).step_by(TILE as usize) {
            for x in (0..96).step_by(TILE as usize) {
                let t = r
                    .visibility
                    .tile(&r.world(), &r.camera, [x, y, x + TILE, y + TILE]);
                tiles += 1;
                empty += t.is_empty() as u32;
                lit += (!t.is_empty() && t.listed() == Some(0)) as u32;
            }
        }
        (tiles, empty, lit)
    }

    /// A tile whose camera rays can meet nothing is taken as black with alpha 0 without
    /// tracing: the render (tile lists and empty tiles) gives the bits and the ray counts of
    /// every pixel's own estimate through the BVH (`Frame::pixel` without a tile hint), with and without
    /// adaptive sampling's extra samples (which reach into empty tiles beside the floor's
    /// edge); a tile holding only a camera-visible light, or any tile under a visible dome, is
    /// not empty.
    #[test]
    fn empty_tiles_render_what_their_rays_see() {
        for (visible, dome) in [(true, false), (false, false), (true, true)] {
            let s = scene(visible, dome);
            let r = Renderer::new(&s, options(AdaptiveSampling::OFF)).unwrap();
            let (tiles, empty, lit) = empties(&r);
            assert_eq!(tiles, 36);
            match (visible, dome) {
                // (the floor covers the middle 4 × 4 tiles or so; the visible light one or
                // two triangle-free tiles on the right)
                (true, false) => assert!(empty >= 12 && lit >= 1, "{empty} empty, {lit} lit"),
                (false, false) => assert!(empty >= 13 && lit == 0, "{empty} empty, {lit} lit"),
                _ => assert_eq!(empty, 0),
            }
            let (img, stats) = r.render(&|_| {});
            let integrator = r.integrator();
            let (scene, mut c) = (r.tile_scene(&integrator), Ctx::default());
            let mut seen = 0;
            for y in 0..96 {
                for x in 0..96 {
                    let v = r.frame.pixel(&scene, x, y, &mut c, &mut |_| {});
                    let want = v.to_array().map(|v| (v as f32).to_bits());
                    let got = img.pixels[(y * 96 + x) as usize].map(f32::to_bits);
                    assert_eq!(
                        got, want,
                        "pixel ({x}, {y}), visible {visible}, dome {dome}"
                    );
                    seen += (f32::from_bits(got[3]) > 0.0) as u32;
                }
            }
            // Camera rays are counted whether traced or not.
            assert_eq!(
                (stats.rays, stats.shadow_rays, stats.light_samples),
                (c.counters.rays, c.counters.shadow, c.counters.light_samples)
            );
            assert!(seen > 1500 && seen < 96 * 96 - 3000 || dome, "{seen}");
            // With adaptive sampling the image is the same wherever the tiles are empty.
            let ra = Renderer::new(&s, options(AdaptiveSampling::DEFAULT)).unwrap();
            let (a, stats) = ra.render(&|_| {});
            assert!(stats.adaptive_samples > 0);
            for y in 0..96u32 {
                for x in 0..96u32 {
                    let t = ra
                        .visibility
                        .tile(&ra.world(), &ra.camera, [x, y, x + 1, y + 1]);
                    if t.is_empty() {
                        assert_eq!(a.pixels[(y * 96 + x) as usize], [0.0; 4], "({x}, {y})");
                    }
                }
            }
        }
    }
}
