//! Materials: what a ray sees where it hits geometry — position, facing normals and the BSDF
//! ([`Bsdf`]): Lambertian ([`DiffuseBsdf`]) or a MaterialX closure tree ([`GraphBsdf`]:
//! UsdPreviewSurface, standard_surface, open_pbr_surface as their MaterialX graphs), the
//! Lambertian's `diffuseColor` a value, a `UsdUVTexture` (`material/texture.rs`) or a primvar of the gprim
//! read by a `UsdPrimvarReader_*` (the hit's interpolated corner values, the reader's
//! `fallback` where the gprim has none); without a material, the gprim's
//! `primvars:displayColor`, else white — the white Lambertian of the reference renders; a
//! `wavelength:reflectance` (LTESpectralAPI) replaces `diffuseColor`.
//!
//! An instanced hit (`Hit::instance`) shades with its prototype mesh's primvars and
//! `doubleSided`, the material `mesh.material.or(instance.material)` (the prototype's own binding
//! wins over the instance's), and shading normals mapped to the world like the loader maps a
//! world mesh's: each corner normal `n` by the inverse transpose of the instance's linear part,
//! `normalize(M⁻ᵀ·n)`, then interpolated and renormalised.

mod diffuse;
pub mod graph;
mod graph_bsdf;
mod texture;

pub use diffuse::DiffuseBsdf;
pub use graph_bsdf::GraphBsdf;

use graph::{GraphShader, ShadingContext};

use crate::RenderError;
use crate::geometry::Hit;
use glam::{DMat3, DVec2, DVec3, DVec4};
use lux_usd::{Input, Scene, SurfaceSpectral, TextureInput};
use std::path::PathBuf;
use std::sync::Arc;
use texture::{TextureFiles, TextureShader, texture_shader};

/// A prepared UsdPreviewSurface input: a constant (a float input in `x`), a texture, or a
/// primvar of the gprim (slot `slot` of the material's [`Shader::primvars`]).
#[derive(Clone, Debug)]
enum Param {
    Value(DVec3),
    Texture(TextureShader),
    Primvar {
        slot: usize,
        /// The reader's output size: a one-component primvar (`_float`, `_int`) feeding a
        /// colour gives all three channels its value.
        components: usize,
    },
}

/// The most primvars one material reads (one an input).
const MAX_PRIMVARS: usize = 10;

/// What shading inputs read at a hit: the texture coordinates, and the material's primvars
/// there ([`Materials::lookup`]).
#[derive(Clone, Copy, Debug)]
struct Lookup {
    st: DVec2,
    primvars: [DVec4; MAX_PRIMVARS],
}

impl Param {
    /// The input at a hit.
    #[inline]
    fn eval(&self, at: &Lookup) -> DVec3 {
        match self {
            Param::Value(v) => *v,
            Param::Texture(t) => t.eval(at.st),
            Param::Primvar { slot, components } => {
                let v = at.primvars[*slot];
                if *components == 1 {
                    DVec3::splat(v.x)
                } else {
                    v.truncate()
                }
            }
        }
    }

    /// A float input at a hit.
    #[inline]
    fn eval1(&self, at: &Lookup) -> f64 {
        self.eval(at).x
    }
}

/// A material, prepared: its diffuse colour (all of it when surfaces are Lambertian), its
/// compiled graph otherwise, and its opacity.
#[derive(Clone, Debug)]
struct Shader {
    diffuse: Param,
    /// `inputs:opacity` (`None`: opaque).
    opacity: Option<Param>,
    /// `inputs:opacityThreshold`.
    threshold: f64,
    /// `inputs:emissiveColor` from a texture or a primvar (a constant emission is a mesh
    /// light instead).
    emission: Option<Param>,
    /// The primvars its primvar readers read, by slot: name and `inputs:fallback`.
    primvars: Vec<(String, DVec4)>,
    /// The material's MaterialX shading graph, compiled (`None`: Lambertian).
    graph: Option<Box<GraphMaterial>>,
}

/// A material shaded by its compiled MaterialX graph, and what the renderer must know of it
/// before any hit.
#[derive(Clone, Debug)]
struct GraphMaterial {
    shader: GraphShader,
    /// The slot of [`Lookup::primvars`] where the graph's primvars begin.
    primvar0: usize,
    /// Some closure may transmit (paths enter the surface; its back faces are seen).
    transmits: bool,
    /// The shader depends on the tangent frame ([`GraphShader::reads_tangent`]): only then is
    /// the tangent `∂p/∂s` (else any tangent about the normal, which is exactly the same
    /// for a hit through an instance and on its flattened copy).
    tangent: bool,
    /// The graph's emission is the material's (a MaterialX surface's EDF that is not a
    /// constant black; a UsdPreviewSurface's `emissiveColor` is the mesh light's or
    /// `emission`'s instead).
    emits: bool,
    /// The graph's opacity is the material's and is not a constant 1 (MaterialX models; a
    /// UsdPreviewSurface keeps `opacity`/`opacityThreshold` of [`Shader`]).
    transparent: bool,
}

/// A BSDF sample: the incident direction, its density, and the weight `f·|cos θ|/pdf` it
/// carries (Mitsuba's convention: for a Lambertian surface sampled by the cosine, exactly the
/// albedo).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// Unit world direction towards the light (away from the surface).
    pub wi: DVec3,
    /// Density of `wi` per unit solid angle.
    pub pdf: f64,
    /// `f(wi)·|cos θᵢ| / pdf`.
    pub weight: DVec3,
    /// Whether it came from a delta lobe (a mirror or smooth refraction): `pdf` is then the
    /// probability of choosing that lobe, and no light sample can reach `wi` (MIS weight 1).
    pub delta: bool,
}

/// The scattering function at a surface point (the closed set of lux's BSDFs).
#[derive(Clone, Debug)]
pub enum Bsdf {
    /// Lambertian reflection.
    Diffuse(DiffuseBsdf),
    /// A MaterialX closure tree (standard_surface, open_pbr_surface, UsdPreviewSurface as
    /// MaterialX defines it, or any graph of pbrlib closures).
    Graph(Box<GraphBsdf>),
}

impl Bsdf {
    /// True when the surface reflects nothing.
    #[inline]
    pub fn is_black(&self) -> bool {
        match self {
            Bsdf::Diffuse(b) => b.albedo == DVec3::ZERO,
            Bsdf::Graph(b) => b.bsdf.is_black(),
        }
    }

    /// Whether `f` is a constant `ρ/π` over the upper hemisphere (a Lambertian BSDF), so that
    /// light samples that follow the cosine-weighted solid angle are best estimated alone
    /// (the direct integrator's [`crate::light::Light::uniform_area`] lights).
    #[inline]
    pub fn is_lambertian(&self) -> bool {
        match self {
            Bsdf::Diffuse(_) => true,
            Bsdf::Graph(_) => false,
        }
    }

    /// Whether the BSDF transmits: light from behind the surface (the other side of the
    /// geometric normal) reaches the viewer, and sampled directions may go through it.
    #[inline]
    pub fn transmits(&self) -> bool {
        match self {
            Bsdf::Diffuse(_) => false,
            Bsdf::Graph(b) => b.transmits,
        }
    }

    /// `f(wi)` for the unit world direction `wi` (towards the light), the viewer given when
    /// the BSDF was made.
    #[inline]
    pub fn f(&self, wi: DVec3) -> DVec3 {
        match self {
            Bsdf::Diffuse(b) => b.f(wi),
            Bsdf::Graph(b) => b.f(wi),
        }
    }

    /// `f(wi)` as its diffuse and specular parts (Lambertian: all diffuse), for lights whose
    /// `inputs:diffuse` / `inputs:specular` multipliers differ.
    #[inline]
    pub fn f_lobes(&self, wi: DVec3) -> (DVec3, DVec3) {
        match self {
            Bsdf::Diffuse(b) => (b.f(wi), DVec3::ZERO),
            Bsdf::Graph(b) => b.f_lobes(wi),
        }
    }

    /// `f(wi)` with its diffuse part scaled by `kd` and its specular part by `ks` (LightAPI
    /// `inputs:diffuse`, `inputs:specular`); exactly [`Bsdf::f`] when both are 1.
    #[inline]
    pub fn f_scaled(&self, wi: DVec3, kd: f64, ks: f64) -> DVec3 {
        if kd == 1.0 && ks == 1.0 {
            return self.f(wi);
        }
        let (d, s) = self.f_lobes(wi);
        d * kd + s * ks
    }

    /// Density with which [`Bsdf::sample`] produces `wi` (per unit solid angle).
    #[inline]
    pub fn pdf(&self, wi: DVec3) -> f64 {
        match self {
            Bsdf::Diffuse(b) => b.pdf(wi),
            Bsdf::Graph(b) => b.pdf(wi),
        }
    }

    /// Samples an incident direction with `u ∈ [0,1)²` (`u_lobe` ∈ [0, 1) chooses the closure
    /// of a MaterialX tree; the others ignore it); `None` below the shading horizon (or
    /// where nothing scatters).
    #[inline]
    pub fn sample(&self, u: [f64; 2], u_lobe: f64) -> Option<BsdfSample> {
        match self {
            Bsdf::Diffuse(b) => b.sample(u),
            Bsdf::Graph(b) => b.sample(u, u_lobe),
        }
    }

    /// Whether `f(wo, wi) = f(wi, wo)`: true of the Lambertian and the hand-written
    /// UsdPreviewSurface BSDF; a MaterialX tree need not be (`layer` scales its base by the
    /// top's albedo towards the viewer, `MaterialX.PBRSpec.md` "layer"), so a light tracer
    /// evaluates it from the camera's side.
    #[inline]
    pub fn reciprocal(&self) -> bool {
        !matches!(self, Bsdf::Graph(_))
    }

    /// Whether [`Bsdf::sample`] reads its `u_lobe`.
    #[inline]
    pub fn chooses_lobes(&self) -> bool {
        matches!(self, Bsdf::Graph(_))
    }
}

/// The prepared materials of a scene.
pub struct Materials {
    /// Textures that could not be read (each replaced by its fallback).
    pub warnings: Vec<String>,
    /// The texture files, and the uses of those decoded on first use ([`Materials::late_warnings`]).
    files: TextureFiles,
    materials: Vec<Shader>,
    /// Per mesh: the albedo of a `wavelength:reflectance` authored on the gprim.
    mesh_reflectance: Vec<Option<DVec3>>,
    /// Per scene instance: `M⁻ᵀ`, the inverse transpose of its transform's linear part, which
    /// maps prototype-space normals to the world.
    instance_normal: Vec<DMat3>,
    /// Per scene instance: its transform's linear part (prototype-space tangents to the world).
    instance_linear: Vec<DMat3>,
    /// Per mesh: whether its material can be transparent somewhere (opacity < 1 or a cut-out).
    mesh_transparent: Vec<bool>,
    /// Per scene instance: whether its material (when its prototype mesh has none) can be.
    instance_transparent: Vec<bool>,
    /// Per mesh: a `MeshLightAPI` light with no surface response (no bound material, or
    /// `materialSyncMode = noMaterialResponse`): it reflects nothing.
    no_response: Vec<bool>,
    /// Per mesh: the albedo of a plain Lambertian surface ([`plain_albedo`]), which
    /// [`Materials::at`] takes for a hit on the mesh itself without evaluating anything.
    plain: Vec<Option<DVec3>>,
}

/// The clamped albedo of mesh `i` when every hit on it (not through an instance) is the same
/// Lambertian surface about its geometric normal: no `normals` primvar, no surface response
/// withheld, and a constant albedo — a `wavelength:reflectance`, a bound material's untextured
/// `diffuseColor` without UsdPreviewSurface lobes, or no material and no `displayColor`
/// primvar (white). What [`Materials::at`] computes for such a hit, once.
fn plain_albedo(
    scene: &Scene,
    i: usize,
    materials: &[Shader],
    reflectance: Option<DVec3>,
    no_response: &[bool],
) -> Option<DVec3> {
    let mesh = &scene.meshes[i];
    let shader = mesh.material.and_then(|k| materials.get(k));
    if mesh.normals.is_some() || no_response[i] || shader.is_some_and(|m| m.graph.is_some()) {
        return None;
    }
    let albedo = match (reflectance, shader) {
        (Some(c), _) => c,
        (None, Some(m)) => match &m.diffuse {
            Param::Value(v) => *v,
            Param::Texture(_) | Param::Primvar { .. } => return None,
        },
        (None, None) if mesh.colors.is_none() => DVec3::ONE,
        (None, None) => return None,
    };
    Some(clamped_albedo(albedo))
}

/// The normal of a closure node (`None` for a combinator).
fn closure_normal(node: &lux_bsdf::Node) -> Option<DVec3> {
    use lux_bsdf::Closure as C;
    let lux_bsdf::Node::Closure(c) = node else {
        return None;
    };
    let frame = match c {
        C::OrenNayar { frame, .. }
        | C::Burley { frame, .. }
        | C::Translucent { frame, .. }
        | C::Dielectric { frame, .. }
        | C::Conductor { frame, .. }
        | C::GeneralizedSchlick { frame, .. }
        | C::Sheen { frame, .. }
        | C::Subsurface { frame, .. } => frame,
    };
    frame.n.is_finite().then_some(frame.n)
}

/// A direction into the surface at `hit` from the side the ray came from (along the geometric
/// normal): the viewer of what does not depend on the ray's own direction (opacity, emission).
#[inline]
fn into_surface(hit: &Hit) -> DVec3 {
    if hit.back { hit.ng } else { -hit.ng }
}

/// An albedo as surfaces take it: each channel clamped to `[0, 1]`, black where not finite.
#[inline]
fn clamped_albedo(albedo: DVec3) -> DVec3 {
    if albedo.is_finite() {
        albedo.clamp(DVec3::ZERO, DVec3::ONE)
    } else {
        DVec3::ZERO
    }
}

/// Linear Rec.709 albedo of a `wavelength:reflectance` (lux-spectral, lit by the colour
/// space's white), if authored.
fn reflectance_albedo(
    prim: &str,
    a: &SurfaceSpectral,
    unit: lux_spectral::WavelengthUnit,
) -> Result<Option<DVec3>, RenderError> {
    let err = |message: String| RenderError::Surface {
        prim: prim.to_owned(),
        message,
    };
    if a.is_empty() {
        return Ok(None);
    }
    let inputs = crate::physical::surface_spectral_inputs(a, unit);
    // Validate the IOR too (it does not change a diffuse surface): bad data is an error.
    inputs.ior().map_err(|e| err(e.to_string()))?;
    inputs
        .reflectance_rgb(lux_spectral::ColorSpace::Rec709)
        .map_err(|e| err(e.to_string()))
}

/// The shading frame and BSDF at a hit.
#[derive(Clone, Debug)]
pub struct SurfacePoint {
    /// Position.
    pub p: DVec3,
    /// Geometric normal, on the side the ray came from.
    pub ng: DVec3,
    /// Shading normal (interpolated `normals` when authored), on the same side as `ng`.
    pub ns: DVec3,
    /// How far along `±ng` rays leaving `p` start ([`Hit::offset`]).
    pub offset: f64,
    /// The BSDF (about the shading normal).
    pub bsdf: Bsdf,
    /// The geometry hit: index into `Scene::meshes` ([`Hit::mesh`]), for light linking.
    pub mesh: usize,
    /// The triangle hit, within the mesh ([`Hit::tri`]).
    pub tri: usize,
    /// The instance hit ([`Hit::instance`]), for light linking.
    pub instance: Option<usize>,
}

/// How surfaces scatter light (`RenderOptions::surfaces`, `--surfaces`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SurfaceModel {
    /// The full UsdPreviewSurface: diffuse, GGX specular (specular or metallic workflow),
    /// clearcoat, ior, opacity and cut-outs, normal maps.
    Preview,
    /// Lambertian `diffuseColor` only, opaque (what the reference renderer shades).
    Lambert,
}

impl SurfaceModel {
    /// The default of a conformance profile: UsdPreviewSurface in `Spec`, Lambertian in
    /// `HdEmbree`.
    pub fn default_for(profile: lux_math::Profile) -> SurfaceModel {
        match profile {
            lux_math::Profile::HdEmbree => SurfaceModel::Lambert,
            _ => SurfaceModel::Preview,
        }
    }
}

/// When the texture files of `UsdUVTexture` inputs are decoded ([`Materials::prepare`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextureDecoding {
    /// All of them in parallel before the render: for integrators whose rays can reach any
    /// surface (a path's bounces, light particles).
    UpFront,
    /// Each when a lookup first needs it, its header checked up front (missing files, formats
    /// lux does not read and bad headers warn at once): a direct-lit frame shades only what
    /// the camera sees, and a texture no camera ray meets is never decoded. The same texels.
    OnFirstUse,
}

impl Materials {
    /// Loads the textures of every material (once per file), UsdPreviewSurface surfaces. A
    /// texture that does not resolve or cannot be read gives its `UsdUVTexture` fallback, with
    /// a warning naming it.
    pub fn new(scene: &Scene) -> Result<Materials, RenderError> {
        Materials::with_policy(scene, false, SurfaceModel::Preview)
    }

    /// [`Materials::new`], where `strict` makes an unreadable texture an error instead of its
    /// fallback with a warning, and `surfaces` chooses the UsdPreviewSurface or Lambertian
    /// `diffuseColor` (opaque).
    pub fn with_policy(
        scene: &Scene,
        strict: bool,
        surfaces: SurfaceModel,
    ) -> Result<Materials, RenderError> {
        Materials::prepare(scene, strict, surfaces, TextureDecoding::UpFront)
    }

    /// [`Materials::with_policy`], with the `UsdUVTexture` files decoded as `decoding` says
    /// (always up front when `strict`, so that a corrupt file is an error before the render).
    pub fn prepare(
        scene: &Scene,
        strict: bool,
        surfaces: SurfaceModel,
        decoding: TextureDecoding,
    ) -> Result<Materials, RenderError> {
        let unit = scene.unit_for_wavelength;
        let mut ld = InputLoader {
            files: TextureFiles {
                on_first_use: decoding == TextureDecoding::OnFirstUse && !strict,
                strict,
                ..TextureFiles::default()
            },
            graph_textures: graph::TextureCache::new(),
            warnings: Vec::new(),
            primvars: Vec::new(),
        };
        // The graphs of UsdPreviewSurfaces built in code, once per material; then every
        // texture file the materials read, decoded in parallel before they are prepared in order.
        let built: Vec<Option<Built>> = scene
            .materials
            .iter()
            .map(|m| built_graph(m, surfaces))
            .collect();
        ld.prefetch(scene, &built, surfaces);
        let mut materials = Vec::with_capacity(scene.materials.len());
        for (m, b) in scene.materials.iter().zip(&built) {
            materials.push(ld.material_shader(m, b.as_ref(), unit, surfaces)?);
        }
        let mut warnings = ld.warnings;
        let mut mesh_reflectance = Vec::with_capacity(scene.meshes.len());
        for m in &scene.meshes {
            mesh_reflectance.push(match reflectance_albedo(&m.path, &m.spectral, unit) {
                Ok(c) => c,
                Err(e) if strict => return Err(e),
                Err(e) => {
                    warnings.push(format!("{e}; the material's colour is used instead"));
                    None
                }
            });
        }
        let transparent = |k: Option<usize>| {
            k.and_then(|k| materials.get(k)).is_some_and(|s: &Shader| {
                s.opacity.is_some() || s.graph.as_ref().is_some_and(|g| g.transparent)
            })
        };
        let mesh_transparent = scene
            .meshes
            .iter()
            .map(|m| transparent(m.material))
            .collect();
        let instance_transparent = scene
            .instances
            .iter()
            .map(|i| transparent(i.material))
            .collect();
        let instance_linear: Vec<DMat3> = scene
            .instances
            .iter()
            .map(|i| DMat3::from_mat4(i.to_world))
            .collect();
        let instance_normal = instance_linear
            .iter()
            .map(|m| m.inverse().transpose())
            .collect();
        // Geometry lights (geometry-lights proposal, "No-Material Behavior" and
        // `noMaterialResponse`): "no specular, diffuse, or transmissive response".
        let no_response: Vec<bool> = scene
            .meshes
            .iter()
            .map(|m| {
                m.light
                    .and_then(|li| scene.lights.get(li))
                    .is_some_and(|l| {
                        m.material.is_none()
                            || l.material_sync_mode == lux_usd::MaterialSyncMode::NoMaterialResponse
                    })
            })
            .collect();
        let plain = (0..scene.meshes.len())
            .map(|i| plain_albedo(scene, i, &materials, mesh_reflectance[i], &no_response))
            .collect();
        Ok(Materials {
            files: ld.files,
            no_response,
            warnings,
            materials,
            mesh_reflectance,
            plain,
            instance_normal,
            instance_linear,
            mesh_transparent,
            instance_transparent,
        })
    }

    /// The warnings of texture files decoded on first use that failed when a render first read
    /// them (their uses took the fallback [`Materials::with_policy`] names): the words a file
    /// failing up front gives in [`Materials::warnings`].
    pub fn late_warnings(&self) -> impl Iterator<Item = String> + '_ {
        self.files.late_warnings()
    }

    /// Whether some surface can let rays through (UsdPreviewSurface `opacity` below 1 or an
    /// `opacityThreshold` cut-out), so that rays must test the opacity of what they hit.
    pub fn any_transparent(&self) -> bool {
        self.mesh_transparent.iter().any(|&t| t) || self.instance_transparent.iter().any(|&t| t)
    }

    /// Whether the material at `hit` transmits light (a path may enter the surface and meet its
    /// back from inside).
    #[inline]
    pub fn transmits(&self, scene: &Scene, hit: &Hit) -> bool {
        self.material_of(scene, hit)
            .and_then(|m| m.graph.as_ref())
            .is_some_and(|g| g.transmits)
    }

    /// Whether some material's `emissiveColor` is a texture ([`Materials::emission`]).
    pub fn any_textured_emission(&self) -> bool {
        self.materials
            .iter()
            .any(|m| m.emission.is_some() || m.graph.as_ref().is_some_and(|g| g.emits))
    }

    /// The radiance a surface emits from a texture-driven UsdPreviewSurface `emissiveColor` at
    /// `hit` (0 elsewhere, and from the back of a single-sided mesh). Such surfaces are not
    /// sampled as lights: camera and BSDF rays find their emission (unbiased, without
    /// next-event estimation); a constant `emissiveColor` makes a mesh light instead.
    #[inline]
    pub fn emission(&self, scene: &Scene, hit: &Hit) -> DVec3 {
        let Some(shader) = self.material_of(scene, hit) else {
            return DVec3::ZERO;
        };
        if hit.back && !scene.meshes[hit.mesh].double_sided {
            return DVec3::ZERO;
        }
        let e = match (&shader.emission, &shader.graph) {
            (Some(t), _) => t.eval(&self.lookup(scene, hit)),
            (None, Some(g)) if g.emits => {
                let at = self.lookup(scene, hit);
                let d = into_surface(hit);
                let n = self.normals(scene, hit, d);
                g.shader
                    .eval(&self.context(scene, hit, &at, g, n, -d))
                    .emission
            }
            _ => return DVec3::ZERO,
        };
        if e.is_finite() {
            e.max(DVec3::ZERO)
        } else {
            DVec3::ZERO
        }
    }

    /// The material of a hit: the mesh's own binding, else its instance's.
    #[inline]
    fn material_of(&self, scene: &Scene, hit: &Hit) -> Option<&Shader> {
        let mesh = &scene.meshes[hit.mesh];
        mesh.material
            .or_else(|| hit.instance.and_then(|i| scene.instances[i].material))
            .and_then(|k| self.materials.get(k))
    }

    /// Texture coordinates at a hit (0 without a texture-coordinate primvar).
    #[inline]
    fn st(scene: &Scene, hit: &Hit) -> DVec2 {
        match &scene.meshes[hit.mesh].uvs {
            Some(uv) => {
                let c = &uv[hit.tri];
                let (b1, b2) = (hit.bary.x, hit.bary.y);
                (1.0 - b1 - b2) * c[0] + b1 * c[1] + b2 * c[2]
            }
            None => DVec2::ZERO,
        }
    }

    /// What the shading inputs of the hit's material read there: the texture coordinates and
    /// its primvars ([`Shader::primvars`]), each interpolated over the triangle from the
    /// mesh's corners — a primvar the gprim does not author is `displayColor` from the mesh's
    /// colours (curves and points keep it there), else the reader's `fallback`.
    #[inline]
    fn lookup(&self, scene: &Scene, hit: &Hit) -> Lookup {
        let mut at = Lookup {
            st: Self::st(scene, hit),
            primvars: [DVec4::ZERO; MAX_PRIMVARS],
        };
        let Some(shader) = self.material_of(scene, hit) else {
            return at;
        };
        let mesh = &scene.meshes[hit.mesh];
        let (b1, b2) = (hit.bary.x, hit.bary.y);
        let b0 = 1.0 - b1 - b2;
        for (slot, (name, fallback)) in shader.primvars.iter().enumerate() {
            at.primvars[slot] = match mesh.primvars.iter().find(|p| &p.name == name) {
                Some(p) => {
                    let c = &p.values[hit.tri];
                    b0 * c[0] + b1 * c[1] + b2 * c[2]
                }
                None => match (&mesh.colors, name.as_str()) {
                    (Some(colors), "displayColor") => {
                        let c = &colors[hit.tri];
                        (b0 * c[0] + b1 * c[1] + b2 * c[2]).extend(0.0)
                    }
                    _ => *fallback,
                },
            };
        }
        at
    }

    /// How much of a ray the surface at `hit` stops: 1 opaque, 0 fully transparent
    /// (UsdPreviewSurface `opacity`; with `opacityThreshold > 0` a mask: 0 below the threshold,
    /// else 1).
    #[inline]
    pub fn opacity(&self, scene: &Scene, hit: &Hit) -> f64 {
        let transparent = self.mesh_transparent[hit.mesh]
            || hit.instance.is_some_and(|i| self.instance_transparent[i]);
        if !transparent {
            return 1.0;
        }
        let Some(shader) = self.material_of(scene, hit) else {
            return 1.0;
        };
        let o = match (&shader.opacity, &shader.graph) {
            (Some(opacity), _) => opacity.eval1(&self.lookup(scene, hit)),
            (None, Some(g)) if g.transparent => {
                let at = self.lookup(scene, hit);
                let d = into_surface(hit);
                let n = self.normals(scene, hit, d);
                g.shader
                    .eval(&self.context(scene, hit, &at, g, n, -d))
                    .opacity
            }
            _ => return 1.0,
        };
        let o = if o.is_finite() {
            o.clamp(0.0, 1.0)
        } else {
            1.0
        };
        if shader.threshold > 0.0 {
            if o < shader.threshold { 0.0 } else { 1.0 }
        } else {
            o
        }
    }

    /// The surface seen by a ray of direction `d` at `hit`.
    pub fn at(&self, scene: &Scene, hit: &Hit, d: DVec3) -> SurfacePoint {
        // A plain Lambertian mesh: what `evaluated_at` gives, known in advance.
        if hit.instance.is_none()
            && let Some(albedo) = self.plain[hit.mesh]
        {
            let ng = if hit.ng.dot(d) > 0.0 { -hit.ng } else { hit.ng };
            return SurfacePoint {
                p: hit.p,
                ng,
                ns: ng,
                offset: hit.offset,
                bsdf: Bsdf::Diffuse(DiffuseBsdf { albedo, ns: ng }),
                mesh: hit.mesh,
                tri: hit.tri,
                instance: None,
            };
        }
        self.evaluated_at(scene, hit, d)
    }

    /// The geometric normal facing against `d` and the shading normal (interpolated
    /// `normals`, through the instance's inverse transpose) on its side.
    #[inline]
    fn normals(&self, scene: &Scene, hit: &Hit, d: DVec3) -> (DVec3, DVec3) {
        let mesh = &scene.meshes[hit.mesh];
        let (b1, b2) = (hit.bary.x, hit.bary.y);
        let b0 = 1.0 - b1 - b2;
        let interp3 = |c: &[DVec3; 3]| b0 * c[0] + b1 * c[1] + b2 * c[2];
        let ng = if hit.ng.dot(d) > 0.0 { -hit.ng } else { hit.ng };
        let mut ns = match &mesh.normals {
            Some(n) => match hit.instance {
                None => interp3(&n[hit.tri]).normalize_or_zero(),
                Some(i) => {
                    let m = self.instance_normal[i];
                    interp3(&n[hit.tri].map(|v| (m * v).normalize_or_zero())).normalize_or_zero()
                }
            },
            None => DVec3::ZERO,
        };
        if ns == DVec3::ZERO || !ns.is_finite() {
            ns = ng;
        } else if ns.dot(ng) < 0.0 {
            ns = -ns;
        }
        (ns, ng)
    }

    /// What a MaterialX graph reads at a hit: position, normals, the tangent `∂p/∂s` made
    /// orthogonal to `ns` (any tangent without texture coordinates), `st`, the graph's
    /// primvars and the viewer's side (`entering`: the hit is on the front of the surface).
    fn context<'a>(
        &self,
        scene: &Scene,
        hit: &Hit,
        at: &'a Lookup,
        g: &GraphMaterial,
        (ns, ng): (DVec3, DVec3),
        wo: DVec3,
    ) -> ShadingContext<'a> {
        let frame = g
            .tangent
            .then(|| self.dpds(scene, hit))
            .flatten()
            .and_then(|(dpds, dpdt)| {
                let t = (dpds - ns * ns.dot(dpds)).normalize_or_zero();
                let b = ns.cross(t);
                (t != DVec3::ZERO && t.is_finite())
                    .then_some((t, if b.dot(dpdt) < 0.0 { -b } else { b }))
            });
        let (t, b) = frame.unwrap_or_else(|| {
            let t = ns.any_orthonormal_vector();
            (t, ns.cross(t))
        });
        ShadingContext {
            p: hit.p,
            n: ns,
            ng,
            t,
            b,
            uv: at.st,
            primvars: at.primvars.get(g.primvar0..).unwrap_or(&[]),
            wo,
            entering: !hit.back,
        }
    }

    /// [`Materials::at`] with every input evaluated at the hit (normals, primvars, textures).
    fn evaluated_at(&self, scene: &Scene, hit: &Hit, d: DVec3) -> SurfacePoint {
        let mesh = &scene.meshes[hit.mesh];
        let (b1, b2) = (hit.bary.x, hit.bary.y);
        let b0 = 1.0 - b1 - b2;
        let interp3 = |c: &[DVec3; 3]| b0 * c[0] + b1 * c[1] + b2 * c[2];
        let (mut ns, ng) = self.normals(scene, hit, d);
        let shader = self.material_of(scene, hit);
        let at = self.lookup(scene, hit);
        // Each branch builds the point in place.
        let point = |ns: DVec3, bsdf: Bsdf| SurfacePoint {
            p: hit.p,
            ng,
            ns,
            offset: hit.offset,
            bsdf,
            mesh: hit.mesh,
            tri: hit.tri,
            instance: hit.instance,
        };
        if !self.no_response[hit.mesh]
            && let Some(g) = shader.and_then(|m| m.graph.as_deref())
        {
            // An interpolated normal turned away from the viewer shades with the geometric
            // one (near silhouettes, where microfacet closures have no value: black spots).
            if ns.dot(-d) <= 0.0 {
                ns = ng;
            }
            let shaded = g
                .shader
                .eval(&self.context(scene, hit, &at, g, (ns, ng), -d));
            // The shading normal is the closures' (a normal map's, through `normalmap`): the
            // first closure's normal where it faces the viewer on the viewer's side.
            if let Some(n) = shaded.bsdf.nodes().find_map(closure_normal)
                && n.dot(-d) > 0.0
                && n.dot(ng) > 0.0
            {
                ns = n;
            }
            return point(
                ns,
                Bsdf::Graph(Box::new(GraphBsdf {
                    bsdf: shaded.bsdf.prepare(),
                    ns,
                    transmits: g.transmits,
                })),
            );
        }
        // (a graph's material never reads its USD-side `diffuseColor`)
        let albedo = if self.no_response[hit.mesh] {
            DVec3::ZERO
        } else {
            clamped_albedo(match (self.mesh_reflectance[hit.mesh], shader) {
                (Some(c), _) => c,
                (None, Some(m)) => m.diffuse.eval(&at),
                (None, None) => match &mesh.colors {
                    Some(c) => interp3(&c[hit.tri]),
                    None => DVec3::ONE,
                },
            })
        };
        point(ns, Bsdf::Diffuse(DiffuseBsdf { albedo, ns }))
    }

    /// The world-space derivatives `(∂p/∂s, ∂p/∂t)` of the hit triangle's position in its
    /// texture coordinates (`None` without texture coordinates or where they are degenerate).
    #[inline]
    fn dpds(&self, scene: &Scene, hit: &Hit) -> Option<(DVec3, DVec3)> {
        let mesh = &scene.meshes[hit.mesh];
        let uv = mesh.uvs.as_ref()?;
        let [i0, i1, i2] = mesh.triangles[hit.tri].map(|i| i as usize);
        let (p0, p1, p2) = (
            mesh.positions.get(i0)?,
            mesh.positions.get(i1)?,
            mesh.positions.get(i2)?,
        );
        let c = &uv[hit.tri];
        let (dp1, dp2) = (*p1 - *p0, *p2 - *p0);
        let (du1, du2) = (c[1] - c[0], c[2] - c[0]);
        let det = du1.x * du2.y - du1.y * du2.x;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let mut dpds = (du2.y * dp1 - du1.y * dp2) / det;
        let mut dpdt = (du1.x * dp2 - du2.x * dp1) / det;
        if let Some(i) = hit.instance {
            let m = self.instance_linear[i];
            dpds = m * dpds;
            dpdt = m * dpdt;
        }
        Some((dpds, dpdt))
    }
}

impl InputLoader {
    /// The shader of material `m` from its MaterialX graph `g`: compiled once; a graph that
    /// folds to a constant Lambertian takes the renderer's plain diffuse path (with a
    /// `wavelength:reflectance` replacing its colour, as for any diffuse surface); a
    /// UsdPreviewSurface keeps its USD-side opacity and emission (`diffuse`, `emission`
    /// prepared by the caller from the same inputs).
    fn graph_shader(
        &mut self,
        m: &lux_usd::Material,
        g: &lux_usd::shading::ShadingGraph,
        network: Option<&lux_usd::shading::Network>,
        diffuse: Param,
        emission: Option<Param>,
    ) -> Result<Shader, RenderError> {
        let reflectance = !m.spectral.is_empty();
        // A `wavelength:reflectance` replaces a UsdPreviewSurface's `diffuseColor`: the
        // network flattened again with that colour.
        let respectral = match (&diffuse, network) {
            (Param::Value(c), Some(net)) if reflectance && m.preview => {
                let mut net = net.clone();
                let surface = net.surface.as_ref().map(|c| c.node);
                if let Some(node) = surface.and_then(|k| net.nodes.get_mut(k)) {
                    node.inputs.retain(|i| i.name != "diffuseColor");
                    node.inputs.push(lux_usd::shading::NetInput {
                        name: "diffuseColor".to_owned(),
                        ty: Some(lux_usd::shading::ValueType::Color3),
                        source: lux_usd::shading::NetSource::Value(
                            lux_usd::shading::Value::Numbers(c.to_array().to_vec()),
                        ),
                    });
                }
                Some(lux_usd::shading::flatten(&net))
            }
            _ => None,
        };
        let g = respectral.as_ref().unwrap_or(g);
        let shader = GraphShader::compile(g, &mut self.graph_textures, &mut self.warnings);
        // UsdPreviewSurface: `opacity` / `opacityThreshold` as the USD inputs say (the graph's
        // surface opacity is the same input).
        let opacity = if m.preview {
            let o = self.float(&m.path, "opacity", &m.opacity, 1.0)?;
            let opaque = match &o {
                Param::Value(v) if m.opacity_threshold > 0.0 => v.x >= m.opacity_threshold,
                Param::Value(v) => v.x >= 1.0,
                Param::Texture(_) | Param::Primvar { .. } => false,
            };
            (!opaque).then_some(o)
        } else {
            None
        };
        if let Some(albedo) = shader.constant_lambert() {
            let diffuse = match (&diffuse, reflectance) {
                (Param::Value(c), true) => Param::Value(*c),
                _ => Param::Value(albedo),
            };
            return Ok(Shader {
                diffuse,
                opacity,
                threshold: m.opacity_threshold,
                emission,
                primvars: self.primvars.clone(),
                graph: None,
            });
        }
        if reflectance && !m.preview {
            self.warnings.push(format!(
                "{}: wavelength:reflectance is not applied to a MaterialX graph that is not a \
                 constant Lambertian; its own colours shade",
                m.path
            ));
        }
        // The USD-side readers' primvars (opacity, emission) first, then the graph's, which
        // reads its slots from `primvar0` on (a missing one is NaN: the node's default).
        let mut primvars = self.primvars.clone();
        let primvar0 = primvars.len();
        primvars.extend(
            shader
                .primvars()
                .iter()
                .take(MAX_PRIMVARS - primvar0)
                .map(|n| (n.clone(), DVec4::NAN)),
        );
        if primvar0 + shader.primvars().len() > MAX_PRIMVARS {
            self.warnings.push(format!(
                "{}: reads {} primvars; lux reads the first {MAX_PRIMVARS}, the others take \
                 their defaults",
                m.path,
                shader.primvars().len()
            ));
        }
        let emits = !m.preview && shader.constant_emission() != Some(DVec3::ZERO);
        let transparent = !m.preview && shader.constant_opacity() != Some(1.0);
        let transmits = shader.may_transmit();
        let tangent = shader.reads_tangent();
        Ok(Shader {
            diffuse,
            opacity,
            threshold: if m.preview { m.opacity_threshold } else { 0.0 },
            emission: if m.preview { emission } else { None },
            primvars,
            graph: Some(Box::new(GraphMaterial {
                shader,
                primvar0,
                transmits,
                tangent,
                emits,
                transparent,
            })),
        })
    }

    /// The shader of material `m` (`unit`: the scene's wavelength unit for spectral
    /// reflectances) as `surfaces` shades it: its inputs read, textures loaded once per file.
    fn material_shader(
        &mut self,
        m: &lux_usd::Material,
        built: Option<&Built>,
        unit: lux_spectral::WavelengthUnit,
        surfaces: SurfaceModel,
    ) -> Result<Shader, RenderError> {
        let path = m.path.as_str();
        let grey = lux_usd::material::DEFAULT_DIFFUSE;
        // The primvars its readers read, by slot.
        self.primvars = m
            .primvar_names()
            .into_iter()
            .take(MAX_PRIMVARS)
            .map(|n| {
                let fallback = m
                    .primvar_readers()
                    .into_iter()
                    .find(|(_, p)| p.name == n)
                    .map_or(DVec4::ZERO, |(_, p)| p.fallback);
                (n.to_owned(), fallback)
            })
            .collect();
        // LTESpectralAPI: a spectral reflectance on the surface shader replaces diffuseColor
        // (one that lux-spectral refuses is a warning, and diffuseColor is used).
        // A graph that shades the material reads its `diffuseColor` through its own image
        // nodes: the USD-side input is then never looked up (its texture not decoded).
        let (network, graph) = shading_graph(m, built);
        let graph = graph.filter(|g| surfaces == SurfaceModel::Preview && g.surface.is_some());
        let read = graph.is_none();
        let diffuse = match reflectance_albedo(path, &m.spectral, unit) {
            Ok(Some(c)) => Param::Value(c),
            Ok(None) => self.colour(path, "diffuseColor", &m.diffuse, grey, read)?,
            Err(e) if self.files.strict => return Err(e),
            Err(e) => {
                self.warnings
                    .push(format!("{e}; diffuseColor is used instead"));
                self.colour(path, "diffuseColor", &m.diffuse, grey, read)?
            }
        };
        let emission = match (&m.emissive_primvar, m.emissive_texture.as_deref()) {
            (Some(p), _) => Some(self.primvar(p)),
            (None, t) => self
                .texture(path, "emissiveColor", DVec3::ZERO, t)?
                .map(Param::Texture),
        };
        let primvars = self.primvars.clone();
        // A graph whose surface shader MaterialX does not define (a `PxrSurface`) has no
        // surface: such a material stays the default grey, as lux-usd warned.
        if let Some(g) = graph {
            return self.graph_shader(m, g, network, diffuse, emission);
        }
        Ok(Shader {
            diffuse,
            opacity: None,
            threshold: 0.0,
            emission,
            primvars,
            graph: None,
        })
    }
}

/// The network and graph of a UsdPreviewSurface built in code ([`built_graph`]).
type Built = (lux_usd::shading::Network, lux_usd::shading::ShadingGraph);

/// A UsdPreviewSurface built in code (no network read from a stage) shades as the graph of
/// the network its fields describe (`Material::preview_network`); `None` for any other
/// material, or when `surfaces` is not [`SurfaceModel::Preview`].
fn built_graph(m: &lux_usd::Material, surfaces: SurfaceModel) -> Option<Built> {
    (m.graph.is_none() && m.preview && surfaces == SurfaceModel::Preview).then(|| {
        let net = m.preview_network();
        let g = lux_usd::shading::flatten(&net);
        (net, g)
    })
}

/// The network and graph that shade `m`: those `built` from its fields, else its own.
fn shading_graph<'a>(
    m: &'a lux_usd::Material,
    built: Option<&'a Built>,
) -> (
    Option<&'a lux_usd::shading::Network>,
    Option<&'a lux_usd::shading::ShadingGraph>,
) {
    match built {
        Some((net, g)) => (Some(net), Some(g)),
        None => (m.network.as_deref(), m.graph.as_deref()),
    }
}

/// Prepares material inputs, reading each texture file once.
struct InputLoader {
    /// The `UsdUVTexture` files, and whether an unreadable input is an error
    /// ([`TextureFiles::strict`]).
    files: TextureFiles,
    /// The textures of MaterialX graphs (per file and colour space).
    graph_textures: graph::TextureCache,
    warnings: Vec<String>,
    /// The primvars of the material being prepared, by slot (name, fallback).
    primvars: Vec<(String, DVec4)>,
}

impl InputLoader {
    /// Decodes, in parallel, the texture files that preparing the materials of `scene` in
    /// order would read one after another: the `UsdUVTexture` files of their USD inputs
    /// (unless they are decoded on first use) and the `image` files of their graphs. The
    /// results are those the reads in order would give; a file of a graph branch that
    /// compiling folds away may be decoded without being used.
    fn prefetch(&mut self, scene: &Scene, built: &[Option<Built>], surfaces: SurfaceModel) {
        let mut files: Vec<PathBuf> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        let mut graphs = Vec::new();
        for (m, b) in scene.materials.iter().zip(built) {
            // The graph that shades the material (UsdPreviewSurface model, a graph with a
            // surface), whose shader also reads a UsdPreviewSurface's `opacity`.
            let graph = match shading_graph(m, b.as_ref()) {
                (_, Some(g)) if surfaces == SurfaceModel::Preview && g.surface.is_some() => Some(g),
                _ => None,
            };
            let opacity = graph.and(m.preview.then(|| m.opacity.texture()).flatten());
            // (where a graph shades, it reads `diffuseColor` through its own image nodes)
            let diffuse = m.diffuse.texture().filter(|_| graph.is_none());
            let emissive = m.emissive_texture.as_deref();
            for t in [diffuse, opacity, emissive].into_iter().flatten() {
                if let Some(p) = t.file.as_ref().and_then(|f| f.resolved.as_ref())
                    && !self.files.on_first_use
                    && !self.files.files.contains_key(p)
                    && seen.insert(p)
                {
                    files.push(p.clone());
                }
            }
            graphs.extend(graph);
        }
        use rayon::prelude::*;
        let loaded: Vec<_> = files
            .into_par_iter()
            .map(|p| {
                let t = crate::assets::load_texture(&p).map_err(|e| e.to_string());
                (
                    p.clone(),
                    Arc::new(crate::assets::TextureFile::decoded(p, t)),
                )
            })
            .collect();
        self.files.files.extend(loaded);
        self.graph_textures.prefetch(&graphs);
    }

    /// The texture `t` feeding input `name` of material `path` (its fallback, or `default`,
    /// when the file cannot be read: [`texture_shader`]); `read`: whether a lookup reads it.
    fn shader(
        &mut self,
        path: &str,
        name: &str,
        default: DVec3,
        t: &TextureInput,
        read: bool,
    ) -> Result<Param, RenderError> {
        texture_shader(
            path,
            name,
            default,
            t,
            &mut self.files,
            read,
            &mut self.warnings,
        )
    }

    /// A colour input of material `path`; `read`: whether a lookup reads it.
    fn colour(
        &mut self,
        path: &str,
        name: &str,
        input: &Input<DVec3>,
        default: DVec3,
        read: bool,
    ) -> Result<Param, RenderError> {
        match input {
            Input::Value(v) => Ok(Param::Value(*v)),
            Input::Texture(t) => self.shader(path, name, default, t, read),
            Input::Primvar(p) => Ok(self.primvar(p)),
        }
    }

    /// A primvar reader of the material being prepared: its slot.
    fn primvar(&mut self, p: &lux_usd::PrimvarInput) -> Param {
        match self.primvars.iter().position(|(n, _)| *n == p.name) {
            Some(slot) => Param::Primvar {
                slot,
                components: p.components,
            },
            // Beyond MAX_PRIMVARS distinct primvars (more than the inputs there are).
            None => Param::Value(p.fallback.truncate()),
        }
    }

    /// A float input of material `path` (kept in `x`).
    fn float(
        &mut self,
        path: &str,
        name: &str,
        input: &Input<f64>,
        default: f64,
    ) -> Result<Param, RenderError> {
        match input {
            Input::Value(v) => Ok(Param::Value(DVec3::splat(*v))),
            Input::Texture(t) => self.shader(path, name, DVec3::splat(default), t, true),
            Input::Primvar(p) => Ok(self.primvar(p)),
        }
    }

    /// An input read only from a texture (`emissiveColor` as a texture, `normal`): the texture,
    /// or `None` without one or when its file cannot be read (no glow, no perturbation; the
    /// warning names the file, an error when strict).
    fn texture(
        &mut self,
        path: &str,
        name: &str,
        default: DVec3,
        t: Option<&TextureInput>,
    ) -> Result<Option<TextureShader>, RenderError> {
        Ok(
            match t
                .map(|t| self.shader(path, name, default, t, true))
                .transpose()?
            {
                Some(Param::Texture(s)) => Some(s),
                _ => None,
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Geometry;
    use lux_usd::{Input, Material, Mesh};

    /// A unit quad at height `y`, front side up.
    fn quad(path: &str, x: f64, y: f64) -> Mesh {
        Mesh::new(
            path,
            vec![
                DVec3::new(x, y, 0.0),
                DVec3::new(x, y, 1.0),
                DVec3::new(x + 1.0, y, 1.0),
                DVec3::new(x + 1.0, y, 0.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    /// A plain mesh's surface, taken without evaluating it, is what evaluating it gives, bit
    /// for bit, from either side — no material (white), an untextured `diffuseColor` in and
    /// out of `[0, 1]` or not finite — and meshes with normals, `displayColor` or a
    /// UsdPreviewSurface are not plain.
    #[test]
    fn plain_surfaces_are_what_evaluating_them_gives() {
        let mut s = Scene::empty("code.usda");
        let lambert = |path: &str, c: DVec3| Material {
            diffuse: Input::Value(c),
            ..Material::new(path)
        };
        s.materials
            .push(lambert("/M0", DVec3::new(0.25, 0.5, 0.75)));
        s.materials.push(lambert("/M1", DVec3::new(1.5, -0.5, 0.5)));
        s.materials
            .push(lambert("/M2", DVec3::new(0.5, f64::NAN, 0.5)));
        s.materials.push(Material {
            preview: true,
            ..lambert("/M3", DVec3::splat(0.5))
        });
        let mut meshes = Vec::new();
        for (i, material) in [None, Some(0), Some(1), Some(2), Some(3), None, Some(0)]
            .into_iter()
            .enumerate()
        {
            let mut m = quad(&format!("/Q{i}"), 2.0 * i as f64, 0.0);
            m.material = material;
            m.double_sided = true;
            meshes.push(m);
        }
        // (one with normals, one with colours)
        let tilt = DVec3::new(0.1, 1.0, 0.0).normalize();
        meshes[5].colors = Some(vec![[DVec3::new(0.2, 0.4, 0.6); 3]; 2]);
        meshes[6].normals = Some(vec![[tilt; 3]; 2]);
        s.meshes = meshes;
        let g = Geometry::new(&s);
        for surfaces in [SurfaceModel::Lambert, SurfaceModel::Preview] {
            let m = Materials::with_policy(&s, false, surfaces).unwrap();
            let preview = surfaces == SurfaceModel::Preview;
            let plain: Vec<bool> = m.plain.iter().map(Option::is_some).collect();
            assert_eq!(
                plain,
                [true, true, true, true, !preview, false, false],
                "{surfaces:?}"
            );
            for i in 0..7 {
                for (y, d) in [(3.0, DVec3::NEG_Y), (-3.0, DVec3::Y)] {
                    let o = DVec3::new(2.0 * i as f64 + 0.3, y, 0.6);
                    let hit = g.intersect(&s, o, d, 0.0, 10.0).unwrap();
                    assert_eq!(hit.mesh, i);
                    let (fast, full) = (m.at(&s, &hit, d), m.evaluated_at(&s, &hit, d));
                    assert_eq!(
                        format!("{fast:?}"),
                        format!("{full:?}"),
                        "mesh {i}, {surfaces:?}"
                    );
                }
            }
        }
    }

    /// A `diffuseColor` read through a `UsdPrimvarReader_float3` is the primvar interpolated at
    /// the hit (red, green, blue corners at barycentric (0.2, 0.3, 0.5): (0.2, 0.3, 0.5)), the reader's
    /// `fallback` where the gprim has no such primvar, and the mesh's `displayColor` where the
    /// reader reads `displayColor` (as curves and points keep it).
    #[test]
    fn primvar_readers_shade_with_the_primvar() {
        let stage = |varname: &str, primvars: &str| {
            format!(
                r#"#usda 1.0
def Material "M" {{
    token outputs:surface.connect = </M/S.outputs:surface>
    def Shader "S" {{
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor.connect = </M/C.outputs:result>
        token outputs:surface
    }}
    def Shader "C" {{
        uniform token info:id = "UsdPrimvarReader_float3"
        token inputs:varname = "{varname}"
        float3 inputs:fallback = (0.5, 0.25, 0.125)
        float3 outputs:result
    }}
}}
def Mesh "T" (prepend apiSchemas = ["MaterialBindingAPI"]) {{
    rel material:binding = </M>
    uniform token subdivisionScheme = "none"
    int[] faceVertexCounts = [3]
    int[] faceVertexIndices = [0, 1, 2]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 0, -1)]
    {primvars}
}}
"#
            )
        };
        let colours = "color3f[] primvars:tint = [(1, 0, 0), (0, 1, 0), (0, 0, 1)] (interpolation = \"vertex\")";
        let cases = [
            (stage("tint", colours), DVec3::new(0.2, 0.3, 0.5)),
            (stage("tint", ""), DVec3::new(0.5, 0.25, 0.125)),
            (
                stage(
                    "displayColor",
                    "color3f[] primvars:displayColor = [(0.75, 0.5, 0.25)] (interpolation = \"constant\")",
                ),
                DVec3::new(0.75, 0.5, 0.25),
            ),
        ];
        for (text, want) in cases {
            let s =
                lux_usd::load_usda_str(&text, lux_usd::Time::Start, &Default::default()).unwrap();
            let g = Geometry::new(&s);
            let m = Materials::with_policy(&s, false, SurfaceModel::Lambert).unwrap();
            // The point 0.3 of the way to corner 1 and 0.5 to corner 2: (0.3, 0, −0.5).
            let d = DVec3::NEG_Y;
            let hit = g
                .intersect(&s, DVec3::new(0.3, 1.0, -0.5), d, 0.0, 10.0)
                .unwrap();
            let Bsdf::Diffuse(b) = m.at(&s, &hit, d).bsdf else {
                panic!("not Lambertian")
            };
            f32_close(b.albedo, want);
        }
    }

    fn f32_close(a: DVec3, b: DVec3) {
        assert!((a - b).abs().max_element() < 1e-6, "{a} ≠ {b}");
    }

    /// A `UsdUVTexture` of `file` (`None`: no file), its rgb connected.
    fn texture_input(file: Option<&std::path::Path>) -> Box<TextureInput> {
        Box::new(TextureInput {
            shader: "/M/Tex".to_owned(),
            file: file.map(|f| lux_usd::AssetRef {
                authored: f.display().to_string(),
                resolved: Some(f.to_path_buf()),
            }),
            st_primvar: "st".to_owned(),
            st_fallback: DVec2::ZERO,
            transform: None,
            scale: DVec4::ONE,
            bias: DVec4::ZERO,
            fallback: DVec4::new(0.0, 0.0, 0.0, 1.0),
            fallback_authored: false,
            wrap_s: lux_usd::Wrap::Repeat,
            wrap_t: lux_usd::Wrap::Repeat,
            source_color_space: lux_usd::SourceColorSpace::Auto,
            output: "rgb".to_owned(),
        })
    }

    /// Decoded on first use, a texture gives the texels decoded up front, and nothing is
    /// decoded before a lookup needs it. A file whose header reads but whose data is
    /// corrupt gives, in both modes, the input's default where it is read, with the same
    /// warning: at once up front, after the lookup (`late_warnings`) on first use.
    #[test]
    fn textures_decoded_on_first_use_are_those_decoded_up_front() {
        let dir = std::env::temp_dir().join(format!("lux_first_use_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (good, bad) = (dir.join("ramp.png"), dir.join("cut.png"));
        image::RgbImage::from_fn(4, 2, |x, y| {
            image::Rgb([60 * x as u8, 200 - 90 * y as u8, 7])
        })
        .save(&good)
        .unwrap();
        // Every chunk up to the image data read whole, then the data cut short.
        let bytes = std::fs::read(&good).unwrap();
        let idat = bytes.windows(4).position(|w| w == b"IDAT").unwrap();
        std::fs::write(&bad, &bytes[..idat + 6]).unwrap();
        let mut s = Scene::empty("code.usda");
        for (name, f) in [("/G", &good), ("/B", &bad)] {
            s.materials.push(Material {
                diffuse: Input::Texture(texture_input(Some(f))),
                ..Material::new(name)
            });
        }
        let diffuse = |m: &Materials, k: usize| match &m.materials[k].diffuse {
            Param::Texture(t) => t.clone(),
            p => panic!("material {k}: {p:?}"),
        };
        let up =
            Materials::prepare(&s, false, SurfaceModel::Lambert, TextureDecoding::UpFront).unwrap();
        let lazy = Materials::prepare(
            &s,
            false,
            SurfaceModel::Lambert,
            TextureDecoding::OnFirstUse,
        )
        .unwrap();
        // Up front: the corrupt file is its fallback (0.18 grey) with a warning at once.
        assert_eq!(up.warnings.len(), 1, "{:?}", up.warnings);
        assert!(up.warnings[0].contains("cut.png"), "{}", up.warnings[0]);
        assert!(matches!(up.materials[1].diffuse, Param::Value(v) if v == DVec3::splat(0.18)));
        // On first use: headers only, no warning yet, nothing decoded.
        assert!(lazy.warnings.is_empty(), "{:?}", lazy.warnings);
        let (g, b) = (diffuse(&lazy, 0), diffuse(&lazy, 1));
        assert!(!g.file().is_decoded() && !b.file().is_decoded());
        assert_eq!(lazy.late_warnings().count(), 0);
        let reference = diffuse(&up, 0);
        for st in [(0.1, 0.2), (0.37, 0.9), (0.875, 0.25), (1.6, -0.3)] {
            let st = DVec2::new(st.0, st.1);
            assert_eq!(g.eval(st), reference.eval(st), "{st}");
        }
        assert!(g.file().is_decoded() && !b.file().is_decoded());
        assert_eq!(b.eval(DVec2::new(0.5, 0.5)), DVec3::splat(0.18));
        assert!(b.file().failure().is_some());
        assert_eq!(lazy.late_warnings().collect::<Vec<_>>(), up.warnings);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Where its graph shades a UsdPreviewSurface (the UsdPreviewSurface model), the graph's
    /// own image node reads `diffuseColor`: the USD-side input's file is opened (its header
    /// checked) but never decoded, even when textures are decoded up front; with Lambertian
    /// surfaces the same input is decoded up front and read.
    #[test]
    fn a_diffuse_texture_its_graph_reads_is_not_decoded_twice() {
        let dir = std::env::temp_dir().join(format!("lux_graph_reads_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("albedo.png");
        image::RgbImage::from_pixel(2, 2, image::Rgb([200, 120, 40]))
            .save(&file)
            .unwrap();
        let mut s = Scene::empty("code.usda");
        s.materials.push(Material {
            preview: true,
            diffuse: Input::Texture(texture_input(Some(&file))),
            ..Material::new("/M")
        });
        for (surfaces, decoded) in [
            (SurfaceModel::Preview, false),
            (SurfaceModel::Lambert, true),
        ] {
            let m = Materials::prepare(&s, false, surfaces, TextureDecoding::UpFront).unwrap();
            assert!(m.warnings.is_empty(), "{:?}", m.warnings);
            assert_eq!(m.materials[0].graph.is_some(), !decoded, "{surfaces:?}");
            match &m.materials[0].diffuse {
                Param::Texture(t) => assert_eq!(t.file().is_decoded(), decoded, "{surfaces:?}"),
                p => panic!("{surfaces:?}: {p:?}"),
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// What preparing a UsdPreviewSurface reads is decoded ahead: its `diffuseColor` texture
    /// where no graph shades it (Lambertian surfaces; a graph reads it through its own image
    /// nodes), its `opacity` texture only where its graph shades it (the UsdPreviewSurface
    /// model); a file that cannot be read keeps its error.
    #[test]
    fn prefetch_decodes_the_textures_the_materials_read() {
        let dir = std::env::temp_dir().join(format!("lux_prefetch_m_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (white, grey) = (dir.join("white.png"), dir.join("grey.png"));
        for (path, code) in [(&white, 255), (&grey, 90)] {
            image::GrayImage::from_pixel(2, 2, image::Luma([code]))
                .save(path)
                .unwrap();
        }
        let mut s = Scene::empty("code.usda");
        s.materials.push(Material {
            preview: true,
            diffuse: Input::Texture(texture_input(Some(&white))),
            opacity: Input::Texture(texture_input(Some(&grey))),
            ..Material::new("/M")
        });
        s.materials.push(Material {
            diffuse: Input::Texture(texture_input(Some(&dir.join("gone.png")))),
            ..Material::new("/N")
        });
        for (surfaces, want) in [
            (SurfaceModel::Lambert, vec![&white]),
            (SurfaceModel::Preview, vec![&grey]),
        ] {
            let mut ld = InputLoader {
                files: TextureFiles::default(),
                graph_textures: graph::TextureCache::new(),
                warnings: Vec::new(),
                primvars: Vec::new(),
            };
            let built: Vec<_> = s
                .materials
                .iter()
                .map(|m| built_graph(m, surfaces))
                .collect();
            ld.prefetch(&s, &built, surfaces);
            let mut got: Vec<_> = (ld.files.files.iter())
                .filter(|(_, f)| f.get().is_some())
                .map(|(p, _)| p)
                .collect();
            let gone = &ld.files.files[&dir.join("gone.png")];
            assert!(gone.failure().is_some(), "{surfaces:?}");
            got.sort();
            let mut want = want.clone();
            want.sort();
            assert_eq!(got, want, "{surfaces:?}");
            assert!(ld.warnings.is_empty());
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
