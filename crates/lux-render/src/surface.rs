//! What a camera ray sees where it hits geometry: position, facing normals and the diffuse
//! albedo (UsdPreviewSurface `diffuseColor` as a value or a `UsdUVTexture`, else the gprim's
//! `primvars:displayColor`, else white — the white Lambertian of the reference renders).

use crate::RenderError;
use crate::geometry::Hit;
use crate::image_io::{Texture, linear_to_srgb};
use glam::{DVec2, DVec3, DVec4};
use lux_usd::{Diffuse, Scene, SpectralAttributes, TextureInput};
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
    fn parse(token: &str) -> Wrap {
        match token {
            "mirror" => Wrap::Mirror,
            "clamp" => Wrap::Clamp,
            "black" => Wrap::Black,
            // "repeat", and "useMetadata" without metadata in the file: repeat.
            _ => Wrap::Repeat,
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
    materials: Vec<Albedo>,
    /// Per mesh: the albedo of a `wavelength:reflectance` authored on the gprim.
    mesh_reflectance: Vec<Option<DVec3>>,
}

/// Linear Rec.709 albedo of a `wavelength:reflectance` (lux-spectral, lit by the colour
/// space's white), if authored.
fn reflectance_albedo(
    prim: &str,
    a: &SpectralAttributes,
    unit: lux_spectral::WavelengthUnit,
) -> Result<Option<DVec3>, RenderError> {
    let err = |message: String| RenderError::Surface {
        prim: prim.to_owned(),
        message,
    };
    if a.is_empty() {
        return Ok(None);
    }
    let inputs = crate::physical::surface_spectral_inputs(a, unit).map_err(err)?;
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
    /// cannot be read is an error naming it.
    pub fn new(scene: &Scene) -> Result<Surfaces, RenderError> {
        let unit = crate::physical::stage_wavelength_unit(scene.unit_for_wavelength.as_deref())
            .map_err(|message| RenderError::Surface {
                prim: "/".into(),
                message,
            })?;
        let mut cache: HashMap<PathBuf, Arc<Texture>> = HashMap::new();
        let mut materials = Vec::with_capacity(scene.materials.len());
        for m in &scene.materials {
            // LTESpectralAPI: a spectral reflectance on the surface shader replaces diffuseColor.
            if let Some(c) = reflectance_albedo(&m.path, &m.spectral, unit)? {
                materials.push(Albedo::Color(c));
                continue;
            }
            materials.push(match &m.diffuse {
                Diffuse::Color(c) => Albedo::Color(*c),
                Diffuse::Texture(t) => texture_shader(&m.path, t, &mut cache)?,
            });
        }
        let mesh_reflectance = scene
            .meshes
            .iter()
            .map(|m| reflectance_albedo(&m.path, &m.spectral, unit))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Surfaces {
            materials,
            mesh_reflectance,
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
            Some(n) => interp3(&n[hit.tri]).normalize_or_zero(),
            None => DVec3::ZERO,
        };
        if ns == DVec3::ZERO || !ns.is_finite() {
            ns = ng;
        } else if ns.dot(ng) < 0.0 {
            ns = -ns;
        }
        let albedo = match (
            self.mesh_reflectance[hit.mesh],
            mesh.material.and_then(|i| self.materials.get(i)),
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
            albedo,
        }
    }
}

fn texture_shader(
    material: &str,
    t: &TextureInput,
    cache: &mut HashMap<PathBuf, Arc<Texture>>,
) -> Result<Albedo, RenderError> {
    let Some(file) = &t.file else {
        return Ok(Albedo::Color(t.fallback.truncate()));
    };
    let Some(path) = &file.resolved else {
        return Err(RenderError::Asset {
            file: PathBuf::from(&file.authored),
            message: format!("texture of material {material} does not resolve to a file"),
        });
    };
    let tex = match cache.get(path) {
        Some(t) => t.clone(),
        None => {
            let t =
                Arc::new(
                    crate::assets::load_texture(path).map_err(|e| RenderError::Asset {
                        file: path.clone(),
                        message: e.to_string(),
                    })?,
                );
            cache.insert(path.clone(), t.clone());
            t
        }
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
        wrap: [Wrap::parse(&t.wrap_s), Wrap::parse(&t.wrap_t)],
        raw: t.source_color_space == "raw" && !matches!(ext.as_str(), "exr" | "hdr"),
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
        assert_eq!(Wrap::parse("useMetadata"), Wrap::Repeat);
    }
}
