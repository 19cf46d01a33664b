//! Instancing: native instances (`instanceable` prims sharing a `/__Prototype_N`) and
//! `UsdGeomPointInstancer`s. A prototype is walked once, its meshes stored once in its own
//! space ([`crate::Prototype`]); each placement is an [`crate::Instance`] (a transform), so
//! memory grows with unique geometry, not with the instance count. Lights, cameras and
//! `MeshLightAPI` meshes inside a prototype are placed per instance as world objects; instances
//! nested in a prototype are placed with the product of the transforms.
//!
//! ## PointInstancer
//!
//! An instancer places `protoIndices.len()` instances; instance `i` draws prototype
//! `prototypes[protoIndices[i]]` with the transform `ComputeInstanceTransformsAtTime` gives
//! (UsdGeomPointInstancer, "Computing an Instance Transform"): in USD's row-vector form
//! `protoRootXform · scale(scales[i]) · rotate(orientations[i]) · translate(positions[i])`,
//! then the instancer's own world transform — in glam's column form
//! `instancerWorld · T(pᵢ) · R(qᵢ) · S(sᵢ) · protoRoot`. The prototype root's local transform
//! is part of the prototype's space here ([`crate::Prototype`]), so an [`crate::Instance`]
//! carries `instancerWorld · T · R · S`.
//!
//! Masking: an instance whose id (`ids[i]`, or `i` when `ids` is not authored) is in
//! `invisibleIds` or in the `inactiveIds` list-op metadata is not drawn. Velocities,
//! accelerations and angular velocities (motion blur) are not used: the instances are where
//! `positions` puts them at the load time.

use crate::error::{LoadError, WarningKind};
use crate::reader::Reader;
use crate::walk::{Inherited, Walk, add_counts};
use crate::{Camera, GprimCounts, Instance, Light, Mesh, Prototype, Scene};
use glam::{DMat4, DQuat, DVec3};
use openusd::usd::Prim;
use std::collections::{HashMap, HashSet};

/// Where the walk puts what it finds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// The world (the stage's own prims).
    World,
    /// The prototype being walked (index into [`ProtoWalk::data`]).
    Proto(usize),
}

/// An instance inside a prototype, placed when the prototype is.
#[derive(Clone, Debug)]
pub struct NestedInstance {
    /// The inner prototype (index into [`ProtoWalk::data`]).
    pub proto: usize,
    /// Inner-prototype-to-outer-prototype transform.
    pub to_outer: DMat4,
    /// The binding on the inner instance's side.
    pub material: Option<usize>,
    /// The inner instance's path relative to the outer prototype (`/A/B`, or `/PI[3]`).
    pub name: String,
}

/// What a prototype walk collected.
#[derive(Clone, Debug, Default)]
pub struct ProtoData {
    /// The prototype's prim path.
    pub path: String,
    /// Its meshes' [`Prototype`] (index into `Scene::prototypes`), made on the first mesh.
    pub prototype: Option<usize>,
    /// Lights, in prototype space.
    pub lights: Vec<Light>,
    /// `MeshLightAPI` meshes with their lights, in prototype space.
    pub light_meshes: Vec<(Mesh, Light)>,
    /// Cameras, in prototype space.
    pub cameras: Vec<Camera>,
    /// Instances inside the prototype.
    pub nested: Vec<NestedInstance>,
    /// Gprims as usd-core counts them under one instance.
    pub counts: GprimCounts,
    /// False while the prototype is being walked (a prototype reached from itself is a cycle).
    pub complete: bool,
}

/// The prototypes walked so far.
#[derive(Debug, Default)]
pub struct ProtoWalk {
    /// Walk results, indexed by [`Target::Proto`].
    pub data: Vec<ProtoData>,
    /// Prototype prim path → index into `data`.
    pub by_path: HashMap<String, usize>,
}

impl ProtoWalk {
    /// The [`Prototype`] of walk result `pd`, created in `scene` on first use.
    pub fn prototype_of(&mut self, pd: usize, scene: &mut Scene) -> usize {
        if let Some(p) = self.data[pd].prototype {
            return p;
        }
        let p = scene.prototypes.len();
        scene.prototypes.push(Prototype {
            path: self.data[pd].path.clone(),
            meshes: Vec::new(),
        });
        self.data[pd].prototype = Some(p);
        p
    }
}

/// `T(p) · R(q) · S(s)` (column form): scale, then rotate, then translate — UsdGeomPointInstancer's
/// per-instance transform. The rotation is `GfMatrix4d::SetRotate(GfQuatd)`'s, the unit-
/// quaternion formula applied to the quaternion as authored (usd-core does not normalise it, so
/// neither does lux: a `quath` that is a few ulps off unit length scales a little, in both);
/// a non-finite quaternion counts as the identity rotation.
pub fn instance_transform(position: DVec3, orientation: DQuat, scale: DVec3) -> DMat4 {
    let q = if orientation.is_finite() {
        orientation
    } else {
        DQuat::IDENTITY
    };
    DMat4::from_scale_rotation_translation(scale, q, position)
}

/// The instances an instancer places, before its prototypes are known to be usable.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointInstances {
    /// Number of `protoIndices` entries (what usd-core counts as instances).
    pub authored: usize,
    /// Drawn instances: (index into `protoIndices`, prototype index, instance transform in the
    /// instancer's space). Masked instances are left out.
    pub placed: Vec<(usize, usize, DMat4)>,
}

/// Reads a PointInstancer's instance arrays at the load time. Inconsistent data is reported as
/// warnings naming the prim: `positions` shorter than `protoIndices` places no instance at all
/// (usd-core's `ComputeInstanceTransformsAtTime` fails likewise); `orientations`/`scales` of
/// the wrong length are ignored; an index past `prototype_count` skips that instance.
pub fn read_point_instances(
    r: &mut Reader<'_>,
    prim: &Prim,
    prototype_count: usize,
) -> Result<PointInstances, LoadError> {
    let indices = r.int_array(prim, "protoIndices")?.unwrap_or_default();
    let n = indices.len();
    let mut out = PointInstances {
        authored: n,
        placed: Vec::new(),
    };
    if n == 0 {
        return Ok(out);
    }
    let positions = r.vec3_array(prim, "positions")?.unwrap_or_default();
    if positions.len() != n {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!(
                "positions has {} entries for {n} protoIndices; no instance drawn",
                positions.len()
            ),
        );
        return Ok(out);
    }
    // `orientationsf` (quatf[]) is the newer, preferred form; `orientations` (quath[]) the
    // original one.
    let mut orientations = None;
    for name in ["orientationsf", "orientations"] {
        if let Some(q) = r.quat_array(prim, name)? {
            if q.len() == n {
                orientations = Some(q);
                break;
            }
            r.warn(
                prim,
                WarningKind::InvalidGeometry,
                format!(
                    "{name} has {} entries for {n} protoIndices; ignored",
                    q.len()
                ),
            );
        }
    }
    let scales = match r.vec3_array(prim, "scales")? {
        Some(s) if s.len() == n => Some(s),
        Some(s) => {
            r.warn(
                prim,
                WarningKind::InvalidGeometry,
                format!(
                    "scales has {} entries for {n} protoIndices; ignored",
                    s.len()
                ),
            );
            None
        }
        None => None,
    };
    let ids = match r.int_array(prim, "ids")? {
        Some(ids) if ids.len() == n => Some(ids),
        Some(ids) => {
            r.warn(
                prim,
                WarningKind::InvalidGeometry,
                format!(
                    "ids has {} entries for {n} protoIndices; ignored",
                    ids.len()
                ),
            );
            None
        }
        None => None,
    };
    let mut hidden: HashSet<i64> = r
        .int_array(prim, "invisibleIds")?
        .unwrap_or_default()
        .into_iter()
        .collect();
    hidden.extend(r.int64_list_metadata(prim, "inactiveIds")?);
    let mut bad_index = 0usize;
    for (i, &pi) in indices.iter().enumerate() {
        let id = ids.as_ref().map_or(i as i64, |ids| ids[i]);
        if hidden.contains(&id) {
            continue;
        }
        let Some(proto) = usize::try_from(pi).ok().filter(|p| *p < prototype_count) else {
            bad_index += 1;
            continue;
        };
        let q = orientations.as_ref().map_or(DQuat::IDENTITY, |o| o[i]);
        let s = scales.as_ref().map_or(DVec3::ONE, |s| s[i]);
        let m = instance_transform(positions[i], q, s);
        if !m.is_finite() {
            bad_index += 1;
            continue;
        }
        out.placed.push((i, proto, m));
    }
    if bad_index > 0 {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!(
                "{bad_index} instances skipped: protoIndices outside the {prototype_count} \
                 prototypes, or a non-finite position/orientation/scale"
            ),
        );
    }
    Ok(out)
}

impl Walk<'_> {
    /// Walks a prototype once, keyed by `key` (the prototype's path): the subtree at `root`
    /// — for a PointInstancer prototype the root prim itself (its own transform is part of the
    /// prototype's space, and whether prims are defined is judged from the root down); for a
    /// native instance the children of the first instance met (instance proxies: their
    /// composition is the prototype's, and they are active even when the referenced source is
    /// not, as the instance prim's own opinions decide that). `None` when the prototype is
    /// being walked already (a cycle) or does not exist.
    fn walk_prototype(
        &mut self,
        key: &str,
        root: &Prim,
        include_root: bool,
        inherited: &Inherited,
        depth: usize,
    ) -> Result<Option<usize>, LoadError> {
        if let Some(&pd) = self.protos.by_path.get(key) {
            return Ok(self.protos.data[pd].complete.then_some(pd));
        }
        let path = root.path().to_string();
        if !crate::reader::is_prim_path(&path) || !self.usd(root, root.is_valid())? {
            return Ok(None);
        }
        let pd = self.protos.data.len();
        self.protos.data.push(ProtoData {
            path,
            ..ProtoData::default()
        });
        self.protos.by_path.insert(key.to_owned(), pd);
        let start = Inherited {
            world: DMat4::IDENTITY,
            visible: true,
            target: Target::Proto(pd),
            defined_from_root: include_root,
            ..inherited.clone()
        };
        if include_root {
            self.visit(root, &start, depth + 1)?;
        } else {
            for child in self.usd(root, root.children())? {
                self.visit(&child, &start, depth + 1)?;
            }
        }
        self.protos.data[pd].complete = true;
        Ok(Some(pd))
    }

    /// A native instance: its prototype (walked once) placed at the instance's transform, with
    /// the instance's binding for prototype meshes that have none of their own. Counted once
    /// per instance, like usd-core's traversal of instance proxies.
    pub(crate) fn native_instance(
        &mut self,
        prim: &Prim,
        here: &Inherited,
        depth: usize,
    ) -> Result<(), LoadError> {
        let Some(proto) = self.usd(prim, prim.prototype())? else {
            return Ok(());
        };
        let proto = proto.to_string();
        let inherited = Inherited {
            bindings: None,
            ..here.clone()
        };
        // The instance's material first: the prototype's meshes without a binding of their
        // own read the primvars it reads (walk.rs).
        let material = match crate::binding::resolve(here.bindings.as_ref(), prim.path().as_str()) {
            Some(b) => Some(self.material(&b)?),
            None => None,
        };
        let Some(pd) = self.walk_prototype(&proto, prim, false, &inherited, depth)? else {
            self.r.warn(
                prim,
                WarningKind::InvalidGeometry,
                format!("instance of prototype {proto} that contains itself; skipped"),
            );
            return Ok(());
        };
        let counts = self.protos.data[pd].counts.clone();
        let into = self.counts(here.target);
        add_counts(into, &counts, 1);
        into.native_instances += 1;
        let path = prim.path().to_string();
        self.place_or_nest(pd, here, DMat4::IDENTITY, material, path, depth)
    }

    /// A PointInstancer: its prototypes (each walked once, with the root's transform), then one
    /// placement per unmasked `protoIndices` entry.
    pub(crate) fn point_instancer(
        &mut self,
        prim: &Prim,
        here: &Inherited,
        depth: usize,
    ) -> Result<(), LoadError> {
        let path = prim.path().to_string();
        let targets = self.r.targets(prim, "prototypes")?;
        let mut protos = Vec::with_capacity(targets.len());
        for t in &targets {
            let bindings = self.inherited_bindings(t)?;
            let inherited = Inherited {
                bindings,
                purpose: "default".into(),
                purpose_inheritable: false,
                ..here.clone()
            };
            let root = self.r.stage.prim(t.as_str());
            let pd = self.walk_prototype(t, &root, true, &inherited, depth)?;
            match pd {
                None => self.r.warn(
                    prim,
                    WarningKind::InvalidValue,
                    format!("prototype <{t}> does not exist or contains this instancer; its instances are skipped"),
                ),
                // A prototype authored below the instancer is traversed (and counted) there by
                // usd-core unless it sits under an `over`; one elsewhere is counted where it is
                // authored.
                Some(pd)
                    if t.starts_with(&format!("{path}/"))
                        && self.usd(&root, root.is_defined())? =>
                {
                    let counts = self.protos.data[pd].counts.clone();
                    add_counts(self.counts(here.target), &counts, 1);
                }
                Some(_) => {}
            }
            protos.push(pd);
        }
        let inst = read_point_instances(&mut self.r, prim, protos.len())?;
        self.counts(here.target).point_instances += inst.authored;
        for (i, proto, m) in inst.placed {
            if let Some(pd) = protos[proto] {
                self.place_or_nest(pd, here, m, None, format!("{path}[{i}]"), depth)?;
            }
        }
        Ok(())
    }

    /// Places prototype `pd` at `here.world · local` in the world, or records it as nested in
    /// the prototype being walked.
    fn place_or_nest(
        &mut self,
        pd: usize,
        here: &Inherited,
        local: DMat4,
        material: Option<usize>,
        path: String,
        depth: usize,
    ) -> Result<(), LoadError> {
        let to = here.world * local;
        match here.target {
            Target::World => self.place(pd, to, material, &path, depth),
            Target::Proto(outer) => {
                let prefix = &self.protos.data[outer].path;
                let name = path
                    .strip_prefix(prefix.as_str())
                    .unwrap_or(&path)
                    .to_owned();
                self.protos.data[outer].nested.push(NestedInstance {
                    proto: pd,
                    to_outer: to,
                    material,
                    name,
                });
                Ok(())
            }
        }
    }

    /// Places prototype `pd` in the world at `to_world`: one [`Instance`] for its meshes, its
    /// lights, cameras and mesh lights as world objects (paths under the instance's), and its
    /// nested instances.
    fn place(
        &mut self,
        pd: usize,
        to_world: DMat4,
        material: Option<usize>,
        path: &str,
        depth: usize,
    ) -> Result<(), LoadError> {
        if depth >= self.r.limits.max_depth {
            return Err(LoadError::TooLarge {
                file: self.r.file.clone(),
                prim: path.to_owned(),
                what: "instance nesting depth",
                count: depth + 1,
                limit: self.r.limits.max_depth,
            });
        }
        let d = &self.protos.data[pd];
        let rename = |p: &str| format!("{path}{}", p.strip_prefix(d.path.as_str()).unwrap_or(p));
        if let Some(p) = d.prototype {
            self.scene.instances.push(Instance {
                path: path.to_owned(),
                prototype: p,
                to_world,
                material,
            });
        }
        // A light's linking rules inside the prototype follow it to the instance (a point
        // instance's geometry is judged by its prototype's own paths: they stay).
        let relink = |l: &mut Light| {
            if crate::reader::is_prim_path(path) {
                l.linking.light = l.linking.light.reparented(&d.path, path);
                l.linking.shadow = l.linking.shadow.reparented(&d.path, path);
            }
        };
        for l in &d.lights {
            let mut l = l.clone();
            relink(&mut l);
            l.path = rename(&l.path);
            l.light_to_world = to_world * l.light_to_world;
            self.scene.lights.push(l);
        }
        for c in &d.cameras {
            let mut c = c.clone();
            c.path = rename(&c.path);
            c.camera_to_world = to_world * c.camera_to_world;
            self.scene.cameras.push(c);
        }
        for (m, l) in &d.light_meshes {
            let mut m = m.transformed(&to_world);
            m.path = rename(&m.path);
            m.material = m.material.or(material);
            let mut l = l.clone();
            relink(&mut l);
            l.path = rename(&l.path);
            l.light_to_world = to_world * l.light_to_world;
            m.light = Some(self.scene.lights.len());
            self.scene.lights.push(l);
            self.scene.meshes.push(m);
        }
        let nested = d.nested.clone();
        for n in nested {
            let p = format!("{path}{}", n.name);
            self.place(
                n.proto,
                to_world * n.to_outer,
                n.material.or(material),
                &p,
                depth + 1,
            )?;
        }
        Ok(())
    }

    /// The material binding sites of the ancestors of the prim at `path` (not its own).
    fn inherited_bindings(
        &mut self,
        path: &str,
    ) -> Result<Option<std::sync::Arc<crate::binding::Chain>>, LoadError> {
        let mut chain = None;
        let mut end = 0;
        while let Some(i) = path[end + 1..].find('/') {
            end += 1 + i;
            let prim = self.r.stage.prim(&path[..end]);
            chain = crate::binding::Chain::extend(&mut self.r, &prim, chain.as_ref())?;
        }
        Ok(chain)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transform_scales_then_rotates_then_translates() {
        let q = DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2);
        let m = instance_transform(DVec3::new(10.0, 0.0, 0.0), q, DVec3::new(2.0, 1.0, 1.0));
        // (1, 0, 0) → scaled (2, 0, 0) → rotated (0, 2, 0) → translated (10, 2, 0)
        let p = m.transform_point3(DVec3::X);
        assert!((p - DVec3::new(10.0, 2.0, 0.0)).length() < 1e-12, "{p}");
        // as USD's SetRotate: the unit-quaternion formula on the quaternion as given (the zero
        // quaternion gives the identity)
        let n = instance_transform(
            DVec3::ZERO,
            DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0),
            DVec3::ONE,
        );
        assert_eq!(n, DMat4::IDENTITY);
    }
}
