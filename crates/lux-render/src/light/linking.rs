//! Light and shadow linking (UsdLux `LightAPI` `collection:lightLink` /
//! `collection:shadowLink`, read by lux-usd as [`lux_usd::Linking`]) in the renderer.
//!
//! Each collection that is not "everything" is resolved once, when the lights are prepared,
//! into a [`GeomSet`]: a bit per scene mesh for the world meshes, and per scene instance
//! whether all, none or some of its prototype's meshes are members (the members of the mixed
//! ones in a set). Geometry is judged by [`lux_usd::Scene::geometry_path`].
//!
//! - **lightLink**: a light whose collection does not hold the shaded geometry contributes
//!   nothing there — neither by light sampling nor when a BSDF ray finds it — so both MIS
//!   techniques agree ([`LightBase::illuminates`]). Light reaching the geometry indirectly
//!   (through linked surfaces, in the path integrator) is not affected.
//! - **shadowLink**: a shadow ray towards a light whose collection does not hold an occluder
//!   passes through it ([`first_shadow_occluder`]): the ray is cast again from just past it,
//!   at most [`MAX_PASS_THROUGH`] times. Such a light counts as not having plain shadows
//!   ([`LightBase::plain_shadows`]), so it is estimated by light sampling alone (a BSDF ray
//!   stops at the first surface, linked or not).
//!
//! A light without authored linking has no sets and takes exactly the code paths of a scene
//! without linking.

use super::LightBase;
use lux_usd::{Linking, Membership, Scene};
use std::collections::HashSet;
use std::sync::Arc;

/// Most occluders a shadow ray passes through (those outside the light's shadowLink) before
/// it counts as blocked.
pub const MAX_PASS_THROUGH: usize = 64;

/// Per scene instance: how many of its prototype's meshes are members.
const NONE: u8 = 0;
const ALL: u8 = 1;
const SOME: u8 = 2;

/// The drawn geometry a linking collection holds (a [`Membership`] resolved over a scene).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GeomSet {
    /// Bit `i` set: world mesh `Scene::meshes[i]` is a member.
    meshes: Vec<u64>,
    /// Per `Scene::instances` entry: none, all or some of its prototype's meshes are members.
    instances: Vec<u8>,
    /// The members `(instance, mesh)` of the instances with some members.
    mixed: HashSet<(u32, u32)>,
}

impl GeomSet {
    /// The geometry of `scene` that `m` holds.
    pub fn new(scene: &Scene, m: &Membership) -> GeomSet {
        let mut meshes = vec![0u64; scene.meshes.len().div_ceil(64)];
        for (i, mesh) in scene.meshes.iter().enumerate() {
            if mesh.prototype.is_none() && m.contains(&mesh.path) {
                meshes[i / 64] |= 1 << (i % 64);
            }
        }
        // A point instance's geometry is judged by the prototype's own mesh paths: the same
        // for every instance of the prototype, computed once.
        let mut by_prototype: Vec<Option<Vec<bool>>> = vec![None; scene.prototypes.len()];
        let mut instances = Vec::with_capacity(scene.instances.len());
        let mut mixed = HashSet::new();
        for (ii, inst) in scene.instances.iter().enumerate() {
            let Some(proto) = scene.prototypes.get(inst.prototype) else {
                instances.push(NONE);
                continue;
            };
            let judge = |scene: &Scene| -> Vec<bool> {
                proto
                    .meshes
                    .iter()
                    .map(|&mi| m.contains(&scene.geometry_path(mi, Some(ii))))
                    .collect()
            };
            let member = if lux_usd::reader::is_prim_path(&inst.path) {
                judge(scene)
            } else {
                by_prototype[inst.prototype]
                    .get_or_insert_with(|| judge(scene))
                    .clone()
            };
            let state = if member.iter().all(|&b| b) {
                ALL
            } else if !member.iter().any(|&b| b) {
                NONE
            } else {
                for (&mi, _) in proto.meshes.iter().zip(&member).filter(|(_, b)| **b) {
                    mixed.insert((ii as u32, mi as u32));
                }
                SOME
            };
            instances.push(state);
        }
        GeomSet {
            meshes,
            instances,
            mixed,
        }
    }

    /// Whether the mesh `mesh` (index into `Scene::meshes`) drawn by `instance` (index into
    /// `Scene::instances`, `None` for a world mesh) is a member.
    #[inline]
    pub fn contains(&self, mesh: usize, instance: Option<usize>) -> bool {
        match instance {
            None => self
                .meshes
                .get(mesh / 64)
                .is_some_and(|w| w & (1 << (mesh % 64)) != 0),
            Some(i) => match self.instances.get(i).copied() {
                Some(ALL) => true,
                Some(SOME) => self.mixed.contains(&(i as u32, mesh as u32)),
                _ => false,
            },
        }
    }
}

/// A light's linking collections resolved over the scene: `None` = every piece of geometry
/// (the default, tested nowhere).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LightLinks {
    /// `collection:lightLink`: the geometry the light illuminates.
    pub light: Option<Arc<GeomSet>>,
    /// `collection:shadowLink`: the geometry that casts the light's shadows.
    pub shadow: Option<Arc<GeomSet>>,
}

impl LightLinks {
    /// Resolves `linking` over `scene` (no set for a collection that holds everything).
    pub fn new(scene: &Scene, linking: &Linking) -> LightLinks {
        let set = |m: &Membership| (!m.is_all()).then(|| Arc::new(GeomSet::new(scene, m)));
        LightLinks {
            light: set(&linking.light),
            shadow: set(&linking.shadow),
        }
    }
}

impl LightBase {
    /// Whether the light illuminates the mesh `mesh` drawn by `instance` (its
    /// `collection:lightLink` holds it).
    #[inline]
    pub fn illuminates(&self, mesh: usize, instance: Option<usize>) -> bool {
        self.links
            .light
            .as_ref()
            .is_none_or(|s| s.contains(mesh, instance))
    }

    /// Whether the mesh `mesh` drawn by `instance` casts the light's shadows (its
    /// `collection:shadowLink` holds it).
    #[inline]
    pub fn casts_shadow(&self, mesh: usize, instance: Option<usize>) -> bool {
        self.links
            .shadow
            .as_ref()
            .is_none_or(|s| s.contains(mesh, instance))
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use glam::{DMat4, DVec3};
    use lux_usd::{Instance, Mesh, Prototype, Rule};

    /// A triangle at height `y` (normal along −Y), wide enough to block rays near the origin.
    pub(crate) fn tri(path: &str, y: f64) -> Mesh {
        Mesh::new(
            path,
            vec![
                DVec3::new(-1.0, y, -1.0),
                DVec3::new(-1.0, y, 3.0),
                DVec3::new(3.0, y, -1.0),
            ],
            vec![[0, 1, 2]],
        )
    }

    /// A collection of the given path rules.
    pub(crate) fn rules(entries: &[(&str, Rule)]) -> Membership {
        Membership::Rules(entries.iter().map(|(p, r)| ((*p).to_owned(), *r)).collect())
    }

    #[test]
    fn sets_over_world_meshes_and_instances() {
        let mut scene = Scene::empty("t.usda");
        scene.meshes = vec![tri("/W/a", 1.0), tri("/W/b", 2.0), tri("/P/x", 0.0)];
        scene.meshes.push(tri("/P/y", 0.0));
        scene.meshes[2].prototype = Some(0);
        scene.meshes[3].prototype = Some(0);
        scene.prototypes = vec![Prototype {
            path: "/P".into(),
            meshes: vec![2, 3],
        }];
        let inst = |p: &str| Instance {
            path: p.into(),
            prototype: 0,
            to_world: DMat4::IDENTITY,
            material: None,
        };
        scene.instances = vec![inst("/I1"), inst("/I2"), inst("/PI[0]")];
        let m = rules(&[
            ("/W/b", Rule::ExpandPrims),
            ("/I1", Rule::ExpandPrims),
            ("/I2/y", Rule::ExpandPrims),
            ("/P/x", Rule::ExpandPrims),
        ]);
        let s = GeomSet::new(&scene, &m);
        assert!(!s.contains(0, None) && s.contains(1, None));
        assert!(s.contains(2, Some(0)) && s.contains(3, Some(0)));
        assert!(!s.contains(2, Some(1)) && s.contains(3, Some(1)));
        // The point instance is judged by the prototype's paths.
        assert!(s.contains(2, Some(2)) && !s.contains(3, Some(2)));
        assert!(!s.contains(99, None) && !s.contains(2, Some(99)));
        assert_eq!(s.instances, vec![ALL, SOME, SOME]);
        let links = LightLinks::new(&scene, &Linking::default());
        assert_eq!(links, LightLinks::default());
    }
}
