//! What a camera ray sees where it hits geometry: position, facing normals and the diffuse
//! albedo (UsdPreviewSurface `diffuseColor` as a value or a `UsdUVTexture`, else the gprim's
//! `primvars:displayColor`, else white — the white Lambertian of the reference renders).
//!
//! An instanced hit (`Hit::instance`) shades with its prototype mesh's primvars and
//! `doubleSided`, the material `mesh.material.or(instance.material)` (the prototype's own binding
//! wins over the instance's), and shading normals mapped to the world like the loader maps a
//! world mesh's: each corner normal `n` by the inverse transpose of the instance's linear part,
//! `normalize(M⁻ᵀ·n)`, then interpolated and renormalised.

use crate::RenderError;
use crate::geometry::Hit;
use crate::image_io::{Texture, linear_to_srgb};
use glam::{DMat3, DVec2, DVec3, DVec4};
use lux_usd::{Diffuse, Scene, SourceColorSpace, SurfaceSpectral, TextureInput};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

/// How a texture coordinate outside \[0, 1\] is folded back (UsdUVTexture `wrapS`/`wrapT`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Wrap {
    Repeat,
    Mirror,
    Clamp,
    Black,
}

impl Wrap {
    /// The fold of a `UsdUVTexture` wrap mode; `useMetadata` without metadata in the file
    /// (lux's image readers carry none) repeats.
    fn of(mode: lux_usd::Wrap) -> Wrap {
        match mode {
            lux_usd::Wrap::Mirror => Wrap::Mirror,
            lux_usd::Wrap::Clamp => Wrap::Clamp,
            lux_usd::Wrap::Black => Wrap::Black,
            lux_usd::Wrap::Repeat | lux_usd::Wrap::UseMetadata => Wrap::Repeat,
        }
    }

    /// Folds `x` into \[0, 1\]; `None` for "black" outside the unit interval.
    #[inline]
    fn apply(self, x: f64) -> Option<f64> {
        if !x.is_finite() {
            return None;
        }
        Some(match self {
            Wrap::Repeat => x - x.floor(),
            Wrap::Clamp => x.clamp(0.0, 1.0),
            Wrap::Mirror => {
                let m = x.rem_euclid(2.0);
                if m > 1.0 { 2.0 - m } else { m }
            }
            Wrap::Black => {
                if (0.0..=1.0).contains(&x) {
                    x
                } else {
                    return None;
                }
            }
        })
    }
}

/// A prepared `UsdUVTexture` feeding `diffuseColor`.
#[derive(Clone, Debug)]
struct TextureShader {
    tex: Arc<Texture>,
    scale: DVec4,
    bias: DVec4,
    fallback: DVec4,
    wrap: [Wrap; 2],
    /// `sourceColorSpace = "raw"` on an 8-bit file: undo the sRGB decode.
    raw: bool,
    /// Which output is connected: 0..=2 a single channel (r, g, b), 3 alpha, 4 rgb.
    output: u8,
}

impl TextureShader {
    #[inline]
    fn eval(&self, st: DVec2) -> DVec3 {
        let pick = |c: DVec4| -> DVec3 {
            match self.output {
                4 => c.truncate(),
                k => DVec3::splat(c[k as usize]),
            }
        };
        let (Some(u), Some(v)) = (self.wrap[0].apply(st.x), self.wrap[1].apply(st.y)) else {
            return pick(self.fallback);
        };
        // USD texture coordinates have (0, 0) at the image's bottom-left.
        let t = self.tex.bilinear(u, 1.0 - v);
        let mut c = DVec4::new(t[0] as f64, t[1] as f64, t[2] as f64, t[3] as f64);
        if self.raw {
            c = DVec4::new(
                linear_to_srgb(t[0]) as f64,
                linear_to_srgb(t[1]) as f64,
                linear_to_srgb(t[2]) as f64,
                c.w,
            );
        }
        pick(c * self.scale + self.bias)
    }
}

#[derive(Clone, Debug)]
enum Albedo {
    Color(DVec3),
    Texture(TextureShader),
}

/// The prepared materials of a scene.
pub struct Surfaces {
    /// Textures that could not be read (each replaced by its fallback).
    pub warnings: Vec<String>,
    materials: Vec<Albedo>,
    /// Per mesh: the albedo of a `wavelength:reflectance` authored on the gprim.
    mesh_reflectance: Vec<Option<DVec3>>,
    /// Per scene instance: `M⁻ᵀ`, the inverse transpose of its transform's linear part, which
    /// maps prototype-space normals to the world.
    instance_normal: Vec<DMat3>,
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

/// The shading frame and albedo at a hit.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    /// Position.
    pub p: DVec3,
    /// Geometric normal, on the side the ray came from.
    pub ng: DVec3,
    /// Shading normal (interpolated `normals` when authored), on the same side as `ng`.
    pub ns: DVec3,
    /// How far along `±ng` rays leaving `p` start ([`Hit::offset`]).
    pub offset: f64,
    /// Diffuse albedo (linear RGB, clamped to \[0, 1\]).
    pub albedo: DVec3,
}

fn output_index(name: &str) -> u8 {
    match name {
        "r" => 0,
        "g" => 1,
        "b" => 2,
        "a" => 3,
        _ => 4,
    }
}

impl Surfaces {
    /// Loads the textures of every material (once per file). A texture that does not resolve or
    /// cannot be read gives its `UsdUVTexture` fallback, with a warning naming it.
    pub fn new(scene: &Scene) -> Result<Surfaces, RenderError> {
        Surfaces::with_policy(scene, false)
    }

    /// [`Surfaces::new`], where `strict` makes an unreadable texture an error instead of its
    /// fallback with a warning.
    pub fn with_policy(scene: &Scene, strict: bool) -> Result<Surfaces, RenderError> {
        let unit = scene.unit_for_wavelength;
        let mut warnings = Vec::new();
        let mut cache: HashMap<PathBuf, Arc<Texture>> = HashMap::new();
        let mut materials = Vec::with_capacity(scene.materials.len());
        for m in &scene.materials {
            // LTESpectralAPI: a spectral reflectance on the surface shader replaces diffuseColor
            // (one that lux-spectral refuses is a warning, and diffuseColor is used).
            match reflectance_albedo(&m.path, &m.spectral, unit) {
                Ok(Some(c)) => {
                    materials.push(Albedo::Color(c));
                    continue;
                }
                Ok(None) => {}
                Err(e) if strict => return Err(e),
                Err(e) => warnings.push(format!("{e}; diffuseColor is used instead")),
            }
            materials.push(match &m.diffuse {
                Diffuse::Color(c) => Albedo::Color(*c),
                Diffuse::Texture(t) => {
                    texture_shader(&m.path, t, &mut cache, strict, &mut warnings)?
                }
            });
        }
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
        let instance_normal = scene
            .instances
            .iter()
            .map(|i| DMat3::from_mat4(i.to_world).inverse().transpose())
            .collect();
        Ok(Surfaces {
            warnings,
            materials,
            mesh_reflectance,
            instance_normal,
        })
    }

    /// The surface seen by a ray of direction `d` at `hit`.
    pub fn at(&self, scene: &Scene, hit: &Hit, d: DVec3) -> SurfacePoint {
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
        let material = mesh
            .material
            .or_else(|| hit.instance.and_then(|i| scene.instances[i].material));
        let albedo = match (
            self.mesh_reflectance[hit.mesh],
            material.and_then(|i| self.materials.get(i)),
        ) {
            (Some(c), _) => c,
            (None, m) => match m {
                Some(Albedo::Color(c)) => *c,
                Some(Albedo::Texture(t)) => match &mesh.uvs {
                    Some(uv) => {
                        let c = &uv[hit.tri];
                        t.eval(b0 * c[0] + b1 * c[1] + b2 * c[2])
                    }
                    None => t.eval(DVec2::ZERO),
                },
                None => match &mesh.colors {
                    Some(c) => interp3(&c[hit.tri]),
                    None => DVec3::ONE,
                },
            },
        };
        let albedo = if albedo.is_finite() {
            albedo.clamp(DVec3::ZERO, DVec3::ONE)
        } else {
            DVec3::ZERO
        };
        SurfacePoint {
            p: hit.p,
            ng,
            ns,
            offset: hit.offset,
            albedo,
        }
    }
}

/// The albedo of a `UsdUVTexture`. A texture file that does not resolve or cannot be read
/// (missing, a format lux does not decode such as RenderMan `.tex`, corrupt) is replaced, with
/// a warning naming the material and the file (an error when `strict`), by the texture's
/// `inputs:fallback` when authored, else by `diffuseColor`'s own fallback (0.18 grey): the
/// surface stays visible and lit, where the schema default (0, 0, 0, 1) would paint it black.
fn texture_shader(
    material: &str,
    t: &TextureInput,
    cache: &mut HashMap<PathBuf, Arc<Texture>>,
    strict: bool,
    warnings: &mut Vec<String>,
) -> Result<Albedo, RenderError> {
    let Some(file) = &t.file else {
        return Ok(Albedo::Color(t.fallback.truncate()));
    };
    let failed = |file: PathBuf, message: String, warnings: &mut Vec<String>| {
        if strict {
            return Err(RenderError::Asset { file, message });
        }
        let (colour, what) = if t.fallback_authored {
            (t.fallback.truncate(), "the texture's inputs:fallback")
        } else {
            (
                lux_usd::material::DEFAULT_DIFFUSE,
                "diffuseColor's fallback",
            )
        };
        warnings.push(format!(
            "{}: {message}; material {material} uses {what} {colour}",
            file.display(),
        ));
        Ok(Albedo::Color(colour))
    };
    let Some(path) = &file.resolved else {
        return failed(
            PathBuf::from(&file.authored),
            format!("texture of material {material} does not resolve to a file"),
            warnings,
        );
    };
    let tex = match cache.get(path) {
        Some(t) => t.clone(),
        None => match crate::assets::load_texture(path) {
            Ok(tex) => {
                let tex = Arc::new(tex);
                cache.insert(path.clone(), tex.clone());
                tex
            }
            Err(e) => return failed(path.clone(), e.to_string(), warnings),
        },
    };
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    Ok(Albedo::Texture(TextureShader {
        tex,
        scale: t.scale,
        bias: t.bias,
        fallback: t.fallback,
        wrap: [Wrap::of(t.wrap_s), Wrap::of(t.wrap_t)],
        raw: t.source_color_space == SourceColorSpace::Raw
            && !matches!(ext.as_str(), "exr" | "hdr"),
        output: output_index(&t.output),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_modes() {
        assert_eq!(Wrap::Repeat.apply(1.25), Some(0.25));
        assert_eq!(Wrap::Repeat.apply(-0.25), Some(0.75));
        assert_eq!(Wrap::Clamp.apply(1.5), Some(1.0));
        assert_eq!(Wrap::Mirror.apply(1.25), Some(0.75));
        assert_eq!(Wrap::Mirror.apply(-0.25), Some(0.25));
        assert_eq!(Wrap::Black.apply(1.5), None);
        assert_eq!(Wrap::Black.apply(0.5), Some(0.5));
        assert_eq!(Wrap::Repeat.apply(f64::NAN), None);
        assert_eq!(Wrap::of(lux_usd::Wrap::UseMetadata), Wrap::Repeat);
        assert_eq!(Wrap::of(lux_usd::Wrap::Mirror), Wrap::Mirror);
    }
}
