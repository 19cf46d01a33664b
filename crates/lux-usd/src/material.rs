//! `material:binding` → the UsdPreviewSurface inputs, each a value or a `UsdUVTexture` (read
//! through a `UsdPrimvarReader_float2` and an optional `UsdTransform2d`).

use crate::error::{LoadError, WarningKind};
use crate::reader::{AssetRef, Reader, is_prim_path, is_property_name};
use crate::shade_network::read_network_terminal;
use crate::spectral::{SurfaceSpectral, read_surface_spectral};
use glam::{DVec2, DVec3, DVec4};
use openusd::usd::Prim;

/// The UsdPreviewSurface default `diffuseColor`.
pub const DEFAULT_DIFFUSE: DVec3 = DVec3::splat(0.18);
/// Longest chain of connections followed before giving up (cycles, deep node graphs).
const MAX_CONNECTION_DEPTH: usize = 16;

/// A `UsdUVTexture` feeding a UsdPreviewSurface input.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureInput {
    /// The texture shader's prim path.
    pub shader: String,
    /// `inputs:file`.
    pub file: Option<AssetRef>,
    /// The primvar read by the `UsdPrimvarReader_float2` on `inputs:st` (default `"st"`).
    pub st_primvar: String,
    /// That reader's `inputs:fallback`: the coordinates where the gprim lacks the primvar
    /// (default (0, 0)).
    pub st_fallback: DVec2,
    /// A `UsdTransform2d` between the primvar reader and `inputs:st`.
    pub transform: Option<Transform2d>,
    /// `inputs:scale` (default (1, 1, 1, 1)).
    pub scale: DVec4,
    /// `inputs:bias` (default 0).
    pub bias: DVec4,
    /// `inputs:fallback` (default (0, 0, 0, 1)).
    pub fallback: DVec4,
    /// Whether `inputs:fallback` is authored (a renderer may prefer the surface input's own
    /// fallback for an unreadable file when the texture's is only the schema default).
    pub fallback_authored: bool,
    /// `inputs:wrapS` (default `useMetadata`).
    pub wrap_s: Wrap,
    /// `inputs:wrapT` (default `useMetadata`).
    pub wrap_t: Wrap,
    /// `inputs:sourceColorSpace` (default `auto`).
    pub source_color_space: SourceColorSpace,
    /// The output connected (`rgb`, `r`, …).
    pub output: String,
}

/// `UsdUVTexture.inputs:wrapS` / `wrapT`: texture coordinates outside [0, 1].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// `black`: the fallback outside.
    Black,
    /// `clamp`: the edge texel.
    Clamp,
    /// `repeat`: tiled.
    Repeat,
    /// `mirror`: tiled, every other tile mirrored.
    Mirror,
    /// `useMetadata` (default): the texture file's own wrap metadata; lux's image readers carry
    /// none, so it means `repeat` (what Hydra Storm does without metadata).
    #[default]
    UseMetadata,
}

impl Wrap {
    /// The schema token.
    pub fn token(self) -> &'static str {
        match self {
            Wrap::Black => "black",
            Wrap::Clamp => "clamp",
            Wrap::Repeat => "repeat",
            Wrap::Mirror => "mirror",
            Wrap::UseMetadata => "useMetadata",
        }
    }

    /// The schema token's mode; `None` for an unknown token.
    pub fn parse(token: &str) -> Option<Wrap> {
        Some(match token {
            "black" => Wrap::Black,
            "clamp" => Wrap::Clamp,
            "repeat" => Wrap::Repeat,
            "mirror" => Wrap::Mirror,
            "useMetadata" => Wrap::UseMetadata,
            _ => return None,
        })
    }
}

/// `UsdUVTexture.inputs:sourceColorSpace`: how texel values are decoded.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SourceColorSpace {
    /// `auto` (default): by the file — 8-bit images are sRGB-encoded, float images linear.
    #[default]
    Auto,
    /// `raw`: values as stored (no transfer function).
    Raw,
    /// `sRGB`: sRGB-encoded.
    Srgb,
}

impl SourceColorSpace {
    /// The schema token.
    pub fn token(self) -> &'static str {
        match self {
            SourceColorSpace::Auto => "auto",
            SourceColorSpace::Raw => "raw",
            SourceColorSpace::Srgb => "sRGB",
        }
    }

    /// The schema token's colour space; `None` for an unknown token.
    pub fn parse(token: &str) -> Option<SourceColorSpace> {
        Some(match token {
            "auto" => SourceColorSpace::Auto,
            "raw" => SourceColorSpace::Raw,
            "sRGB" => SourceColorSpace::Srgb,
            _ => return None,
        })
    }
}

/// A UsdPreviewSurface input: an authored (or default) value, a `UsdUVTexture` output, or a
/// primvar read by a `UsdPrimvarReader_*`.
#[derive(Clone, Debug, PartialEq)]
pub enum Input<T> {
    /// A constant.
    Value(T),
    /// A texture lookup (the texture's connected output: `rgb` for colours, `r`/`g`/`b`/`a`
    /// for floats).
    Texture(Box<TextureInput>),
    /// A primvar of the gprim (`UsdPrimvarReader_float`, `_float2`, `_float3`, `_float4`,
    /// `_int`, `_normal`, `_point`, `_vector`).
    Primvar(Box<PrimvarInput>),
}

impl<T: Copy> Input<T> {
    /// The constant, if the input is one.
    pub fn value(&self) -> Option<T> {
        match self {
            Input::Value(v) => Some(*v),
            _ => None,
        }
    }

    /// The texture, if the input is one.
    pub fn texture(&self) -> Option<&TextureInput> {
        match self {
            Input::Texture(t) => Some(t),
            _ => None,
        }
    }

    /// The primvar reader, if the input is one.
    pub fn primvar(&self) -> Option<&PrimvarInput> {
        match self {
            Input::Primvar(p) => Some(p),
            _ => None,
        }
    }
}

/// A `UsdPrimvarReader_*` feeding a UsdPreviewSurface input: the gprim's primvar `varname`,
/// interpolated over the surface as its `interpolation` says, or `fallback` where the gprim
/// has no such primvar (UsdPreviewSurface spec, "Primvar Reader").
#[derive(Clone, Debug, PartialEq)]
pub struct PrimvarInput {
    /// The reader shader's prim path.
    pub shader: String,
    /// Its `info:id` (`UsdPrimvarReader_float3`, …).
    pub id: String,
    /// `inputs:varname` (a token or a string; through interface connections): the primvar
    /// name without `primvars:`.
    pub name: String,
    /// How many components the reader outputs (1 for `_float` and `_int`, 2, 3 or 4).
    pub components: usize,
    /// `inputs:fallback` (schema default 0), padded with zeros to four components.
    pub fallback: DVec4,
}

/// The `UsdPrimvarReader_*` shader ids and their output sizes.
pub const PRIMVAR_READERS: [(&str, usize); 8] = [
    ("UsdPrimvarReader_float", 1),
    ("UsdPrimvarReader_float2", 2),
    ("UsdPrimvarReader_float3", 3),
    ("UsdPrimvarReader_float4", 4),
    ("UsdPrimvarReader_int", 1),
    ("UsdPrimvarReader_normal", 3),
    ("UsdPrimvarReader_point", 3),
    ("UsdPrimvarReader_vector", 3),
];

/// Where a material's diffuse colour comes from (`inputs:diffuseColor`).
pub type Diffuse = Input<DVec3>;

/// `UsdTransform2d` between a `UsdPrimvarReader_float2` and a texture's `inputs:st`:
/// `result = R(rotation) · (in ∘ scale) + translation`, rotation counter-clockwise in degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform2d {
    /// `inputs:rotation` (degrees, default 0).
    pub rotation: f64,
    /// `inputs:scale` (default (1, 1)).
    pub scale: DVec2,
    /// `inputs:translation` (default (0, 0)).
    pub translation: DVec2,
}

impl Default for Transform2d {
    fn default() -> Transform2d {
        Transform2d {
            rotation: 0.0,
            scale: DVec2::ONE,
            translation: DVec2::ZERO,
        }
    }
}

impl Transform2d {
    /// `R(rotation) · (st ∘ scale) + translation`.
    pub fn apply(&self, st: DVec2) -> DVec2 {
        let s = st * self.scale;
        let (sin, cos) = self.rotation.to_radians().sin_cos();
        DVec2::new(cos * s.x - sin * s.y, sin * s.x + cos * s.y) + self.translation
    }
}

/// A bound material: its UsdPreviewSurface inputs (schema defaults where unauthored).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The Material prim path.
    pub path: String,
    /// Whether the surface shader is a UsdPreviewSurface (else every input is its default, with
    /// a warning, and renderers draw the default grey Lambertian).
    pub preview: bool,
    /// `inputs:diffuseColor` (default 0.18 grey).
    pub diffuse: Input<DVec3>,
    /// `inputs:useSpecularWorkflow` (default 0: the metallic workflow).
    pub use_specular_workflow: bool,
    /// `inputs:specularColor` (default black; used by the specular workflow).
    pub specular: Input<DVec3>,
    /// `inputs:metallic` (default 0; used by the metallic workflow).
    pub metallic: Input<f64>,
    /// `inputs:roughness` (default 0.5).
    pub roughness: Input<f64>,
    /// `inputs:clearcoat` (default 0).
    pub clearcoat: Input<f64>,
    /// `inputs:clearcoatRoughness` (default 0.01).
    pub clearcoat_roughness: Input<f64>,
    /// `inputs:ior` (default 1.5): the specular lobe's Fresnel in the metallic workflow.
    pub ior: Input<f64>,
    /// `inputs:opacity` (default 1).
    pub opacity: Input<f64>,
    /// `inputs:opacityThreshold` (default 0: opacity is partial presence; above 0 a cut-out
    /// mask, opacity < threshold fully transparent, else opaque).
    pub opacity_threshold: f64,
    /// `inputs:normal`: a tangent-space normal map (a texture; a constant is the unperturbed
    /// normal and ignored).
    pub normal: Option<Box<TextureInput>>,
    /// Authored inputs lux does not use (`displacement`, `occlusion`, unknown names).
    pub other_inputs: Vec<String>,
    /// Whether the surface asks for transparency or cut-outs (UsdPreviewSurface `opacity`
    /// below 1 or connected, or `opacityThreshold` above 0).
    pub uses_opacity: bool,
    /// LTESpectralAPI inputs of the surface shader (`wavelength:reflectance`,
    /// `wavelength:ior`, scalar `ior`); a `wavelength:reflectance` replaces `diffuseColor`.
    pub spectral: SurfaceSpectral,
    /// UsdPreviewSurface `inputs:emissiveColor` (radiance, nits; default black) when authored
    /// as a value (through interface inputs); 0 when it is a texture.
    pub emissive: DVec3,
    /// `inputs:emissiveColor` from a `UsdUVTexture` (radiance per texel).
    pub emissive_texture: Option<Box<TextureInput>>,
    /// `inputs:emissiveColor` from a primvar reader (radiance per point of the surface).
    pub emissive_primvar: Option<Box<PrimvarInput>>,
    /// The material's shading network flattened against the MaterialX library
    /// ([`crate::shading::flatten`] of [`crate::shade_network::read_network`]): read from
    /// `outputs:mtlx:surface` (the MaterialX render context), else `outputs:surface`, for every
    /// material whose surface shader has an `info:id` (a UsdPreviewSurface included: its
    /// MaterialX graph); `None` without a readable surface shader. The fields above describe
    /// the `outputs:surface` UsdPreviewSurface as before, whatever this holds.
    pub graph: Option<Box<crate::shading::ShadingGraph>>,
    /// The network [`Material::graph`] was flattened from (for a renderer that changes an
    /// input before flattening again, such as a `wavelength:reflectance` replacing a
    /// UsdPreviewSurface's `diffuseColor`).
    pub network: Option<Box<crate::shading::Network>>,
}

impl Material {
    /// A material with every UsdPreviewSurface default (0.18 grey, roughness 0.5, ior 1.5).
    pub fn new(path: impl Into<String>) -> Material {
        Material {
            path: path.into(),
            preview: false,
            diffuse: Input::Value(DEFAULT_DIFFUSE),
            use_specular_workflow: false,
            specular: Input::Value(DVec3::ZERO),
            metallic: Input::Value(0.0),
            roughness: Input::Value(0.5),
            clearcoat: Input::Value(0.0),
            clearcoat_roughness: Input::Value(0.01),
            ior: Input::Value(1.5),
            opacity: Input::Value(1.0),
            opacity_threshold: 0.0,
            normal: None,
            other_inputs: Vec::new(),
            uses_opacity: false,
            spectral: SurfaceSpectral::default(),
            emissive: DVec3::ZERO,
            emissive_texture: None,
            emissive_primvar: None,
            graph: None,
            network: None,
        }
    }

    /// Every texture the material reads, with the input it feeds.
    pub fn textures(&self) -> Vec<(&'static str, &TextureInput)> {
        [
            ("diffuseColor", self.diffuse.texture()),
            ("specularColor", self.specular.texture()),
            ("metallic", self.metallic.texture()),
            ("roughness", self.roughness.texture()),
            ("clearcoat", self.clearcoat.texture()),
            ("clearcoatRoughness", self.clearcoat_roughness.texture()),
            ("ior", self.ior.texture()),
            ("opacity", self.opacity.texture()),
            ("normal", self.normal.as_deref()),
            ("emissiveColor", self.emissive_texture.as_deref()),
        ]
        .into_iter()
        .filter_map(|(n, t)| t.map(|t| (n, t)))
        .collect()
    }

    /// Every primvar reader feeding one of the material's inputs, with the input's name.
    pub fn primvar_readers(&self) -> Vec<(&'static str, &PrimvarInput)> {
        [
            ("diffuseColor", self.diffuse.primvar()),
            ("specularColor", self.specular.primvar()),
            ("metallic", self.metallic.primvar()),
            ("roughness", self.roughness.primvar()),
            ("clearcoat", self.clearcoat.primvar()),
            ("clearcoatRoughness", self.clearcoat_roughness.primvar()),
            ("ior", self.ior.primvar()),
            ("opacity", self.opacity.primvar()),
            ("emissiveColor", self.emissive_primvar.as_deref()),
        ]
        .into_iter()
        .filter_map(|(n, p)| p.map(|p| (n, p)))
        .collect()
    }

    /// The names of the primvars the material's primvar readers read (each once, in input
    /// order).
    pub fn primvar_names(&self) -> Vec<&str> {
        let mut names: Vec<&str> = Vec::new();
        for (_, p) in self.primvar_readers() {
            if !names.contains(&p.name.as_str()) {
                names.push(&p.name);
            }
        }
        names
    }

    /// The texture-coordinate primvar the material reads (that of its first texture; lux reads
    /// one `st` set per mesh).
    pub fn st_primvar(&self) -> Option<&str> {
        self.textures().first().map(|(_, t)| t.st_primvar.as_str())
    }
}

/// Follows the connection of `attr` on `prim` through NodeGraph/Material interface inputs;
/// returns the final (prim path, attribute name) that holds a value or is a shader output.
fn follow(r: &Reader<'_>, prim_path: &str, attr: &str) -> Result<(String, String), LoadError> {
    let mut cur = (prim_path.to_owned(), attr.to_owned());
    for _ in 0..MAX_CONNECTION_DEPTH {
        let prim = r.stage.prim(cur.0.as_str());
        let Some(src) = r.connections(&prim, &cur.1)?.into_iter().next() else {
            return Ok(cur);
        };
        let Some((p, a)) = src.split_once('.') else {
            return Ok(cur);
        };
        if !is_prim_path(p) || !is_property_name(a) {
            return Ok(cur);
        }
        cur = (p.to_owned(), a.to_owned());
        if cur.1.starts_with("outputs:") {
            return Ok(cur);
        }
    }
    Ok(cur)
}

fn shader_id(r: &Reader<'_>, prim: &Prim) -> Result<Option<String>, LoadError> {
    r.text(prim, "info:id")
}

/// A token attribute parsed by `parse`: `None` when unauthored, or (with a warning naming the
/// prim and attribute) when the token is unknown.
fn token<T>(
    r: &mut Reader<'_>,
    prim: &Prim,
    name: &str,
    parse: impl Fn(&str) -> Option<T>,
) -> Result<Option<T>, LoadError> {
    let Some(t) = r.text(prim, name)? else {
        return Ok(None);
    };
    let v = parse(&t);
    if v.is_none() {
        r.warn(
            prim,
            WarningKind::InvalidValue,
            format!("{name} {t:?} is not a token of the schema; using the default"),
        );
    }
    Ok(v)
}

/// The inputs lux reads (the rest are listed in [`Material::other_inputs`]).
const READ_INPUTS: [&str; 12] = [
    "inputs:diffuseColor",
    "inputs:emissiveColor",
    "inputs:useSpecularWorkflow",
    "inputs:specularColor",
    "inputs:metallic",
    "inputs:roughness",
    "inputs:clearcoat",
    "inputs:clearcoatRoughness",
    "inputs:ior",
    "inputs:opacity",
    "inputs:opacityThreshold",
    "inputs:normal",
];

/// A UsdPreviewSurface network's constant inputs as the fields read them: a value the fields
/// replaced by its default (out of range, with a warning naming it) is replaced in the
/// network too, so the graph shades what the warning says.
fn validate_network(network: &mut crate::shading::Network, m: &Material) {
    use crate::shading::{NetSource, Value};
    let Some(k) = network.surface.as_ref().map(|c| c.node) else {
        return;
    };
    let colour = |i: &Input<DVec3>| i.value().map(|c| c.to_array().to_vec());
    let float = |i: &Input<f64>| i.value().map(|v| vec![v]);
    let fields: [(&str, Option<Vec<f64>>); 10] = [
        ("diffuseColor", colour(&m.diffuse)),
        ("specularColor", colour(&m.specular)),
        ("metallic", float(&m.metallic)),
        ("roughness", float(&m.roughness)),
        ("clearcoat", float(&m.clearcoat)),
        ("clearcoatRoughness", float(&m.clearcoat_roughness)),
        ("ior", float(&m.ior)),
        ("opacity", float(&m.opacity)),
        ("opacityThreshold", Some(vec![m.opacity_threshold])),
        (
            "useSpecularWorkflow",
            Some(vec![f64::from(u8::from(m.use_specular_workflow))]),
        ),
    ];
    for input in &mut network.nodes[k].inputs {
        let Some((_, Some(valid))) = fields.iter().find(|(n, _)| *n == input.name) else {
            continue;
        };
        if let NetSource::Value(Value::Numbers(v)) = &mut input.source
            && v.len() == valid.len()
            && v != valid
        {
            v.clone_from(valid);
        }
    }
}

/// Reads the Material at `path`.
pub fn read_material(r: &mut Reader<'_>, path: &str) -> Result<Material, LoadError> {
    let first_warning = r.warnings.len();
    let mut out = read_preview(r, path)?;
    let (network, _terminal) = read_network_terminal(r, path)?;
    let surface = network
        .surface
        .as_ref()
        .and_then(|c| network.nodes.get(c.node));
    let nodedef = surface.and_then(|n| n.nodedef.clone());
    if let Some(nodedef) = nodedef {
        let mut network = network;
        if nodedef == "UsdPreviewSurface" && out.preview {
            validate_network(&mut network, &out);
        }
        let graph = crate::shading::flatten(&network);
        // The renderer draws a MaterialX surface from the graph (from either terminal): the
        // UsdPreviewSurface fields' "default grey" does not apply to it — unless the shader
        // is none MaterialX knows (a `PxrSurface`), whose graph has no surface.
        if nodedef != "UsdPreviewSurface" && graph.surface.is_some() {
            r.warnings.retain(|w| {
                !(w.prim == path && (w.message == NOT_PREVIEW_SURFACE || w.message == NO_SURFACE))
            });
        }
        out.graph = Some(Box::new(graph));
        out.network = Some(Box::new(network));
    }
    // One warning per problem, whichever of the two readings found it first.
    let mut seen = Vec::new();
    let mut k = first_warning;
    while k < r.warnings.len() {
        if seen.contains(&r.warnings[k]) {
            r.warnings.remove(k);
        } else {
            seen.push(r.warnings[k].clone());
            k += 1;
        }
    }
    Ok(out)
}

/// The warning of a material whose `outputs:surface` is not a UsdPreviewSurface.
const NOT_PREVIEW_SURFACE: &str = "surface shader is not UsdPreviewSurface; default grey";
/// The warning of a material without `outputs:surface`.
const NO_SURFACE: &str = "material has no connected outputs:surface; default grey";

/// The UsdPreviewSurface fields of the Material at `path` (its `outputs:surface`).
fn read_preview(r: &mut Reader<'_>, path: &str) -> Result<Material, LoadError> {
    let mat = r.stage.prim(path);
    let mut out = Material::new(path);
    let (shader_path, _) = follow(r, path, "outputs:surface")?;
    if shader_path == path {
        r.warn(&mat, WarningKind::Ignored, NO_SURFACE);
        return Ok(out);
    }
    let shader = r.stage.prim(shader_path.as_str());
    if shader_id(r, &shader)?.as_deref() != Some("UsdPreviewSurface") {
        r.warn(&mat, WarningKind::Unsupported, NOT_PREVIEW_SURFACE);
        return Ok(out);
    }
    out.preview = true;
    out.spectral = read_surface_spectral(r, &shader)?;
    for name in shader
        .property_names()
        .map_err(|e| r.usd_error(&shader, e))?
    {
        let n = name.as_str();
        if n.starts_with("inputs:") && !READ_INPUTS.contains(&n) {
            out.other_inputs.push(n.to_owned());
        }
    }
    match colour_input(r, &mat, &shader_path, "emissiveColor", DVec3::ZERO, |e| {
        e.is_finite() && e.min_element() >= 0.0
    })? {
        Input::Value(e) => out.emissive = e,
        Input::Texture(t) => out.emissive_texture = Some(t),
        Input::Primvar(p) => out.emissive_primvar = Some(p),
    }
    let colour = |v: DVec3| v.is_finite();
    let unit = |v: f64| v.is_finite() && (0.0..=1.0).contains(&v);
    out.diffuse = colour_input(
        r,
        &mat,
        &shader_path,
        "diffuseColor",
        DEFAULT_DIFFUSE,
        colour,
    )?;
    out.use_specular_workflow =
        float_input(r, &mat, &shader_path, "useSpecularWorkflow", 0.0, |v| {
            v == 0.0 || v == 1.0
        })?
        .value()
        .is_some_and(|v| v == 1.0);
    out.specular = colour_input(r, &mat, &shader_path, "specularColor", DVec3::ZERO, colour)?;
    out.metallic = float_input(r, &mat, &shader_path, "metallic", 0.0, unit)?;
    out.roughness = float_input(r, &mat, &shader_path, "roughness", 0.5, unit)?;
    out.clearcoat = float_input(r, &mat, &shader_path, "clearcoat", 0.0, unit)?;
    out.clearcoat_roughness = float_input(r, &mat, &shader_path, "clearcoatRoughness", 0.01, unit)?;
    out.ior = float_input(r, &mat, &shader_path, "ior", 1.5, |v| {
        v.is_finite() && v >= 1.0
    })?;
    out.opacity = float_input(r, &mat, &shader_path, "opacity", 1.0, unit)?;
    out.opacity_threshold = float_input(r, &mat, &shader_path, "opacityThreshold", 0.0, unit)?
        .value()
        .unwrap_or(0.0);
    out.uses_opacity = out.opacity.value().is_none_or(|o| o < 1.0) || out.opacity_threshold > 0.0;
    match colour_input(r, &mat, &shader_path, "normal", DVec3::Z, |v| v.is_finite())? {
        Input::Texture(t) => out.normal = Some(t),
        Input::Primvar(p) => r.warn(
            &mat,
            WarningKind::Unsupported,
            format!(
                "normal connected to the primvar reader {} (a tangent-space normal map from a \
                 primvar); the surface's own normal is used",
                p.shader
            ),
        ),
        Input::Value(_) => {}
    }
    Ok(out)
}

/// A colour input (`color3f`/`normal3f`): its value when valid (else the default with a
/// warning), or the texture it is connected to.
fn colour_input(
    r: &mut Reader<'_>,
    mat: &Prim,
    shader: &str,
    name: &str,
    default: DVec3,
    valid: impl Fn(DVec3) -> bool,
) -> Result<Input<DVec3>, LoadError> {
    input(r, mat, shader, name, default, |r, p, a| r.vec3(p, a), valid)
}

/// A float input: its value when valid (else the default with a warning), or the texture
/// (one channel) it is connected to.
fn float_input(
    r: &mut Reader<'_>,
    mat: &Prim,
    shader: &str,
    name: &str,
    default: f64,
    valid: impl Fn(f64) -> bool,
) -> Result<Input<f64>, LoadError> {
    input(r, mat, shader, name, default, |r, p, a| r.f64(p, a), valid)
}

/// Reads `inputs:<name>` of the surface shader through interface connections: a value of the
/// right type, or a `UsdUVTexture` output. A value of the wrong type, an invalid value or a
/// connection to another kind of shader is the default, with a warning naming the material.
fn input<T: Copy + std::fmt::Debug>(
    r: &mut Reader<'_>,
    mat: &Prim,
    shader: &str,
    name: &str,
    default: T,
    read: impl Fn(&Reader<'_>, &Prim, &str) -> Result<Option<T>, LoadError>,
    valid: impl Fn(T) -> bool,
) -> Result<Input<T>, LoadError> {
    let (src_prim, src_attr) = follow(r, shader, &format!("inputs:{name}"))?;
    let src = r.stage.prim(src_prim.as_str());
    if let Some(output) = src_attr.strip_prefix("outputs:") {
        let id = shader_id(r, &src)?;
        if let Some(&(id, components)) = PRIMVAR_READERS
            .iter()
            .find(|(known, _)| Some(*known) == id.as_deref())
        {
            return match read_primvar_reader(r, &src_prim, id, components)? {
                Some(p) => Ok(Input::Primvar(Box::new(p))),
                None => {
                    r.warn(
                        mat,
                        WarningKind::InvalidValue,
                        format!(
                            "{name} connected to {src_prim} ({id}) whose inputs:varname is \
                             unauthored; default {default:?}"
                        ),
                    );
                    Ok(Input::Value(default))
                }
            };
        }
        if id.as_deref() != Some("UsdUVTexture") {
            r.warn(
                mat,
                WarningKind::Unsupported,
                format!(
                    "{name} connected to {src_prim} which is not a UsdUVTexture; default {default:?}"
                ),
            );
            return Ok(Input::Value(default));
        }
        return Ok(Input::Texture(Box::new(read_texture(
            r, &src_prim, output,
        )?)));
    }
    match read(r, &src, &src_attr) {
        Ok(None) => Ok(Input::Value(default)),
        Ok(Some(v)) if valid(v) => Ok(Input::Value(v)),
        Ok(Some(v)) => {
            r.warn(
                mat,
                WarningKind::InvalidValue,
                format!("inputs:{name} = {v:?} is out of range; using the default {default:?}"),
            );
            Ok(Input::Value(default))
        }
        Err(e @ LoadError::AttributeType { .. }) => {
            r.warn(
                mat,
                WarningKind::InvalidValue,
                format!("{e}; using the default {default:?}"),
            );
            Ok(Input::Value(default))
        }
        Err(e) => Err(e),
    }
}

/// The `UsdPrimvarReader_*` at `src_prim`: its `varname` (token or string, through interface
/// connections) and `fallback`; `None` without a varname.
fn read_primvar_reader(
    r: &mut Reader<'_>,
    src_prim: &str,
    id: &str,
    components: usize,
) -> Result<Option<PrimvarInput>, LoadError> {
    let (vp, va) = follow(r, src_prim, "inputs:varname")?;
    let vprim = r.stage.prim(vp.as_str());
    let Some(name) = r.text(&vprim, &va)? else {
        return Ok(None);
    };
    let (fp, fa) = follow(r, src_prim, "inputs:fallback")?;
    let fprim = r.stage.prim(fp.as_str());
    let fallback = match r.raw(&fprim, &fa)? {
        Some(v) => crate::value::as_vec4(&v)
            .or_else(|| crate::value::as_vec3(&v).map(|c| c.extend(0.0)))
            .or_else(|| crate::value::as_vec2(&v).map(|c| DVec4::new(c.x, c.y, 0.0, 0.0)))
            .or_else(|| crate::value::as_f64(&v).map(|x| DVec4::new(x, 0.0, 0.0, 0.0)))
            .filter(|v| v.is_finite())
            .unwrap_or(DVec4::ZERO),
        None => DVec4::ZERO,
    };
    Ok(Some(PrimvarInput {
        shader: src_prim.to_owned(),
        id: id.to_owned(),
        name: name.strip_prefix("primvars:").unwrap_or(&name).to_owned(),
        components,
        fallback,
    }))
}

/// The `UsdUVTexture` at `src_prim` read through its `output`, with the primvar (and
/// `UsdTransform2d`) feeding its `inputs:st`.
fn read_texture(
    r: &mut Reader<'_>,
    src_prim: &str,
    output: &str,
) -> Result<TextureInput, LoadError> {
    let src = r.stage.prim(src_prim);
    let mut st_primvar = "st".to_owned();
    let mut st_fallback = DVec2::ZERO;
    let mut transform = None;
    let (mut reader_prim, _) = follow(r, src_prim, "inputs:st")?;
    if reader_prim != src_prim {
        let rp = r.stage.prim(reader_prim.as_str());
        if shader_id(r, &rp)?.as_deref() == Some("UsdTransform2d") {
            let t = Transform2d {
                rotation: finite_or(r.f64(&rp, "inputs:rotation"), 0.0),
                scale: r
                    .vec2(&rp, "inputs:scale")
                    .ok()
                    .flatten()
                    .filter(|v| v.is_finite())
                    .unwrap_or(DVec2::ONE),
                translation: r
                    .vec2(&rp, "inputs:translation")
                    .ok()
                    .flatten()
                    .filter(|v| v.is_finite())
                    .unwrap_or(DVec2::ZERO),
            };
            transform = Some(t);
            let (next, _) = follow(r, &reader_prim, "inputs:in")?;
            if next == reader_prim {
                reader_prim = src_prim.to_owned();
            } else {
                reader_prim = next;
            }
        }
        if reader_prim != src_prim {
            let (vp, va) = follow(r, &reader_prim, "inputs:varname")?;
            let vprim = r.stage.prim(vp.as_str());
            if let Some(v) = r.text(&vprim, &va)? {
                st_primvar = v;
            }
            let rp = r.stage.prim(reader_prim.as_str());
            if let Some(f) = r.vec2(&rp, "inputs:fallback")?.filter(|f| f.is_finite()) {
                st_fallback = f;
            }
        }
    }
    let file = r.asset(&src, "inputs:file")?;
    let fallback = r.vec4(&src, "inputs:fallback")?;
    if let Some(a) = &file
        && a.resolved.is_none()
    {
        r.warn(
            &src,
            WarningKind::UnresolvedAsset,
            format!("texture @{}@ does not resolve to a file", a.authored),
        );
    }
    Ok(TextureInput {
        shader: src_prim.to_owned(),
        file,
        st_primvar,
        st_fallback,
        transform,
        scale: r.vec4(&src, "inputs:scale")?.unwrap_or(DVec4::ONE),
        bias: r.vec4(&src, "inputs:bias")?.unwrap_or(DVec4::ZERO),
        fallback: fallback.unwrap_or(DVec4::new(0.0, 0.0, 0.0, 1.0)),
        fallback_authored: fallback.is_some(),
        wrap_s: token(r, &src, "inputs:wrapS", Wrap::parse)?.unwrap_or_default(),
        wrap_t: token(r, &src, "inputs:wrapT", Wrap::parse)?.unwrap_or_default(),
        source_color_space: token(r, &src, "inputs:sourceColorSpace", SourceColorSpace::parse)?
            .unwrap_or_default(),
        output: output.to_owned(),
    })
}

fn finite_or(v: Result<Option<f64>, LoadError>, default: f64) -> f64 {
    v.ok()
        .flatten()
        .filter(|x| x.is_finite())
        .unwrap_or(default)
}
