//! `material:binding` → `UsdPreviewSurface.inputs:diffuseColor`, as a value or a `UsdUVTexture`.

use crate::error::{LoadError, WarningKind};
use crate::reader::{AssetRef, Reader, is_prim_path, is_property_name};
use crate::spectral::{SurfaceSpectral, read_surface_spectral};
use glam::{DVec3, DVec4};
use openusd::usd::Prim;

/// The UsdPreviewSurface default `diffuseColor`.
pub const DEFAULT_DIFFUSE: DVec3 = DVec3::splat(0.18);
/// Longest chain of connections followed before giving up (cycles, deep node graphs).
const MAX_CONNECTION_DEPTH: usize = 16;

/// A `UsdUVTexture` feeding `diffuseColor`.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureInput {
    /// The texture shader's prim path.
    pub shader: String,
    /// `inputs:file`.
    pub file: Option<AssetRef>,
    /// The primvar read by the `UsdPrimvarReader_float2` on `inputs:st` (default `"st"`).
    pub st_primvar: String,
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

/// Where a material's diffuse colour comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum Diffuse {
    /// A constant colour.
    Color(DVec3),
    /// A texture lookup.
    Texture(Box<TextureInput>),
}

/// A bound material, reduced to what the reference renderer shades with.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The Material prim path.
    pub path: String,
    /// The UsdPreviewSurface diffuse colour (default 0.18 grey; also when the surface shader is
    /// not a UsdPreviewSurface, with a warning).
    pub diffuse: Diffuse,
    /// Other authored UsdPreviewSurface inputs (recorded by name, not used).
    pub other_inputs: Vec<String>,
    /// Whether the surface asks for transparency or cut-outs (UsdPreviewSurface `opacity`
    /// below 1 or connected, or `opacityThreshold` above 0), which lux draws opaque.
    pub uses_opacity: bool,
    /// LTESpectralAPI inputs of the surface shader (`wavelength:reflectance`,
    /// `wavelength:ior`, scalar `ior`); a `wavelength:reflectance` replaces `diffuseColor`.
    pub spectral: SurfaceSpectral,
    /// UsdPreviewSurface `inputs:emissiveColor` (radiance, nits; default black) when authored
    /// as a value (through interface inputs); a texture-driven emission is a warning and 0.
    pub emissive: DVec3,
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

/// Reads the Material at `path`.
pub fn read_material(r: &mut Reader<'_>, path: &str) -> Result<Material, LoadError> {
    let mat = r.stage.prim(path);
    let mut out = Material {
        path: path.to_owned(),
        diffuse: Diffuse::Color(DEFAULT_DIFFUSE),
        other_inputs: Vec::new(),
        uses_opacity: false,
        spectral: SurfaceSpectral::default(),
        emissive: DVec3::ZERO,
    };
    let (shader_path, _) = follow(r, path, "outputs:surface")?;
    if shader_path == path {
        r.warn(
            &mat,
            WarningKind::Ignored,
            "material has no connected outputs:surface; default grey",
        );
        return Ok(out);
    }
    let shader = r.stage.prim(shader_path.as_str());
    if shader_id(r, &shader)?.as_deref() != Some("UsdPreviewSurface") {
        r.warn(
            &mat,
            WarningKind::Unsupported,
            "surface shader is not UsdPreviewSurface; default grey",
        );
        return Ok(out);
    }
    out.spectral = read_surface_spectral(r, &shader)?;
    for name in shader
        .property_names()
        .map_err(|e| r.usd_error(&shader, e))?
    {
        let n = name.as_str();
        if n.starts_with("inputs:") && n != "inputs:diffuseColor" && n != "inputs:emissiveColor" {
            out.other_inputs.push(n.to_owned());
        }
    }
    let opacity_connected = !r.connections(&shader, "inputs:opacity")?.is_empty();
    let opacity = r.f64(&shader, "inputs:opacity")?.unwrap_or(1.0);
    let threshold = r.f64(&shader, "inputs:opacityThreshold")?.unwrap_or(0.0);
    out.uses_opacity = opacity_connected || opacity < 1.0 || threshold > 0.0;
    let (emit_prim, emit_attr) = follow(r, &shader_path, "inputs:emissiveColor")?;
    if emit_attr.starts_with("outputs:") {
        r.warn(
            &mat,
            WarningKind::Unsupported,
            format!("emissiveColor from {emit_prim} (a texture) is not supported yet; no emission"),
        );
    } else if let Some(e) = r.vec3(&r.stage.prim(emit_prim.as_str()), &emit_attr)? {
        if e.is_finite() && e.min_element() >= 0.0 {
            out.emissive = e;
        } else {
            r.warn(
                &mat,
                WarningKind::InvalidValue,
                format!("emissiveColor {e} is not a finite non-negative colour; no emission"),
            );
        }
    }
    let (src_prim, src_attr) = follow(r, &shader_path, "inputs:diffuseColor")?;
    let src = r.stage.prim(src_prim.as_str());
    if let Some(output) = src_attr.strip_prefix("outputs:") {
        if shader_id(r, &src)?.as_deref() != Some("UsdUVTexture") {
            r.warn(
                &mat,
                WarningKind::Unsupported,
                format!(
                    "diffuseColor connected to {src_prim} which is not a UsdUVTexture; default grey"
                ),
            );
            return Ok(out);
        }
        let (reader_prim, _) = follow(r, &src_prim, "inputs:st")?;
        let mut st_primvar = "st".to_owned();
        if reader_prim != src_prim {
            let rp = r.stage.prim(reader_prim.as_str());
            let (vp, va) = follow(r, &reader_prim, "inputs:varname")?;
            let vprim = r.stage.prim(vp.as_str());
            if let Some(v) = r.text(&vprim, &va)? {
                st_primvar = v;
            }
            let _ = rp;
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
        out.diffuse = Diffuse::Texture(Box::new(TextureInput {
            shader: src_prim.clone(),
            file,
            st_primvar,
            scale: r.vec4(&src, "inputs:scale")?.unwrap_or(DVec4::ONE),
            bias: r.vec4(&src, "inputs:bias")?.unwrap_or(DVec4::ZERO),
            fallback: fallback.unwrap_or(DVec4::new(0.0, 0.0, 0.0, 1.0)),
            fallback_authored: fallback.is_some(),
            wrap_s: token(r, &src, "inputs:wrapS", Wrap::parse)?.unwrap_or_default(),
            wrap_t: token(r, &src, "inputs:wrapT", Wrap::parse)?.unwrap_or_default(),
            source_color_space: token(r, &src, "inputs:sourceColorSpace", SourceColorSpace::parse)?
                .unwrap_or_default(),
            output: output.to_owned(),
        }));
    } else if let Some(c) = r.vec3(&src, &src_attr)? {
        out.diffuse = Diffuse::Color(if c.is_finite() { c } else { DEFAULT_DIFFUSE });
    }
    Ok(out)
}
