//! Every light of a scene, prepared, and how the light to sample at a shading point is chosen:
//! all lights, one by power, or one by the light BVH's importance.

use super::Light;
use super::load::Loader;
use crate::RenderError;
use lux_math::Profile;
use lux_sample::{LightBounds, LightBvh, LightSelector};
use lux_usd::Scene;

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
    /// Sample shaped rect and cylinder lights only where their emission cone reaches the
    /// receiver (`with_emission_cone` of lux-sample); `false` samples the whole light, for
    /// A/B measurements of the clipping. Images agree in expectation either way.
    pub cone_clipping: bool,
}

/// Every light of a scene, prepared, with the selection strategy.
pub struct LightSet {
    /// The lights, in scene order (lights that cannot emit are left out, with a warning).
    pub lights: Vec<Light>,
    /// For each scene mesh, the index in `lights` of the mesh light it carries.
    pub mesh_light: Vec<Option<usize>>,
    /// `None` = sample every light at every shading point.
    pub selector: Option<LightSelector>,
    /// Lights at infinity that a ray escaping the scene reaches (not the delta ones), in order.
    pub infinite: Vec<usize>,
    /// Lights at infinity shown as the background of camera rays that miss, in order.
    pub background: Vec<usize>,
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
        let mut loader = Loader::new(scene, options);
        let mut lights = Vec::new();
        let mut mesh_light = vec![None; scene.meshes.len()];
        for (li, l) in scene.lights.iter().enumerate() {
            // Only a world-space mesh is drawn where its positions say (a prototype's mesh is in
            // prototype space; the loader never gives one MeshLightAPI).
            let mesh = scene
                .meshes
                .iter()
                .position(|m| m.light == Some(li) && m.prototype.is_none());
            let prepared = match loader.light(l, mesh) {
                Ok(p) => p,
                Err(e) if options.strict => return Err(e),
                // One light's unusable inputs (a spectrum lux-spectral refuses…) leave that
                // light out, named, and never the others.
                Err(e) => {
                    loader
                        .warnings
                        .push(format!("{e}; the light is not rendered"));
                    None
                }
            };
            if let Some(mut rl) = prepared {
                if let Some(m) = mesh {
                    mesh_light[m] = Some(lights.len());
                    sync_with_material(&mut rl, l, &scene.meshes[m], scene);
                }
                lights.push(rl);
            }
        }
        // Emissive geometry (UsdPreviewSurface emissiveColor) is light too.
        for (mi, m) in scene.meshes.iter().enumerate() {
            let Some(e) = m.material.map(|k| scene.materials[k].emissive) else {
                continue;
            };
            if mesh_light[mi].is_some() || e.max_element() <= 0.0 {
                continue;
            }
            if m.prototype.is_some() {
                loader.warnings.push(format!(
                    "{}: emissive geometry inside an instanced prototype does not light the scene yet",
                    m.path
                ));
                continue;
            }
            match loader.emissive_mesh(mi, e) {
                Ok(l) => {
                    mesh_light[mi] = Some(lights.len());
                    lights.push(l);
                }
                Err(msg) => loader.warnings.push(format!(
                    "{}: emissive geometry: {msg}; it does not light the scene",
                    m.path
                )),
            }
        }
        let mut warnings = loader.warnings;
        let selector = build_selector(&lights, options.selection, &mut warnings);
        let infinite = (0..lights.len())
            .filter(|&i| lights[i].is_infinite() && !lights[i].is_delta())
            .collect();
        let background = (0..lights.len())
            .filter(|&i| lights[i].is_infinite() && lights[i].base().camera_visible)
            .collect();
        Ok(LightSet {
            lights,
            mesh_light,
            selector,
            infinite,
            background,
            warnings,
        })
    }
}

fn build_selector(
    lights: &[Light],
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
            let p: Vec<f64> = lights.iter().map(|l| l.base().power).collect();
            LightSelector::power(&p)
        }
        _ => {
            let bounds: Vec<Option<LightBounds>> = lights.iter().map(Light::bounds).collect();
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

/// `materialSyncMode` of a `MeshLightAPI` light `rl` on `mesh` (geometry-lights proposal,
/// "Synchronizing Light with Material"), when the mesh has a bound UsdPreviewSurface:
/// - `materialGlowTintsLight` (default): the light's radiance is multiplied by the material's
///   `emissiveColor`, and camera rays see the material's glow;
/// - `independent`: the light's radiance as authored, camera rays see the material's glow;
/// - `noMaterialResponse`: the light's radiance everywhere (and no surface response,
///   `Materials`).
///
/// lux's choice for secondary rays: the light's radiance, so that light samples and BSDF rays
/// that hit the mesh estimate one emission with MIS (the proposal lets them see the glow).
fn sync_with_material(rl: &mut Light, l: &lux_usd::Light, mesh: &lux_usd::Mesh, scene: &Scene) {
    let Light::Mesh(ml) = rl else {
        return;
    };
    let Some(m) = mesh.material.map(|k| &scene.materials[k]) else {
        return;
    };
    if !m.preview {
        return;
    }
    match l.material_sync_mode {
        lux_usd::MaterialSyncMode::MaterialGlowTintsLight => {
            // Power ∝ luminance(radiance): rescale it with the tinted radiance.
            let before = lux_math::luminance(ml.base.radiance);
            ml.base.radiance *= m.emissive;
            let after = lux_math::luminance(ml.base.radiance);
            ml.base.power = if before > 0.0 {
                ml.base.power * (after / before)
            } else {
                0.0
            };
            ml.glow = Some(m.emissive);
        }
        lux_usd::MaterialSyncMode::Independent => ml.glow = Some(m.emissive),
        lux_usd::MaterialSyncMode::NoMaterialResponse => {}
    }
}
