//! The scene's lights prepared for rendering: base emission (lux-math, or lux-spectral for
//! physical units), shaping (lux-shaping), samplers (lux-sample), textures, ray intersection
//! and the selection strategy.
//!
//! Every emitted radiance follows the spec pipeline (spec README §3):
//! `L(ω) = base · shapingFactor(ω_light) · texture(uv)`, with `base` the LightAPI emission
//! `intensity · 2^exposure · color · blackbody / sizeFactor` and `ω_light` the emission
//! direction (from the light towards the receiver) in the light's local space.
//!
//! Profile-dependent behaviour implemented here (see `lux_math::Profile`):
//! - RectLight texture on the lit path: [`Profile::Spec`] uses the schema orientation (image
//!   u runs along local −X, i.e. left-to-right for an observer facing the emitting −Z side;
//!   image top row at local +Y) on both the lit and the visible path; [`Profile::HdEmbree`]
//!   mirrors u on the lit path (u along +X), as the reference renderer does.
//! - Camera visibility: both profiles show the DomeLight as the background of camera rays
//!   that miss (hdEmbree evaluates the dome for a ray that hits nothing; measured on the
//!   luxtest dome-only frame, spec README §4); [`Profile::HdEmbree`] shows only a RectLight
//!   whose custom `inputs:visibility:camera` is true, [`Profile::Spec`] honours that attribute
//!   for every area light.
//! - Texture filtering (not a UsdLux behaviour): nearest texel in `HdEmbree` — the reference's
//!   `SampleLightTexture` reads texel `(⌊w·s⌋, ⌊h·t⌋)` for lighting *and* for the background
//!   of camera rays, which is what makes the dome frame's sharp texel edges agree (a bilinear
//!   background matches its mean to 1e-5 but blurs every edge) — bilinear in `Spec`.
//! - The IES emission direction of an area light (both profiles): from the sampled point on
//!   the light towards the receiver, as hdEmbree's `EvalIES(light, wI)` takes it, not from the
//!   light's centre. In the near field of a small SphereLight with a sharp (angle-scaled)
//!   profile the two differ by at most 0.15 % of the image mean on the luxtest
//!   `iesLibPreview` frames; the 1–2 % (locally 3–9 %) by which one 64-spp reference render
//!   sits below lux there is the right skew of the reference's estimator (uniform sampling of
//!   the whole sphere's area): its realizations are typically below its expectation, which
//!   more samples reach (`tests/hdembree_profile.rs`).

use crate::RenderError;
use crate::image_io::Texture;
use crate::physical;
use glam::{DMat3, DMat4, DVec3};
use lux_ies::{IesFile, ParseOptions, PhotometricWeb};
use lux_math::{LightKind, LightShape, Profile};
use lux_sample::{
    CylinderLight, CylinderTechnique, DiskLight, DiskTechnique, DistantLight, DomeLight,
    DomeTechnique, EmissionCone, LatLongMap, LightBounds, LightBvh, LightSample, LightSelector,
    LightTransform, MeshLight, MeshTechnique, RectLight, RectTechnique, Reference, SphereLight,
    SphereTechnique,
};
use lux_shaping::{Shaping, ShapingOptions, ShapingParams};
use lux_usd::{Light, PoleAxis, Scene, ShadowInputs, UpAxis};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Which sampling techniques the renderer uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SamplingMode {
    /// lux's importance sampling (solid-angle techniques, textured dome) with MIS against
    /// cosine-weighted BSDF sampling.
    #[default]
    Lux,
    /// hdEmbree's strategies, for A/B comparison: every area light sampled uniformly by area,
    /// the dome uniformly over the hemisphere around the normal, light sampling only (no
    /// MIS). Same expectation, more noise.
    Reference,
}

/// How the light to sample at a shading point is chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LightSelection {
    /// Every light at every shading point when there are at most [`AUTO_ALL_LIGHTS`] lights,
    /// else one light chosen by the light BVH.
    #[default]
    Auto,
    /// Every light at every shading point.
    All,
    /// One light, chosen in proportion to its estimated power.
    Power,
    /// One light, chosen by the light BVH's importance at the shading point
    /// (Conty Estevez & Kulla 2018).
    Bvh,
}

/// Light count up to which [`LightSelection::Auto`] samples every light.
pub const AUTO_ALL_LIGHTS: usize = 8;

/// Per-kind geometry for intersection and texture lookups (local space).
#[derive(Clone, Debug)]
enum Geom {
    Rect { hw: f64, hh: f64 },
    Disk { r: f64 },
    Sphere { r: f64 },
    Cylinder { r: f64, hl: f64 },
    Distant,
    Dome,
    Mesh { mesh: usize },
}

/// A texture bound to a light, with how it is looked up.
#[derive(Clone, Debug)]
struct LightTexture {
    tex: Arc<Texture>,
    nearest: bool,
}

impl LightTexture {
    #[inline]
    fn rgb(&self, u: f64, v: f64) -> DVec3 {
        let t = if self.nearest {
            self.tex.nearest(u, v)
        } else {
            self.tex.bilinear(u, v)
        };
        DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64)
    }
}

/// One light ready to render.
#[derive(Clone, Debug)]
pub struct RenderLight {
    /// Prim path.
    pub path: String,
    /// Light family.
    pub kind: LightKind,
    /// Base radiance (RGB nits) before shaping and texture.
    pub radiance: DVec3,
    /// ShapingAPI factor (identity without the API).
    pub shaping: Shaping,
    /// Estimated emitted power (RGB-luminance-weighted), for light selection.
    pub power: f64,
    /// Whether camera rays see the light's surface (or, for a dome, the background).
    pub camera_visible: bool,
    /// A delta light (DistantLight of angle 0): light sampling only.
    pub delta: bool,
    /// `inputs:diffuse`: multiplier of the light's effect on diffuse surfaces (finite, ≥ 0).
    pub diffuse: f64,
    /// `ShadowAPI` inputs (`enable`, `color`, `distance`, `falloff`, `falloffGamma`).
    pub shadow: ShadowInputs,
    geom: Geom,
    xf: LightTransform,
    /// World → light linear map, for emission directions.
    inv_linear: DMat3,
    sampler: lux_sample::Light,
    reference: lux_sample::Light,
    texture: Option<LightTexture>,
    mirror_u: bool,
}

/// What a ray crossing a light's surface found.
#[derive(Clone, Copy, Debug)]
pub struct LightHit {
    /// Distance along the ray.
    pub t: f64,
    /// The point in light space.
    pub local: DVec3,
    /// True when the ray arrives on the emitting side.
    pub front: bool,
}

impl RenderLight {
    /// Whether the light's shadows are the physical default (enabled, black, no distance
    /// limit). Lights with other `ShadowAPI` settings are estimated by light sampling alone,
    /// since a BSDF ray stops at the first occluder.
    #[inline]
    pub fn plain_shadows(&self) -> bool {
        self.shadow.enable
            && self.shadow.color == DVec3::ZERO
            && (self.shadow.distance.is_nan() || self.shadow.distance < 0.0)
    }

    /// Emitted radiance (RGB) from light-space point `local` along the world direction `emit`
    /// (from the light towards the receiver). `lit_path` selects the texture orientation of
    /// the lit path (which the `HdEmbree` profile mirrors).
    #[inline]
    pub fn emitted(&self, local: DVec3, emit: DVec3, lit_path: bool) -> DVec3 {
        let wl = self.inv_linear * emit;
        let len = wl.length();
        if !(len > 0.0 && len.is_finite()) {
            return DVec3::ZERO;
        }
        let wl = wl / len;
        match self.geom {
            Geom::Rect { .. } | Geom::Disk { .. } if wl.z >= 0.0 => return DVec3::ZERO,
            Geom::Sphere { .. } if local.dot(wl) <= 0.0 => return DVec3::ZERO,
            Geom::Cylinder { .. } if local.y * wl.y + local.z * wl.z <= 0.0 => {
                return DVec3::ZERO;
            }
            _ => {}
        }
        let f = self.shaping.factor(wl);
        let mut l = self.radiance * DVec3::new(f[0] as f64, f[1] as f64, f[2] as f64);
        if let (Some(t), Geom::Rect { hw, hh }) = (&self.texture, &self.geom) {
            let x = 0.5 * local.x / hw;
            let u = if lit_path && self.mirror_u {
                0.5 + x
            } else {
                0.5 - x
            };
            let v = 0.5 - 0.5 * local.y / hh;
            l *= t.rgb(u, v);
        }
        l
    }

    /// Radiance arriving from the infinitely distant light along world direction `wi`
    /// (receiver → light): the dome texture, or a distant light's cone; zero otherwise.
    #[inline]
    pub fn infinite_radiance(&self, wi: DVec3) -> DVec3 {
        match self.geom {
            Geom::Dome => {
                let Some(t) = &self.texture else {
                    return self.radiance;
                };
                let d = (self.inv_linear * wi).normalize_or_zero();
                if d == DVec3::ZERO {
                    return DVec3::ZERO;
                }
                let uv = lux_sample::latlong_uv(d);
                self.radiance * t.rgb(uv[0], uv[1])
            }
            Geom::Distant => {
                if self.delta || self.sampler.pdf(&Reference::point(DVec3::ZERO), wi) <= 0.0 {
                    return DVec3::ZERO;
                }
                self.emitted(DVec3::ZERO, -wi, true)
            }
            _ => DVec3::ZERO,
        }
    }

    /// Whether the light lies at infinity (dome, distant).
    #[inline]
    pub fn is_infinite(&self) -> bool {
        matches!(self.geom, Geom::Dome | Geom::Distant)
    }

    /// The scene mesh a mesh light emits from.
    pub fn mesh(&self) -> Option<usize> {
        match self.geom {
            Geom::Mesh { mesh } => Some(mesh),
            _ => None,
        }
    }

    /// Samples the light from `r` with the technique of `mode`.
    #[inline]
    pub fn sample(&self, r: &Reference, u: [f64; 2], mode: SamplingMode) -> Option<LightSample> {
        match mode {
            SamplingMode::Lux => self.sampler.sample(r, u),
            SamplingMode::Reference => {
                if let Geom::Dome = self.geom {
                    // hdEmbree: uniform over the hemisphere around the receiver normal.
                    if r.n == DVec3::ZERO {
                        return self.reference.sample(r, u);
                    }
                    let f = lux_math::Frame::from_normal(r.n);
                    let w = f.to_world(lux_sample::warp::sample_uniform_hemisphere(u));
                    return Some(LightSample {
                        point: w,
                        normal: -w,
                        wi: w,
                        distance: f64::INFINITY,
                        pdf: 0.5 * std::f64::consts::FRAC_1_PI,
                        delta: false,
                    });
                }
                self.reference.sample(r, u)
            }
        }
    }

    /// Solid-angle density of the lux technique for direction `wi` from `r` (for MIS).
    #[inline]
    pub fn pdf(&self, r: &Reference, wi: DVec3) -> f64 {
        self.sampler.pdf(r, wi)
    }

    /// Density of a mesh light's technique through triangle `tri` (for MIS after a BSDF ray hit
    /// that triangle).
    #[inline]
    pub fn pdf_triangle(&self, r: &Reference, tri: usize, wi: DVec3) -> f64 {
        match &self.sampler {
            lux_sample::Light::Mesh(m) => m.pdf_triangle(r, tri, wi),
            _ => 0.0,
        }
    }

    /// The light-space point of a world point.
    #[inline]
    pub fn to_local(&self, p: DVec3) -> DVec3 {
        self.xf.inv_point(p)
    }

    /// First crossing of the ray `o + t·d`, `t ∈ (tmin, tmax)`, with the light's analytic
    /// surface (rect, disk, sphere, cylinder). Transforms are affine, so `t` is the same in
    /// light space.
    pub fn intersect(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> Option<LightHit> {
        let ol = self.xf.inv_point(o);
        let dl = self.xf.inv_vector(d);
        let in_range = |t: f64| t > tmin && t < tmax;
        match self.geom {
            Geom::Rect { hw, hh } => {
                let t = -ol.z / dl.z;
                if !in_range(t) {
                    return None;
                }
                let q = ol + t * dl;
                (q.x.abs() <= hw && q.y.abs() <= hh).then_some(LightHit {
                    t,
                    local: DVec3::new(q.x, q.y, 0.0),
                    front: dl.z > 0.0,
                })
            }
            Geom::Disk { r } => {
                let t = -ol.z / dl.z;
                if !in_range(t) {
                    return None;
                }
                let q = ol + t * dl;
                (q.x * q.x + q.y * q.y <= r * r).then_some(LightHit {
                    t,
                    local: DVec3::new(q.x, q.y, 0.0),
                    front: dl.z > 0.0,
                })
            }
            Geom::Sphere { r } => {
                let (t0, t1) =
                    quadratic(dl.length_squared(), ol.dot(dl), ol.length_squared() - r * r)?;
                let t = if in_range(t0) {
                    t0
                } else if in_range(t1) {
                    t1
                } else {
                    return None;
                };
                let q = ol + t * dl;
                Some(LightHit {
                    t,
                    local: q,
                    front: q.dot(dl) < 0.0,
                })
            }
            Geom::Cylinder { r, hl } => {
                let a = dl.y * dl.y + dl.z * dl.z;
                let b = ol.y * dl.y + ol.z * dl.z;
                let c = ol.y * ol.y + ol.z * ol.z - r * r;
                let (t0, t1) = quadratic(a, b, c)?;
                for t in [t0, t1] {
                    if in_range(t) {
                        let q = ol + t * dl;
                        if q.x.abs() <= hl {
                            return Some(LightHit {
                                t,
                                local: q,
                                front: q.y * dl.y + q.z * dl.z < 0.0,
                            });
                        }
                    }
                }
                None
            }
            Geom::Distant | Geom::Dome | Geom::Mesh { .. } => None,
        }
    }
}

/// Roots t0 ≤ t1 of a·t² + 2b·t + c = 0 (numerically stable form), `None` without real roots.
#[inline]
fn quadratic(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    if a.is_nan() || a <= 0.0 {
        return None;
    }
    let disc = b * b - a * c;
    if disc.is_nan() || disc < 0.0 {
        return None;
    }
    let s = disc.sqrt();
    let q = -(b + s.copysign(b));
    let (x, y) = if q != 0.0 { (q / a, c / q) } else { (0.0, 0.0) };
    Some((x.min(y), x.max(y)))
}

/// Options that decide how lights are prepared.
#[derive(Clone, Copy, Debug)]
pub struct LightOptions {
    /// Conformance profile.
    pub profile: Profile,
    /// Light selection strategy.
    pub selection: LightSelection,
    /// An IES profile or light texture that does not resolve or cannot be read is an error
    /// (`true`) or a warning, the light emitting without it (`false`, usd-core's and Hydra's
    /// behaviour).
    pub strict: bool,
}

/// Every light of a scene, prepared, with the selection strategy.
pub struct LightSet {
    /// The lights, in scene order (lights that cannot emit are left out, with a warning).
    pub lights: Vec<RenderLight>,
    /// For each scene mesh, the index in `lights` of the mesh light it carries.
    pub mesh_light: Vec<Option<usize>>,
    /// `None` = sample every light at every shading point.
    pub selector: Option<LightSelector>,
    /// Non-fatal problems met while preparing the lights.
    pub warnings: Vec<String>,
}

impl LightSet {
    /// Prepares every light of `scene`. IES profiles and textures are loaded once per file.
    /// A malformed or missing IES/texture file referenced by a light is a warning naming the
    /// light and the file, and the light emits without it (an error with
    /// [`LightOptions::strict`]); a light whose inputs cannot be converted at all is left out
    /// with a warning naming it, so one bad light never takes the others with it.
    pub fn new(scene: &Scene, options: LightOptions) -> Result<LightSet, RenderError> {
        let mut ies_cache: HashMap<PathBuf, PhotometricWeb> = HashMap::new();
        let mut tex_cache: HashMap<PathBuf, Arc<Texture>> = HashMap::new();
        let mut lights = Vec::new();
        let mut warnings = Vec::new();
        let mut mesh_light = vec![None; scene.meshes.len()];
        for (li, l) in scene.lights.iter().enumerate() {
            // Only a world-space mesh is drawn where its positions say (a prototype's mesh is in
            // prototype space; the loader never gives one MeshLightAPI).
            let mesh = scene
                .meshes
                .iter()
                .position(|m| m.light == Some(li) && m.prototype.is_none());
            let prepared = prepare(
                scene,
                l,
                mesh,
                options,
                &mut ies_cache,
                &mut tex_cache,
                &mut warnings,
            );
            let prepared = match prepared {
                Ok(p) => p,
                Err(e) if options.strict => return Err(e),
                // One light's unusable inputs (a spectrum lux-spectral refuses…) leave that
                // light out, named, and never the others.
                Err(e) => {
                    warnings.push(format!("{e}; the light is not rendered"));
                    None
                }
            };
            if let Some(rl) = prepared {
                if let Some(m) = mesh {
                    mesh_light[m] = Some(lights.len());
                }
                lights.push(rl);
            }
        }
        let selector = build_selector(scene, &lights, options.selection, &mut warnings);
        Ok(LightSet {
            lights,
            mesh_light,
            selector,
            warnings,
        })
    }
}

fn build_selector(
    scene: &Scene,
    lights: &[RenderLight],
    selection: LightSelection,
    warnings: &mut Vec<String>,
) -> Option<LightSelector> {
    let n = lights.len();
    let sel = match selection {
        LightSelection::Auto if n <= AUTO_ALL_LIGHTS => return None,
        LightSelection::All => return None,
        LightSelection::Auto => LightSelection::Bvh,
        s => s,
    };
    if n == 0 {
        return None;
    }
    let result = match sel {
        LightSelection::Power => {
            let p: Vec<f64> = lights.iter().map(|l| l.power).collect();
            LightSelector::power(&p)
        }
        _ => {
            let bounds: Vec<Option<LightBounds>> =
                lights.iter().map(|l| light_bounds(scene, l)).collect();
            LightBvh::new(&bounds).map(LightSelector::Bvh)
        }
    };
    match result {
        Ok(s) => Some(s),
        Err(e) => {
            warnings.push(format!(
                "light selection {sel:?} unavailable ({e}); sampling every light"
            ));
            None
        }
    }
}

/// World bounds, power and emission cone of a finite light (`None` for infinite lights).
fn light_bounds(scene: &Scene, l: &RenderLight) -> Option<LightBounds> {
    let corners: Vec<DVec3> = match l.geom {
        Geom::Distant | Geom::Dome => return None,
        Geom::Rect { hw, hh } => [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .iter()
            .map(|(a, b)| l.xf.point(DVec3::new(a * hw, b * hh, 0.0)))
            .collect(),
        Geom::Disk { r } => box_corners(DVec3::new(r, r, 0.0))
            .map(|c| l.xf.point(c))
            .to_vec(),
        Geom::Sphere { r } => box_corners(DVec3::splat(r)).map(|c| l.xf.point(c)).to_vec(),
        Geom::Cylinder { r, hl } => box_corners(DVec3::new(hl, r, r))
            .map(|c| l.xf.point(c))
            .to_vec(),
        Geom::Mesh { mesh } => scene.meshes[mesh].positions.clone(),
    };
    let (mut min, mut max) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for c in &corners {
        min = min.min(*c);
        max = max.max(*c);
    }
    let axis = l.xf.normal(DVec3::NEG_Z);
    let (theta_o, two_sided) = match l.geom {
        Geom::Rect { .. } | Geom::Disk { .. } => (0.0, false),
        Geom::Mesh { .. } => (std::f64::consts::PI, true),
        _ => (std::f64::consts::PI, false),
    };
    // The ShapingAPI (cone, IES profile and its angleScale) narrows the emission around the
    // axis to lux-shaping's conservative half-angle: for planar lights only (for spheres and
    // cylinders the shaping is about the light axis, not each surface normal) under a
    // similarity transform (a non-uniform scale or shear changes angles between light and
    // world space).
    let theta_e = match l.geom {
        Geom::Rect { .. } | Geom::Disk { .. } if l.xf.is_similarity() => l
            .shaping
            .emission_half_angle()
            .min(std::f64::consts::FRAC_PI_2),
        _ => std::f64::consts::FRAC_PI_2,
    };
    let cone = EmissionCone::new(axis, theta_o, theta_e).unwrap_or(EmissionCone::SPHERE);
    LightBounds::new(min, max, l.power.max(0.0), cone, two_sided).ok()
}

fn box_corners(h: DVec3) -> [DVec3; 8] {
    let mut out = [DVec3::ZERO; 8];
    for (i, o) in out.iter_mut().enumerate() {
        *o = DVec3::new(
            if i & 1 == 0 { -h.x } else { h.x },
            if i & 2 == 0 { -h.y } else { h.y },
            if i & 4 == 0 { -h.z } else { h.z },
        );
    }
    out
}

/// Rec.709 luminance of an RGB triple.
#[inline]
pub fn luminance(c: DVec3) -> f64 {
    c.dot(DVec3::from(lux_math::REC709_LUMINANCE))
}

/// Loads and expands an IES profile (once per file). Real-world files are read leniently —
/// integer fields written as decimals and trailing numbers are accepted with a warning — and
/// a `TILT=<file>` is looked up next to the IES file.
fn load_ies(
    cache: &mut HashMap<PathBuf, PhotometricWeb>,
    path: &Path,
    profile: Profile,
    warnings: &mut Vec<String>,
) -> Result<PhotometricWeb, RenderError> {
    if let Some(w) = cache.get(path) {
        return Ok(w.clone());
    }
    let bytes = lux_usd::asset::read_asset(path).map_err(|e| RenderError::Asset {
        file: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let text = String::from_utf8_lossy(&bytes);
    let err = |e: lux_ies::IesError| RenderError::Asset {
        file: path.to_path_buf(),
        message: e.to_string(),
    };
    // TILT=<file>: next to the IES file (inside the same package for a packaged profile).
    let ies_path = path.to_path_buf();
    let resolver = move |name: &str| {
        lux_usd::asset::read_asset(&lux_usd::asset::sibling(&ies_path, name))
            .ok()
            .map(|b| String::from_utf8_lossy(&b).into_owned())
    };
    let options = ParseOptions {
        tilt_resolver: Some(&resolver),
        lenient: true,
        ..ParseOptions::default()
    };
    let parsed = IesFile::parse_with(&text, &options).map_err(err)?;
    // Only what changes how the file is read is worth a render warning (missing keywords
    // and stray text lines are `lux ies info`'s business).
    for w in &parsed.warnings {
        if matches!(
            w,
            lux_ies::Warning::TiltFileUnresolved { .. }
                | lux_ies::Warning::IntegerWrittenAsDecimal { .. }
                | lux_ies::Warning::TrailingData { .. }
        ) {
            warnings.push(format!("{}: {w}", path.display()));
        }
    }
    let web = PhotometricWeb::new(&parsed.file, profile).map_err(err)?;
    cache.insert(path.to_path_buf(), web.clone());
    Ok(web)
}

fn load_texture(
    cache: &mut HashMap<PathBuf, Arc<Texture>>,
    path: &Path,
) -> Result<Arc<Texture>, RenderError> {
    if let Some(t) = cache.get(path) {
        return Ok(t.clone());
    }
    let t = Arc::new(
        crate::assets::load_texture(path).map_err(|e| RenderError::Asset {
            file: path.to_path_buf(),
            message: e.to_string(),
        })?,
    );
    cache.insert(path.to_path_buf(), t.clone());
    Ok(t)
}

/// The dome's latlong frame: its light-to-world transform, turned +90° about X when the pole
/// axis is Z (`poleAxis = "Z"`, or `"scene"` on a Z-up stage), spec §2.
fn dome_transform(scene: &Scene, l: &Light) -> DMat4 {
    let z_up = match l.pole_axis {
        PoleAxis::Z => true,
        PoleAxis::Y => false,
        PoleAxis::Scene => scene.up_axis == UpAxis::Z,
    };
    if z_up {
        l.light_to_world * DMat4::from_rotation_x(std::f64::consts::FRAC_PI_2)
    } else {
        l.light_to_world
    }
}

#[allow(clippy::too_many_arguments)]
fn prepare(
    scene: &Scene,
    l: &Light,
    mesh: Option<usize>,
    options: LightOptions,
    ies_cache: &mut HashMap<PathBuf, PhotometricWeb>,
    tex_cache: &mut HashMap<PathBuf, Arc<Texture>>,
    warnings: &mut Vec<String>,
) -> Result<Option<RenderLight>, RenderError> {
    let profile = options.profile;
    let skip = |warnings: &mut Vec<String>, why: String| {
        warnings.push(format!("{}: {why}; the light is not rendered", l.path));
        Ok(None)
    };
    let m = if l.kind == LightKind::Dome {
        dome_transform(scene, l)
    } else {
        l.light_to_world
    };
    let xf = match LightTransform::new(m) {
        Ok(xf) => xf,
        Err(e) => return skip(warnings, format!("unusable transform ({e})")),
    };
    // A light's asset that cannot be used: an error when strict, else a warning and `None`.
    let asset = |warnings: &mut Vec<String>, file: &Path, what: &str, message: String| {
        if options.strict {
            return Err(RenderError::Asset {
                file: file.to_path_buf(),
                message,
            });
        }
        warnings.push(format!(
            "{}: {message}; {} emits without its {what}",
            file.display(),
            l.path
        ));
        Ok(())
    };
    // Shaping.
    let shaping = match &l.shaping {
        None => Shaping::identity(),
        Some(s) => {
            let ies = match s.ies_file.as_ref() {
                None => None,
                Some(a) => match &a.resolved {
                    Some(p) => match load_ies(ies_cache, p, profile, warnings) {
                        Ok(w) => Some(w),
                        Err(RenderError::Asset { file, message }) => {
                            asset(warnings, &file, "IES profile", message)?;
                            None
                        }
                        Err(e) => return Err(e),
                    },
                    None => {
                        asset(
                            warnings,
                            Path::new(&a.authored),
                            "IES profile",
                            format!(
                                "inputs:shaping:ies:file of {} does not resolve to a file",
                                l.path
                            ),
                        )?;
                        None
                    }
                },
            };
            let params = ShapingParams {
                focus: s.focus,
                focus_tint: s.focus_tint.to_array(),
                cone_angle_deg: s.cone_angle_deg,
                cone_softness: s.cone_softness,
                ies_angle_scale: s.ies_angle_scale,
                ies_normalize: s.ies_normalize,
            };
            let opts = ShapingOptions {
                profile,
                ..ShapingOptions::default()
            };
            match Shaping::new(&params, ies, opts) {
                Ok(s) => s,
                Err(e) => return skip(warnings, format!("invalid ShapingAPI inputs ({e})")),
            }
        }
    };
    // Texture (rect and dome).
    let texture = match (&l.texture, l.kind) {
        (Some(a), LightKind::Rect | LightKind::Dome) => match &a.resolved {
            Some(p) => match load_texture(tex_cache, p) {
                Ok(tex) => Some(LightTexture {
                    tex,
                    nearest: profile == Profile::HdEmbree,
                }),
                Err(RenderError::Asset { file, message }) => {
                    asset(warnings, &file, "texture", message)?;
                    None
                }
                Err(e) => return Err(e),
            },
            None => {
                asset(
                    warnings,
                    Path::new(&a.authored),
                    "texture",
                    format!(
                        "inputs:texture:file of {} does not resolve to a file",
                        l.path
                    ),
                )?;
                None
            }
        },
        _ => None,
    };
    // Geometry and samplers.
    let (geom, sampler, reference, delta) = match &l.shape {
        LightShape::Rect { width, height } => {
            let mk = |t| RectLight::new(*width, *height, xf, t).map(lux_sample::Light::Rect);
            match (
                mk(RectTechnique::SphericalRectangle),
                mk(RectTechnique::Area),
            ) {
                (Ok(a), Ok(b)) => (
                    Geom::Rect {
                        hw: 0.5 * width,
                        hh: 0.5 * height,
                    },
                    a,
                    b,
                    false,
                ),
                (Err(e), _) | (_, Err(e)) => return skip(warnings, e.to_string()),
            }
        }
        LightShape::Disk { radius } => {
            let mk = |t| DiskLight::new(*radius, xf, t).map(lux_sample::Light::Disk);
            match (mk(DiskTechnique::EllipticCone), mk(DiskTechnique::Area)) {
                (Ok(a), Ok(b)) => (Geom::Disk { r: *radius }, a, b, false),
                (Err(e), _) | (_, Err(e)) => return skip(warnings, e.to_string()),
            }
        }
        LightShape::Sphere { radius } => {
            let mk = |t| SphereLight::new(*radius, xf, t).map(lux_sample::Light::Sphere);
            match (mk(SphereTechnique::Cone), mk(SphereTechnique::Area)) {
                (Ok(a), Ok(b)) => (Geom::Sphere { r: *radius }, a, b, false),
                (Err(_), _) | (_, Err(_)) if *radius == 0.0 => {
                    // DCC exports write point lights this way (Maya: treatAsPoint, radius 0).
                    return skip(
                        warnings,
                        format!(
                            "SphereLight of radius 0{} is a point light, and lux renders \
                             only lights with an area",
                            if l.treat_as_point {
                                " (treatAsPoint, a renderer hint)"
                            } else {
                                ""
                            }
                        ),
                    );
                }
                (Err(e), _) | (_, Err(e)) => return skip(warnings, e.to_string()),
            }
        }
        LightShape::Cylinder { radius, length } => {
            let mk =
                |t| CylinderLight::new(*radius, *length, xf, t).map(lux_sample::Light::Cylinder);
            match (
                mk(CylinderTechnique::SolidAngle),
                mk(CylinderTechnique::Area),
            ) {
                (Ok(a), Ok(b)) => (
                    Geom::Cylinder {
                        r: *radius,
                        hl: 0.5 * length,
                    },
                    a,
                    b,
                    false,
                ),
                (Err(e), _) | (_, Err(e)) => return skip(warnings, e.to_string()),
            }
        }
        LightShape::Distant { angle_deg } => match DistantLight::new(*angle_deg, &xf) {
            Ok(d) => {
                let delta = d.is_delta();
                let s = lux_sample::Light::Distant(d);
                (Geom::Distant, s.clone(), s, delta)
            }
            Err(e) => return skip(warnings, e.to_string()),
        },
        LightShape::Dome => {
            let lux = match &texture {
                Some(t) => {
                    let (w, h) = (t.tex.width(), t.tex.height());
                    let lum: Vec<f32> = t
                        .tex
                        .texels()
                        .iter()
                        .map(|p| {
                            luminance(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)).max(0.0)
                                as f32
                        })
                        .collect();
                    match LatLongMap::new(w, h, lum)
                        .and_then(|map| DomeLight::new(&map, xf, DomeTechnique::Texture))
                    {
                        Ok(d) => d,
                        Err(e) => return skip(warnings, format!("dome texture unusable ({e})")),
                    }
                }
                None => DomeLight::uniform(xf),
            };
            let s = lux_sample::Light::Dome(lux);
            (
                Geom::Dome,
                s,
                lux_sample::Light::Dome(DomeLight::uniform(xf)),
                false,
            )
        }
        LightShape::Portal { .. } => {
            return skip(
                warnings,
                "PortalLight is not rendered (lux does not restrict dome lights to portals)".into(),
            );
        }
        LightShape::Mesh { .. } => {
            let Some(mi) = mesh else {
                return skip(warnings, "mesh light without drawn geometry".into());
            };
            let sm = &scene.meshes[mi];
            let mk = |t| {
                MeshLight::new(&sm.positions, &sm.triangles, None, sm.double_sided, t)
                    .map(lux_sample::Light::Mesh)
            };
            match (
                mk(MeshTechnique::SphericalTriangle),
                mk(MeshTechnique::Area),
            ) {
                (Ok(a), Ok(b)) => (Geom::Mesh { mesh: mi }, a, b, false),
                (Err(e), _) | (_, Err(e)) => return skip(warnings, e.to_string()),
            }
        }
    };
    // Base emission.
    let stage_unit = scene.unit_for_wavelength;
    // the stage's up axis in the dome texture's frame (for a photometric dome's illuminance)
    let world_up = match scene.up_axis {
        UpAxis::Z => DVec3::Z,
        UpAxis::Y => DVec3::Y,
    };
    let dome_up = xf.inv_vector(world_up);
    let radiance = physical::base_radiance(
        l,
        &shaping,
        texture.as_ref().map(|t| &*t.tex),
        dome_up,
        profile,
        stage_unit,
    )?;
    let camera_visible = match (profile, l.kind) {
        (_, LightKind::Dome) => true,
        (Profile::HdEmbree, LightKind::Rect) => l.visible_to_camera,
        (Profile::HdEmbree, _) => false,
        (
            Profile::Spec,
            LightKind::Rect | LightKind::Disk | LightKind::Sphere | LightKind::Cylinder,
        ) => l.visible_to_camera,
        (Profile::Spec, _) => false,
    };
    let area = lux_math::size_factor(&l.shape, &l.light_to_world, Profile::Spec);
    let mean_tex = texture
        .as_ref()
        .map(|t| {
            let a = t.tex.average();
            luminance(DVec3::new(a[0], a[1], a[2]))
        })
        .unwrap_or(1.0);
    let rad_lum = luminance(radiance).max(0.0) * mean_tex;
    let ints = shaping.integral_cos_hemisphere();
    let g = luminance(DVec3::from(ints)).max(0.0);
    let power = match l.kind {
        LightKind::Rect | LightKind::Disk => rad_lum * area * g,
        LightKind::Sphere | LightKind::Cylinder | LightKind::Mesh => {
            rad_lum * area * std::f64::consts::PI * shaping.max_factor() as f64
        }
        _ => rad_lum * std::f64::consts::PI,
    };
    Ok(Some(RenderLight {
        path: l.path.clone(),
        kind: l.kind,
        radiance,
        shaping,
        power: if power.is_finite() { power } else { 0.0 },
        camera_visible,
        delta,
        diffuse: if l.diffuse.is_finite() {
            l.diffuse.max(0.0)
        } else {
            0.0
        },
        shadow: l.shadow.clone(),
        geom,
        inv_linear: xf.linear().inverse(),
        xf,
        sampler,
        reference,
        texture,
        mirror_u: profile == Profile::HdEmbree,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadratic_roots() {
        // (t − 1)(t − 3) = t² − 4t + 3: a = 1, b = −2, c = 3.
        assert_eq!(quadratic(1.0, -2.0, 3.0), Some((1.0, 3.0)));
        assert_eq!(quadratic(1.0, 0.0, 1.0), None);
        assert_eq!(quadratic(0.0, 1.0, 1.0), None);
        assert_eq!(quadratic(f64::NAN, 1.0, 1.0), None);
        // Tiny root without cancellation: t² − 2·1e8 t + 1 → 5e-9.
        let (t0, _) = quadratic(1.0, -1e8, 1.0).unwrap();
        assert!((t0 - 5e-9).abs() < 1e-22);
    }
}
