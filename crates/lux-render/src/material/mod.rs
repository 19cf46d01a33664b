//! Materials: what a ray sees where it hits geometry — position, facing normals and the BSDF
//! ([`Bsdf`]). Today every surface is Lambertian ([`DiffuseBsdf`]) with the albedo of
//! UsdPreviewSurface `diffuseColor` as a value or a `UsdUVTexture` (`material/texture.rs`),
//! else the gprim's `primvars:displayColor`, else white — the white Lambertian of the
//! reference renders; a `wavelength:reflectance` (LTESpectralAPI) replaces `diffuseColor`.
//!
//! An instanced hit (`Hit::instance`) shades with its prototype mesh's primvars and
//! `doubleSided`, the material `mesh.material.or(instance.material)` (the prototype's own binding
//! wins over the instance's), and shading normals mapped to the world like the loader maps a
//! world mesh's: each corner normal `n` by the inverse transpose of the instance's linear part,
//! `normalize(M⁻ᵀ·n)`, then interpolated and renormalised.

mod diffuse;
mod texture;

pub use diffuse::DiffuseBsdf;

use crate::RenderError;
use crate::geometry::Hit;
use crate::image_io::Texture;
use glam::{DMat3, DVec2, DVec3};
use lux_usd::{Diffuse, Scene, SurfaceSpectral};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;
use texture::{TextureShader, texture_shader};

#[derive(Clone, Debug)]
enum Albedo {
    Color(DVec3),
    Texture(TextureShader),
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
}

/// The scattering function at a surface point (the closed set of lux's BSDFs).
#[derive(Clone, Copy, Debug)]
pub enum Bsdf {
    /// Lambertian reflection.
    Diffuse(DiffuseBsdf),
}

impl Bsdf {
    /// True when the surface reflects nothing.
    #[inline]
    pub fn is_black(&self) -> bool {
        match self {
            Bsdf::Diffuse(b) => b.albedo == DVec3::ZERO,
        }
    }

    /// Whether `f` is a constant `ρ/π` over the upper hemisphere (a Lambertian BSDF), so that
    /// light samples that follow the cosine-weighted solid angle are best estimated alone
    /// (the direct integrator's [`crate::light::Light::uniform_area`] lights).
    #[inline]
    pub fn is_lambertian(&self) -> bool {
        match self {
            Bsdf::Diffuse(_) => true,
        }
    }

    /// `f(wi)` for the unit world direction `wi` (towards the light), the viewer given.
    #[inline]
    pub fn f(&self, wi: DVec3) -> DVec3 {
        match self {
            Bsdf::Diffuse(b) => b.f(wi),
        }
    }

    /// Density with which [`Bsdf::sample`] produces `wi` (per unit solid angle).
    #[inline]
    pub fn pdf(&self, wi: DVec3) -> f64 {
        match self {
            Bsdf::Diffuse(b) => b.pdf(wi),
        }
    }

    /// Samples an incident direction with `u ∈ [0,1)²`; `None` below the shading horizon.
    #[inline]
    pub fn sample(&self, u: [f64; 2]) -> Option<BsdfSample> {
        match self {
            Bsdf::Diffuse(b) => b.sample(u),
        }
    }
}

/// The prepared materials of a scene.
pub struct Materials {
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

/// The shading frame and BSDF at a hit.
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
    /// The BSDF (about the shading normal).
    pub bsdf: Bsdf,
    /// The geometry hit: index into `Scene::meshes` ([`Hit::mesh`]), for light linking.
    pub mesh: usize,
    /// The instance hit ([`Hit::instance`]), for light linking.
    pub instance: Option<usize>,
}

impl Materials {
    /// Loads the textures of every material (once per file). A texture that does not resolve or
    /// cannot be read gives its `UsdUVTexture` fallback, with a warning naming it.
    pub fn new(scene: &Scene) -> Result<Materials, RenderError> {
        Materials::with_policy(scene, false)
    }

    /// [`Materials::new`], where `strict` makes an unreadable texture an error instead of its
    /// fallback with a warning.
    pub fn with_policy(scene: &Scene, strict: bool) -> Result<Materials, RenderError> {
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
        Ok(Materials {
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
            bsdf: Bsdf::Diffuse(DiffuseBsdf { albedo, ns }),
            mesh: hit.mesh,
            instance: hit.instance,
        }
    }
}
