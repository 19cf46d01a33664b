//! Building a [`Light`] from lux-usd's typed light: transform, ShapingAPI with its IES
//! profile, texture, the kind's geometry and sampler, then the base emission
//! ([`crate::physical`]), camera visibility and power.
//!
//! Assets (IES profiles, textures) are loaded once per file. One that does not resolve or
//! cannot be read is a warning naming the light and the file, and the light emits without it
//! (an error when strict); a light whose inputs cannot be used at all is left out with a
//! warning naming it.

use super::{
    CylinderLight, DiskLight, DistantLight, DomeLight, Light, LightBase, LightOptions,
    LightTexture, MeshLight, RectLight, SphereLight, dome::dome_transform,
};
use crate::RenderError;
use crate::image_io::Texture;
use crate::physical;
use glam::DVec3;
use lux_ies::{IesFile, ParseOptions, PhotometricWeb};
use lux_math::{LightKind, LightShape, Profile};
use lux_sample::LightTransform;
use lux_shaping::{Shaping, ShapingOptions, ShapingParams};
use lux_usd::{Light as UsdLight, Scene, UpAxis};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The state of preparing a scene's lights: options, asset caches and the warnings so far.
pub(super) struct Loader<'s> {
    scene: &'s Scene,
    options: LightOptions,
    ies_cache: HashMap<PathBuf, PhotometricWeb>,
    tex_cache: HashMap<PathBuf, Arc<Texture>>,
    /// Non-fatal problems met so far.
    pub warnings: Vec<String>,
}

/// Why a light is not built: left out with a warning, or an error for the whole render.
enum Skip {
    Warn(String),
    Fail(RenderError),
}

impl From<RenderError> for Skip {
    fn from(e: RenderError) -> Skip {
        Skip::Fail(e)
    }
}

impl<'s> Loader<'s> {
    pub(super) fn new(scene: &'s Scene, options: LightOptions) -> Loader<'s> {
        Loader {
            scene,
            options,
            ies_cache: HashMap::new(),
            tex_cache: HashMap::new(),
            warnings: Vec::new(),
        }
    }

    /// The light `l`, emitting from the world-space scene mesh `mesh` for a mesh light;
    /// `Ok(None)` (with a warning) when it cannot emit.
    pub(super) fn light(
        &mut self,
        l: &UsdLight,
        mesh: Option<usize>,
    ) -> Result<Option<Light>, RenderError> {
        match self.build(l, mesh) {
            Ok(light) => Ok(Some(light)),
            Err(Skip::Warn(why)) => {
                self.warnings
                    .push(format!("{}: {why}; the light is not rendered", l.path));
                Ok(None)
            }
            Err(Skip::Fail(e)) => Err(e),
        }
    }

    fn build(&mut self, l: &UsdLight, mesh: Option<usize>) -> Result<Light, Skip> {
        let profile = self.options.profile;
        let m = if l.kind == LightKind::Dome {
            dome_transform(self.scene, l)
        } else {
            l.light_to_world
        };
        let xf =
            LightTransform::new(m).map_err(|e| Skip::Warn(format!("unusable transform ({e})")))?;
        let shaping = self.shaping(l)?;
        let texture = self.texture(l)?;
        let tex = texture.as_ref().map(|t| t.tex.clone());
        let base = LightBase::new(&l.path, xf, shaping, l.shadow.clone());
        let mut light = match &l.shape {
            LightShape::Rect { width, height } => RectLight::new(
                base,
                *width,
                *height,
                texture,
                profile == Profile::HdEmbree,
                self.options.cone_clipping,
            )
            .map(Light::Rect),
            LightShape::Disk { radius } => DiskLight::new(base, *radius).map(Light::Disk),
            LightShape::Sphere { radius } => {
                SphereLight::new(base, *radius)
                    .map(Light::Sphere)
                    .map_err(|e| {
                        if *radius == 0.0 {
                            // DCC exports write point lights this way (Maya: treatAsPoint).
                            format!(
                                "SphereLight of radius 0{} is a point light, and lux renders \
                                 only lights with an area",
                                if l.treat_as_point {
                                    " (treatAsPoint, a renderer hint)"
                                } else {
                                    ""
                                }
                            )
                        } else {
                            e
                        }
                    })
            }
            LightShape::Cylinder { radius, length } => {
                CylinderLight::new(base, *radius, *length, self.options.cone_clipping)
                    .map(Light::Cylinder)
            }
            LightShape::Distant { angle_deg } => {
                DistantLight::new(base, *angle_deg).map(Light::Distant)
            }
            LightShape::Dome => DomeLight::new(base, texture).map(Light::Dome),
            LightShape::Portal { .. } => Err(
                "PortalLight is not rendered (lux does not restrict dome lights to portals)"
                    .to_owned(),
            ),
            LightShape::Mesh { .. } => match mesh {
                Some(mi) => MeshLight::new(base, mi, &self.scene.meshes[mi]).map(Light::Mesh),
                None => Err("mesh light without drawn geometry".to_owned()),
            },
        }
        .map_err(Skip::Warn)?;
        // Base emission: the stage's up axis in the dome texture's frame (for a photometric
        // dome's illuminance).
        let world_up = match self.scene.up_axis {
            UpAxis::Z => DVec3::Z,
            UpAxis::Y => DVec3::Y,
        };
        let dome_up = xf.inv_vector(world_up);
        let radiance = physical::base_radiance(
            l,
            &light.base().shaping,
            tex.as_deref(),
            dome_up,
            profile,
            self.scene.unit_for_wavelength,
        )?;
        let area = lux_math::size_factor(&l.shape, &l.light_to_world, Profile::Spec);
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
        let b = light.base_mut();
        b.links = super::LightLinks::new(self.scene, &l.linking);
        b.radiance = radiance;
        b.camera_visible = camera_visible;
        b.diffuse = if l.diffuse.is_finite() {
            l.diffuse.max(0.0)
        } else {
            0.0
        };
        b.specular = if l.specular.is_finite() {
            l.specular.max(0.0)
        } else {
            0.0
        };
        let power = light.power(area);
        light.base_mut().power = if power.is_finite() { power } else { 0.0 };
        Ok(light)
    }

    /// The light of the scene mesh `mi` whose material emits `emissive` (UsdPreviewSurface
    /// `emissiveColor`, radiance), drawn in the world (`instance` `None`) or by the instance
    /// `instance` of its prototype: emissive geometry is light, sampled and found by rays as a
    /// `MeshLightAPI` mesh is, of radiance `emissive` from each side the mesh shows (one side
    /// for a single-sided mesh), unshaped and with the default shadows.
    ///
    /// An instance's light emits from the prototype mesh mapped to the world as flattening
    /// maps it (`lux_usd::Mesh::transformed`): positions `M·v` by `DMat4::transform_point3`,
    /// the winding reversed when `det M < 0`; so its triangles, areas, power and sampling are
    /// those of the flattened mesh, bit for bit. It is named by its instance-proxy path (a
    /// native instance) or by the prototype mesh and the instance (a point instance).
    pub(super) fn emissive_mesh(
        &self,
        mi: usize,
        instance: Option<usize>,
        emissive: DVec3,
    ) -> Result<Light, String> {
        let m = &self.scene.meshes[mi];
        let Some(ii) = instance else {
            return emitter(&m.path, mi, None, &m.positions, &m.triangles, m, emissive);
        };
        let inst = &self.scene.instances[ii];
        let to_world = inst.to_world;
        let positions: Vec<DVec3> = m
            .positions
            .iter()
            .map(|p| to_world.transform_point3(*p))
            .collect();
        // The geometry leaves such an instance out (`geometry::instances`): nothing to emit.
        if !positions.iter().all(|p| p.as_vec3().is_finite()) {
            return Err("its instance lies outside the f32 range the renderer draws".to_owned());
        }
        let mirror = glam::DMat3::from_mat4(to_world).determinant() < 0.0;
        let reversed: Vec<[u32; 3]>;
        let triangles = if mirror {
            reversed = m.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect();
            &reversed
        } else {
            &m.triangles
        };
        let path = if lux_usd::reader::is_prim_path(&inst.path) {
            self.scene.geometry_path(mi, Some(ii)).into_owned()
        } else {
            format!("{} (instance {})", m.path, inst.path)
        };
        emitter(&path, mi, Some(ii), &positions, triangles, m, emissive)
    }

    /// An asset of light `l` that cannot be used: an error when strict, else a warning.
    fn asset_problem(
        &mut self,
        l: &UsdLight,
        file: &Path,
        what: &str,
        message: String,
    ) -> Result<(), Skip> {
        if self.options.strict {
            return Err(Skip::Fail(RenderError::Asset {
                file: file.to_path_buf(),
                message,
            }));
        }
        self.warnings.push(format!(
            "{}: {message}; {} emits without its {what}",
            file.display(),
            l.path
        ));
        Ok(())
    }

    /// The ShapingAPI factor of `l` (identity without the API), with its IES profile.
    fn shaping(&mut self, l: &UsdLight) -> Result<Shaping, Skip> {
        let Some(s) = &l.shaping else {
            return Ok(Shaping::identity());
        };
        let profile = self.options.profile;
        let ies = match s.ies_file.as_ref() {
            None => None,
            Some(a) => match &a.resolved {
                Some(p) => match load_ies(&mut self.ies_cache, p, profile, &mut self.warnings) {
                    Ok(w) => Some(w),
                    Err(RenderError::Asset { file, message }) => {
                        self.asset_problem(l, &file, "IES profile", message)?;
                        None
                    }
                    Err(e) => return Err(Skip::Fail(e)),
                },
                None => {
                    let message = format!(
                        "inputs:shaping:ies:file of {} does not resolve to a file",
                        l.path
                    );
                    self.asset_problem(l, Path::new(&a.authored), "IES profile", message)?;
                    None
                }
            },
        };
        let params = ShapingParams {
            focus: s.focus,
            focus_tint: s.focus_tint,
            cone_angle_deg: s.cone_angle_deg,
            cone_softness: s.cone_softness,
            ies_angle_scale: s.ies_angle_scale,
            ies_normalize: s.ies_normalize,
        };
        let opts = ShapingOptions {
            profile,
            ..ShapingOptions::default()
        };
        Shaping::new(&params, ies, opts)
            .map_err(|e| Skip::Warn(format!("invalid ShapingAPI inputs ({e})")))
    }

    /// The texture of a RectLight or DomeLight (`inputs:texture:file`), looked up nearest-texel
    /// in the `HdEmbree` profile and bilinearly in `Spec`.
    fn texture(&mut self, l: &UsdLight) -> Result<Option<LightTexture>, Skip> {
        let (Some(a), LightKind::Rect | LightKind::Dome) = (&l.texture, l.kind) else {
            return Ok(None);
        };
        let Some(p) = &a.resolved else {
            let message = format!(
                "inputs:texture:file of {} does not resolve to a file",
                l.path
            );
            self.asset_problem(l, Path::new(&a.authored), "texture", message)?;
            return Ok(None);
        };
        match load_texture(&mut self.tex_cache, p) {
            Ok(tex) => Ok(Some(LightTexture {
                tex,
                nearest: self.options.profile == Profile::HdEmbree,
            })),
            Err(RenderError::Asset { file, message }) => {
                self.asset_problem(l, &file, "texture", message)?;
                Ok(None)
            }
            Err(e) => Err(Skip::Fail(e)),
        }
    }
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

/// Loads a light texture (once per file).
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

/// The light of emissive geometry: scene mesh `mi` (`m`) drawn by `instance`, from its
/// world-space `positions` and `triangles`, of radiance `emissive`.
fn emitter(
    path: &str,
    mi: usize,
    instance: Option<usize>,
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    m: &lux_usd::Mesh,
    emissive: DVec3,
) -> Result<Light, String> {
    let base = LightBase::new(
        path,
        LightTransform::IDENTITY,
        Shaping::identity(),
        lux_usd::ShadowInputs::default(),
    );
    let mut light = MeshLight::from_world(base, mi, instance, positions, triangles, m.double_sided)
        .map(Light::Mesh)?;
    let corners: Vec<[DVec3; 3]> = triangles
        .iter()
        .map(|t| t.map(|k| positions[k as usize]))
        .collect();
    let area = lux_math::mesh_area(&glam::DMat4::IDENTITY, &corners);
    light.base_mut().radiance = emissive;
    let power = light.power(area);
    light.base_mut().power = if power.is_finite() { power } else { 0.0 };
    Ok(light)
}
