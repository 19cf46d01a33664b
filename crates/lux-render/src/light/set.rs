//! Every light of a scene, prepared, and how the light to sample at a shading point is chosen:
//! all lights, one by power, or one by the light BVH's importance.

use super::load::Loader;
use super::{Light, LightHit, LightShapes};
use crate::RenderError;
use glam::DVec3;
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
    /// For each scene mesh, the index in `lights` of the mesh light it carries in the world
    /// (a prototype's mesh carries none: see [`LightSet::light_of`]).
    pub mesh_light: Vec<Option<usize>>,
    /// The emissive geometry of instances: `(instance, mesh)` (indices into
    /// `Scene::instances` and `Scene::meshes`) of `lights[instanced_first + k]` at `k`, in
    /// increasing order.
    instanced: Vec<(u32, u32)>,
    /// Index in `lights` of the first instance's light.
    instanced_first: usize,
    /// `None` = sample every light at every shading point.
    pub selector: Option<LightSelector>,
    /// Lights at infinity that a ray escaping the scene reaches (not the delta ones), in order.
    pub infinite: Vec<usize>,
    /// Lights at infinity shown as the background of camera rays that miss, in order.
    pub background: Vec<usize>,
    /// Non-fatal problems met while preparing the lights.
    pub warnings: Vec<String>,
    /// The analytic area lights' surfaces in a BVH of their own ([`LightShapes`]).
    pub shapes: LightShapes,
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
                // Emits once per instance (below).
                continue;
            }
            match loader.emissive_mesh(mi, None, e) {
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
        let instanced_first = lights.len();
        let instanced =
            instanced_emitters(scene, &mut loader, &mut lights, MAX_INSTANCED_EMITTER_BYTES);
        lights.shrink_to_fit();
        let mut warnings = loader.warnings;
        let selector = build_selector(&lights, options.selection, &mut warnings);
        let infinite = (0..lights.len())
            .filter(|&i| lights[i].is_infinite() && !lights[i].is_delta())
            .collect();
        let background = (0..lights.len())
            .filter(|&i| lights[i].is_infinite() && lights[i].base().camera_visible)
            .collect();
        let shapes = LightShapes::new(&lights);
        Ok(LightSet {
            shapes,
            lights,
            mesh_light,
            instanced,
            instanced_first,
            selector,
            infinite,
            background,
            warnings,
        })
    }
}

impl LightSet {
    /// The closest analytic light on `origin + t·dir`, `t ∈ (tmin, tmax)`, among those
    /// `visible` keeps (a camera ray: the camera-visible ones), the lower index on a tie.
    #[inline]
    pub fn closest_light(
        &self,
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
        visible: impl Fn(&Light) -> bool,
    ) -> Option<(usize, LightHit)> {
        self.shapes
            .closest(&self.lights, origin, dir, tmin, tmax, visible)
    }

    /// Calls `f` with every analytic light crossing `origin + t·dir`, `t ∈ (tmin, tmax)`, and
    /// its hit, by light index (lights do not occlude one another).
    #[inline]
    pub fn lights_crossed(
        &self,
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
        f: impl FnMut(usize, LightHit),
    ) {
        self.shapes
            .crossed(&self.lights, origin, dir, tmin, tmax, f)
    }

    /// The light that the scene mesh `mesh` drawn by `instance` (`None`: a world mesh) carries:
    /// what a ray hitting that geometry found, for its emission and MIS weight.
    #[inline]
    pub fn light_of(&self, mesh: usize, instance: Option<usize>) -> Option<usize> {
        match instance {
            None => self.mesh_light.get(mesh).copied().flatten(),
            Some(_) if self.instanced.is_empty() => None,
            Some(i) => self
                .instanced
                .binary_search(&(i as u32, mesh as u32))
                .ok()
                .map(|k| self.instanced_first + k),
        }
    }

    /// Number of lights emitting from instanced geometry (one per instance and emissive
    /// prototype mesh).
    pub fn instanced_count(&self) -> usize {
        self.instanced.len()
    }
}

/// Most light data (estimated by [`emitter_bytes`]) that the emissive geometry of instances
/// may make: 1 GiB, about 440 000 instances of an emissive two-triangle card. Instances past
/// it do not light the scene (a warning says how many).
pub const MAX_INSTANCED_EMITTER_BYTES: usize = 1 << 30;

/// Estimated bytes of an instance's light of `triangles` triangles: the [`Light`] (1704
/// bytes, whatever the kind), its sampler's world triangles and alias table (120 bytes a
/// triangle), and its name, its share of the light BVH and its hit-index entry (≈ 480 bytes).
/// For a two-triangle card that is 2424 bytes; `emissive_instance_memory.rs` measures 2412.
fn emitter_bytes(triangles: usize) -> usize {
    size_of::<Light>() + 120 * triangles + 480
}

/// One light per instance and emissive mesh of its prototype (a mesh whose own material, or
/// else its instance's, has a non-black `emissiveColor`), appended to `lights` in (instance,
/// mesh) order, while their estimated bytes ([`emitter_bytes`]) fit in `budget`; returns
/// those pairs. Instances that are not drawn (a transform that is not finite or singular, a
/// prototype out of range) emit nothing. Failures are one warning per prototype mesh, not per
/// instance.
fn instanced_emitters(
    scene: &Scene,
    loader: &mut Loader,
    lights: &mut Vec<Light>,
    mut budget: usize,
) -> Vec<(u32, u32)> {
    let limit = budget;
    let np = scene.prototypes.len();
    if scene.instances.is_empty() || np == 0 {
        return Vec::new();
    }
    // A prototype's meshes as the geometry draws them (`Mesh::prototype`), and whether any can
    // emit in some instance (its own material, else one of its instances'), so that instances
    // of prototypes that cannot emit cost nothing.
    let emits = |k: Option<usize>| {
        k.and_then(|k| scene.materials.get(k))
            .is_some_and(|m| m.emissive.max_element() > 0.0)
    };
    let instance_emits = scene.instances.iter().any(|i| emits(i.material));
    let mut proto_meshes: Vec<Vec<usize>> = vec![Vec::new(); np];
    for (mi, m) in scene.meshes.iter().enumerate() {
        if let Some(p) = m.prototype
            && p < np
            && m.light.is_none()
            && (emits(m.material) || (m.material.is_none() && instance_emits))
        {
            proto_meshes[p].push(mi);
        }
    }
    if proto_meshes.iter().all(Vec::is_empty) {
        return Vec::new();
    }
    let mut keys = Vec::new();
    let mut over_budget = 0usize;
    // Per prototype mesh: (instances whose light failed, the first reason).
    let mut failed: Vec<(usize, usize, String)> = Vec::new();
    for (ii, inst) in scene.instances.iter().enumerate().take(u32::MAX as usize) {
        let Some(meshes) = proto_meshes.get(inst.prototype) else {
            continue;
        };
        if meshes.is_empty() || !crate::geometry::drawable_transform(&inst.to_world) {
            continue;
        }
        for &mi in meshes {
            let m = &scene.meshes[mi];
            let e = m
                .material
                .or(inst.material)
                .and_then(|k| scene.materials.get(k))
                .map_or(DVec3::ZERO, |k| k.emissive);
            if e.max_element() <= 0.0 {
                continue;
            }
            let cost = emitter_bytes(m.triangles.len());
            if cost > budget {
                over_budget += 1;
                continue;
            }
            match loader.emissive_mesh(mi, Some(ii), e) {
                Ok(l) => {
                    budget -= cost;
                    keys.push((ii as u32, mi as u32));
                    lights.push(l);
                }
                Err(msg) => match failed.iter_mut().find(|f| f.0 == mi) {
                    Some(f) => f.1 += 1,
                    None => failed.push((mi, 1, msg)),
                },
            }
        }
    }
    for (mi, n, msg) in failed {
        loader.warnings.push(format!(
            "{}: emissive geometry inside an instanced prototype: {msg}; it does not light \
             the scene ({n} instance{})",
            scene.meshes[mi].path,
            if n == 1 { "" } else { "s" }
        ));
    }
    keys.shrink_to_fit();
    if over_budget > 0 {
        loader.warnings.push(format!(
            "emissive geometry inside instanced prototypes: {over_budget} more instance \
             meshes neither light the scene nor glow (they are drawn unlit): the first {} \
             hold the {} MiB of light data lux allows them",
            keys.len(),
            limit >> 20
        ));
    }
    keys
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

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DMat4;
    use lux_usd::{Instance, Material, Mesh, Prototype};

    fn options() -> LightOptions {
        LightOptions {
            profile: Profile::Spec,
            selection: LightSelection::All,
            strict: false,
            cone_clipping: true,
        }
    }

    /// Prototype 0: an emissive card (mesh 0) and a degenerate emissive triangle (mesh 1);
    /// prototype 1: a plain card (mesh 2) without a binding of its own.
    fn scene(instances: Vec<(usize, DMat4, Option<usize>)>) -> Scene {
        let mut s = Scene::empty("emitters.usda");
        s.materials.push(Material {
            emissive: DVec3::ONE,
            ..Material::new("/Glow")
        });
        s.materials.push(Material::new("/Plain"));
        let card = |path: &str| {
            Mesh::new(
                path,
                vec![
                    DVec3::new(0.0, 0.0, 0.0),
                    DVec3::new(1.0, 0.0, 0.0),
                    DVec3::new(1.0, 0.0, 1.0),
                    DVec3::new(0.0, 0.0, 1.0),
                ],
                vec![[0, 1, 2], [0, 2, 3]],
            )
        };
        let mut glow = card("/P0/Glow");
        glow.material = Some(0);
        glow.prototype = Some(0);
        let mut flat = Mesh::new("/P0/Flat", vec![DVec3::ZERO; 3], vec![[0, 1, 2]]);
        flat.material = Some(0);
        flat.prototype = Some(0);
        let mut plain = card("/P1/Card");
        plain.prototype = Some(1);
        s.meshes = vec![glow, flat, plain];
        s.prototypes = vec![
            Prototype {
                path: "/P0".to_owned(),
                meshes: vec![0, 1],
            },
            Prototype {
                path: "/P1".to_owned(),
                meshes: vec![2],
            },
        ];
        s.instances = instances
            .into_iter()
            .enumerate()
            .map(|(i, (prototype, to_world, material))| Instance {
                path: format!("/PI[{i}]"),
                prototype,
                to_world,
                material,
            })
            .collect();
        s
    }

    #[test]
    fn instances_emit_by_their_material_once_each() {
        let t = |x: f64| DMat4::from_translation(DVec3::new(x, 1.0, 0.0));
        let s = scene(vec![
            (0, t(0.0), None),
            // Singular: not drawn, no light, no warning.
            (0, DMat4::from_scale(DVec3::new(1.0, 0.0, 1.0)), None),
            // The plain card glows where its instance binds the emissive material.
            (1, t(2.0), Some(0)),
            (1, t(4.0), Some(1)),
            (1, t(6.0), None),
            (0, t(8.0), Some(1)),
            // Outside the f32 range the geometry draws.
            (0, t(1e300), None),
        ]);
        let set = LightSet::new(&s, options()).unwrap();
        // (instance, mesh): 0's card, 2's card, 5's card (its own binding wins).
        assert_eq!(set.instanced, vec![(0, 0), (2, 2), (5, 0)]);
        assert_eq!(set.lights.len(), 3);
        for (k, &(i, m)) in set.instanced.iter().enumerate() {
            assert_eq!(set.light_of(m as usize, Some(i as usize)), Some(k));
            assert_eq!(set.lights[k].mesh(), Some(m as usize));
        }
        assert_eq!(set.light_of(2, Some(3)), None);
        assert_eq!(set.light_of(0, None), None);
        // One warning per prototype mesh, in the order they first failed: the degenerate
        // triangle in its 3 drawn instances, the card in the instance outside the f32 range.
        assert_eq!(set.warnings.len(), 2, "{:?}", set.warnings);
        let w = &set.warnings;
        assert!(
            w[0].starts_with("/P0/Flat: ") && w[0].ends_with("(3 instances)"),
            "{w:?}"
        );
        assert!(
            w[1].starts_with("/P0/Glow: ") && w[1].ends_with("(1 instance)"),
            "{w:?}"
        );
        assert!(w[1].contains("outside the f32 range"), "{w:?}");
    }

    #[test]
    fn instanced_emitters_stop_at_their_budget_with_a_warning() {
        let t = |x: f64| DMat4::from_translation(DVec3::new(x, 1.0, 0.0));
        let s = scene((0..5).map(|i| (1, t(i as f64), Some(0))).collect());
        let mut loader = Loader::new(&s, options());
        let mut lights = Vec::new();
        let keys = instanced_emitters(&s, &mut loader, &mut lights, 3 * emitter_bytes(2));
        assert_eq!(keys, vec![(0, 2), (1, 2), (2, 2)]);
        assert_eq!(lights.len(), 3);
        assert_eq!(loader.warnings.len(), 1);
        assert!(
            loader.warnings[0].contains("2 more instance meshes"),
            "{}",
            loader.warnings[0]
        );
    }
}
