//! The stage walk: one pass over the composed prims that accumulates transforms, visibility,
//! purpose and material bindings, and reads every drawn gprim, light and camera — into the
//! world, or into the instancing prototype being walked ([`crate::instancing`]).

use crate::arcs::{ArcProblem, missing_reference_targets};
use crate::camera::{read_camera, read_render_settings};
use crate::error::{LoadError, Warning, WarningKind};
use crate::instancing::{ProtoWalk, Target};
use crate::light::{is_unsupported_light_type, kind_of_type, read_light};
use crate::material::read_material;
use crate::mesh::{
    CornerPrimvar, Gprim, Mesh, Topology, expand_primvar, mesh_topology, mirror_corners,
    normals_to_world, to_world,
};
use crate::reader::Reader;
use crate::tessellate::{self, Axis};
use crate::xform::local_transform;
use crate::{GprimCounts, Scene};
use glam::DMat4;
use lux_math::LightKind;
use openusd::usd::Prim;
use std::collections::HashMap;

/// Gprim types lux does not draw; each is counted and reported once per load.
pub const SKIPPED_GPRIMS: [&str; 5] = [
    "HermiteCurves",
    "NurbsPatch",
    "TetMesh",
    "Volume",
    "ParticleField",
];

/// Inherited state of the walk.
#[derive(Clone)]
pub struct Inherited {
    /// Local-to-world transform (or local-to-prototype inside a prototype).
    pub world: DMat4,
    /// Visibility so far (an `invisible` ancestor hides everything below).
    pub visible: bool,
    /// Effective purpose.
    pub purpose: String,
    /// Whether `purpose` was authored on this prim or an ancestor (UsdGeomImageable
    /// `PurposeInfo::isInheritable`): children without their own purpose inherit it.
    pub purpose_inheritable: bool,
    /// The material binding sites of this prim and its ancestors ([`crate::binding`]).
    pub bindings: Option<std::sync::Arc<crate::binding::Chain>>,
    /// Where what is found goes.
    pub target: Target,
    /// Inside a PointInstancer prototype: whether a prim is defined is judged from the
    /// prototype root down (its own specifier and its ancestors' up to the root), so that
    /// prototypes authored under an `over` — the usual way to hide them from traversal — are
    /// instanced, as UsdImaging does.
    pub defined_from_root: bool,
    /// Whether a `SkelRoot` is at or above this prim: gprims below one may be posed by UsdSkel
    /// ([`crate::skel`]).
    pub skel_scope: bool,
}

impl Inherited {
    /// The state above the stage's root prims.
    pub fn root() -> Inherited {
        Inherited {
            world: DMat4::IDENTITY,
            visible: true,
            purpose: "default".into(),
            purpose_inheritable: false,
            bindings: None,
            target: Target::World,
            defined_from_root: false,
            skel_scope: false,
        }
    }
}

/// The walk's state.
pub struct Walk<'s> {
    /// Attribute reads at the load time.
    pub r: Reader<'s>,
    /// What has been read so far.
    pub scene: Scene,
    material_index: HashMap<String, usize>,
    /// Composition problems found by the walk (missing reference targets).
    pub problems: Vec<ArcProblem>,
    /// Prototypes walked so far, and where they are.
    pub protos: ProtoWalk,
    /// Gprims with `SkelBindingAPI` outside any `SkelRoot` (UsdSkel does not pose them), for
    /// one warning.
    skinned: Vec<String>,
}

impl<'s> Walk<'s> {
    /// A walk reading through `r` into `scene`.
    pub fn new(r: Reader<'s>, scene: Scene) -> Walk<'s> {
        Walk {
            r,
            scene,
            material_index: HashMap::new(),
            problems: Vec::new(),
            protos: ProtoWalk::default(),
            skinned: Vec::new(),
        }
    }

    /// The scene, the walk's warnings (with one summary each for skipped gprim types and
    /// skinning) and the composition problems found.
    pub fn finish(mut self) -> (Scene, Vec<Warning>, Vec<ArcProblem>) {
        self.r.take_type_warnings();
        let skipped = &self.scene.gprims.skipped;
        if !skipped.is_empty() {
            let list: Vec<String> = skipped.iter().map(|(t, n)| format!("{n} {t}")).collect();
            self.r.warnings.push(Warning {
                prim: "/".into(),
                kind: WarningKind::Unsupported,
                message: format!(
                    "not drawn (lux draws meshes and implicit surfaces): {}",
                    list.join(", ")
                ),
            });
        }
        if !self.skinned.is_empty() {
            self.r.warnings.push(Warning {
                prim: self.skinned[0].clone(),
                kind: WarningKind::Unsupported,
                message: format!(
                    "{} gprim(s) with SkelBindingAPI outside any SkelRoot are drawn as authored \
                     (UsdSkel poses only gprims under a SkelRoot)",
                    self.skinned.len()
                ),
            });
        }
        (self.scene, self.r.warnings, self.problems)
    }

    pub(crate) fn usd<T, E: std::fmt::Display>(
        &self,
        prim: &Prim,
        r: Result<T, E>,
    ) -> Result<T, LoadError> {
        r.map_err(|e| self.r.usd_error(prim, e))
    }

    /// Records a composition problem: a warning, or the load's error when strict.
    pub(crate) fn problem(&mut self, p: ArcProblem) -> Result<(), LoadError> {
        if self.r.limits.strict {
            return Err(crate::load::composition_error(&self.r.file, p));
        }
        self.problems.push(p);
        Ok(())
    }

    /// The root path of the prototype being walked (`None` in the world).
    fn prototype_root(&self, target: Target) -> Option<String> {
        match target {
            Target::World => None,
            Target::Proto(pd) => Some(self.protos.data[pd].path.clone()),
        }
    }

    /// The gprim counts of the current target (the world, or the prototype being walked).
    pub(crate) fn counts(&mut self, target: Target) -> &mut GprimCounts {
        match target {
            Target::World => &mut self.scene.gprims,
            Target::Proto(pd) => &mut self.protos.data[pd].counts,
        }
    }

    /// Visits `prim` and its subtree.
    pub fn visit(
        &mut self,
        prim: &Prim,
        parent: &Inherited,
        depth: usize,
    ) -> Result<(), LoadError> {
        if depth >= self.r.limits.max_depth {
            return Err(LoadError::TooLarge {
                file: self.r.file.clone(),
                prim: prim.path().to_string(),
                what: "namespace depth",
                count: depth + 1,
                limit: self.r.limits.max_depth,
            });
        }
        // `openusd` 0.6 accepts prim names that are not identifiers (`"a b"`, `"c}d"`) and
        // then recurses without end when composing them: such prims (and everything below)
        // are skipped before any other query.
        let path = prim.path().to_string();
        if !crate::reader::is_prim_path(&path) {
            self.r.warnings.push(Warning {
                prim: path,
                kind: WarningKind::InvalidValue,
                message: "prim name is not a USD identifier; prim and descendants skipped".into(),
            });
            return Ok(());
        }
        let active = self.usd(prim, prim.is_active())?;
        let defined = if parent.defined_from_root {
            matches!(
                self.usd(prim, prim.specifier())?,
                Some(openusd::sdf::Specifier::Def)
            )
        } else {
            self.usd(prim, prim.is_defined())?
        };
        let abstract_ = !parent.defined_from_root && self.usd(prim, prim.is_abstract())?;
        if !active || !defined || abstract_ {
            return Ok(());
        }
        let missing =
            missing_reference_targets(self.r.stage, prim).map_err(|m| self.r.usd_error(prim, m))?;
        for p in missing {
            self.problem(p)?;
        }
        self.scene.prim_count += 1;
        let type_name = self
            .usd(prim, prim.type_name())?
            .map(|t| t.as_str().to_owned())
            .unwrap_or_default();
        if matches!(
            type_name.as_str(),
            "Material" | "Shader" | "NodeGraph" | "GeomSubset"
        ) {
            return Ok(());
        }
        let api: Vec<String> = self
            .usd(prim, prim.api_schemas())?
            .iter()
            .map(|t| t.as_str().to_owned())
            .collect();
        let (local, reset) = local_transform(&mut self.r, prim)?;
        let world = if reset { local } else { parent.world * local };
        let visible =
            parent.visible && self.r.text(prim, "visibility")?.as_deref() != Some("invisible");
        // UsdGeomImageable purpose (PurposeInfo): the prim's own authored purpose; else the
        // nearest ancestor's authored purpose (inherited by children without their own);
        // else the fallback "default".
        let (purpose, purpose_inheritable) = match self.r.text(prim, "purpose")? {
            Some(p) => (p, true),
            None if parent.purpose_inheritable => (parent.purpose.clone(), true),
            None => ("default".to_owned(), false),
        };
        let bindings = crate::binding::Chain::extend(&mut self.r, prim, parent.bindings.as_ref())?;
        let here = Inherited {
            world,
            visible,
            purpose,
            purpose_inheritable,
            bindings,
            target: parent.target,
            defined_from_root: parent.defined_from_root,
            skel_scope: parent.skel_scope || type_name == "SkelRoot",
        };
        let drawn = here.visible && matches!(here.purpose.as_str(), "default" | "render");
        if drawn {
            self.prim_of_type(prim, &type_name, &api, &here, depth)?;
        }
        // UsdImaging draws a PointInstancer's subtree only through the instancer (its
        // prototypes live there), and a native instance's subtree is its prototype's.
        if type_name == "PointInstancer" {
            return Ok(());
        }
        if self.usd(prim, prim.is_instance())? {
            if drawn {
                self.native_instance(prim, &here, depth)?;
            }
            return Ok(());
        }
        for child in self.usd(prim, prim.children())? {
            self.visit(&child, &here, depth + 1)?;
        }
        Ok(())
    }

    fn prim_of_type(
        &mut self,
        prim: &Prim,
        type_name: &str,
        api: &[String],
        here: &Inherited,
        depth: usize,
    ) -> Result<(), LoadError> {
        if let Some(kind) = kind_of_type(type_name) {
            let light = read_light(&mut self.r, prim, type_name, kind, here.world, api, None)?;
            match here.target {
                Target::World => self.scene.lights.push(light),
                Target::Proto(pd) => self.protos.data[pd].lights.push(light),
            }
            return Ok(());
        }
        if is_unsupported_light_type(type_name) {
            self.counts(here.target).unsupported_lights += 1;
            self.r.warn(
                prim,
                WarningKind::UnsupportedLight,
                format!("{type_name} is not supported; skipped"),
            );
            return Ok(());
        }
        match type_name {
            "Camera" => {
                let cam = read_camera(&mut self.r, prim, here.world)?;
                match here.target {
                    Target::World => self.scene.cameras.push(cam),
                    Target::Proto(pd) => self.protos.data[pd].cameras.push(cam),
                }
            }
            "RenderSettings" if here.target == Target::World => {
                let s = read_render_settings(&mut self.r, prim)?;
                self.scene.render_settings.push(s);
            }
            "PointInstancer" => self.point_instancer(prim, here, depth)?,
            t if Gprim::of_type(t).is_some() => {
                self.gprim(prim, type_name, api, here)?;
            }
            "BasisCurves" | "NurbsCurves" | "Points" => {
                self.curves_or_points(prim, type_name, here)?
            }
            t if SKIPPED_GPRIMS.contains(&t) => {
                *self
                    .counts(here.target)
                    .skipped
                    .entry(t.to_owned())
                    .or_insert(0) += 1;
            }
            _ => {}
        }
        Ok(())
    }

    fn implicit(&mut self, prim: &Prim, type_name: &str) -> Result<Topology, LoadError> {
        let r = &mut self.r;
        let axis = Axis::parse(r.text(prim, "axis")?.as_deref());
        Ok(match type_name {
            "Sphere" => tessellate::sphere(r.size_or(prim, "radius", 1.0)?),
            "Cube" => tessellate::cube(r.size_or(prim, "size", 2.0)?),
            "Cylinder" => tessellate::cylinder(
                r.size_or(prim, "radius", 1.0)?,
                r.size_or(prim, "height", 2.0)?,
                axis,
            ),
            "Cone" => tessellate::cone(
                r.size_or(prim, "radius", 1.0)?,
                r.size_or(prim, "height", 2.0)?,
                axis,
            ),
            "Capsule" => tessellate::capsule(
                r.size_or(prim, "radius", 0.5)?,
                r.size_or(prim, "height", 1.0)?,
                axis,
            ),
            _ => tessellate::plane(
                r.size_or(prim, "width", 2.0)?,
                r.size_or(prim, "length", 2.0)?,
                axis,
            ),
        })
    }

    fn gprim(
        &mut self,
        prim: &Prim,
        type_name: &str,
        api: &[String],
        here: &Inherited,
    ) -> Result<(), LoadError> {
        let gprim = Gprim::of_type(type_name).unwrap_or(Gprim::Mesh);
        {
            let counts = self.counts(here.target);
            if gprim == Gprim::Mesh {
                counts.meshes += 1;
            } else {
                counts.implicit += 1;
            }
        }
        let mut topo = if gprim == Gprim::Mesh {
            match mesh_topology(&mut self.r, prim)? {
                Some(t) => t,
                None => return Ok(()),
            }
        } else {
            self.implicit(prim, type_name)?
        };
        // UsdSkel: a skinned gprim's points are posed (in its skeleton's space, `pose.to_target`).
        let pose = if here.skel_scope {
            let root = self.prototype_root(here.target);
            crate::skel::pose(
                &mut self.r,
                prim,
                gprim,
                &mut topo,
                &here.world,
                root.as_deref(),
            )?
        } else {
            if api.iter().any(|a| a == "SkelBindingAPI") {
                self.skinned.push(prim.path().to_string());
            }
            None
        };
        self.scene.drawn.posed_meshes += usize::from(pose.is_some());
        let world = pose.as_ref().map_or(here.world, |p| p.to_target);
        let (positions, triangles, mirror) = to_world(&topo, &world);
        let mut normals = None;
        if gprim == Gprim::Mesh {
            for (name, default_interp) in [("primvars:normals", "constant"), ("normals", "vertex")]
            {
                if let Some(n) = self.r.vec3_array(
                    prim,
                    if name == "normals" {
                        "normals"
                    } else {
                        "primvars:normals"
                    },
                )? {
                    normals = expand_primvar(&mut self.r, prim, name, n, default_interp, &topo)?
                        .map(|c| match &pose {
                            Some(p) => {
                                p.skin_normals(&mut self.r, prim, name, default_interp, c, &topo)
                            }
                            None => c,
                        })
                        .map(|c| normals_to_world(c, &world, mirror));
                    break;
                }
            }
        } else {
            // Implicit gprims are smooth surfaces: shade them with crease-angle normals.
            normals = Some(normals_to_world(
                tessellate::crease_normals(&topo, 60.0),
                &world,
                mirror,
            ));
        }
        let colors = match self.r.vec3_array(prim, "primvars:displayColor")? {
            Some(c) => expand_primvar(
                &mut self.r,
                prim,
                "primvars:displayColor",
                c,
                "constant",
                &topo,
            )?
            .map(|c| mirror_corners(c, mirror)),
            None => None,
        };
        let material = match crate::binding::resolve(here.bindings.as_ref(), prim.path().as_str()) {
            Some(path) => Some(self.material(&path)?),
            None => None,
        };
        // Texture coordinates: the primvar the bound material reads; a prototype's mesh
        // without a binding of its own may get an instance's material, so it keeps `st`.
        let st = match material.map(|m| &self.scene.materials[m]) {
            Some(m) => m.st_primvar().map(str::to_owned),
            None => (here.target != Target::World).then(|| "st".to_owned()),
        };
        let mut uvs = None;
        if let Some(st) = &st {
            let name = format!("primvars:{st}");
            if let Some(v) = self.r.raw(prim, &name)?
                && let Some(st) = crate::value::as_vec2_array(&v)
            {
                uvs = expand_primvar(&mut self.r, prim, &name, st, "constant", &topo)?
                    .map(|c| mirror_corners(c, mirror));
            }
        }
        // The primvars the bound material's primvar readers read; a prototype's mesh without
        // a binding of its own may be drawn with an instance's material: those any material
        // read so far reads (an instance's is read before its prototype is walked).
        let mut reads: Vec<String> = Vec::new();
        let materials: Vec<usize> = match material {
            Some(m) => vec![m],
            None if here.target != Target::World => (0..self.scene.materials.len()).collect(),
            None => Vec::new(),
        };
        for m in materials {
            for n in self.scene.materials[m].primvar_names() {
                if !reads.iter().any(|r| r == n) {
                    reads.push(n.to_owned());
                }
            }
        }
        let mut primvars = Vec::new();
        for name in &reads {
            let attr = format!("primvars:{name}");
            if let Some(values) = crate::mesh::primvar_values(&self.r, prim, &attr)?
                && let Some(c) =
                    expand_primvar(&mut self.r, prim, &attr, values, "constant", &topo)?
            {
                primvars.push(CornerPrimvar {
                    name: name.clone(),
                    values: mirror_corners(c, mirror),
                });
            }
        }
        // A subdivision surface keeps its control cage for refinement (`subdiv`); `triangles`
        // holds the cage's polygons meanwhile.
        let subdivision = if gprim == Gprim::Mesh {
            crate::subdiv::read_cage(&mut self.r, prim, &topo, &world, st.as_deref(), &reads)?
                .map(std::sync::Arc::new)
        } else {
            None
        };
        // UsdGeomPlane overrides the Gprim fallback: planes are double-sided unless authored.
        let double_sided = self.r.bool_or(prim, "doubleSided", type_name == "Plane")?;
        let spectral = crate::spectral::read_surface_spectral(&mut self.r, prim)?;
        let mut light = None;
        if api.iter().any(|a| a == "MeshLightAPI") {
            let tris = topo
                .triangles
                .iter()
                .map(|t| t.map(|k| topo.points[k as usize]))
                .collect();
            light = Some(read_light(
                &mut self.r,
                prim,
                type_name,
                LightKind::Mesh,
                world,
                api,
                Some(tris),
            )?);
        } else if api.iter().any(|a| a == "VolumeLightAPI") {
            self.r.warn(
                prim,
                WarningKind::UnsupportedLight,
                "VolumeLightAPI is not supported",
            );
        }
        let mesh = Mesh {
            path: prim.path().to_string(),
            positions,
            triangles,
            normals,
            colors,
            uvs,
            primvars,
            double_sided,
            material,
            light: None,
            spectral,
            prototype: None,
            gprim,
            subdivision,
        };
        self.emit_mesh(mesh, light, here.target);
        Ok(())
    }

    /// A `BasisCurves`, `NurbsCurves` or `Points` prim: counted, tessellated in its own space
    /// ([`crate::curves`], [`crate::points`]) and emitted as one mesh with the bound material.
    /// Tubes and spheres are closed and single-sided (unless `doubleSided` is authored true);
    /// ribbons are double-sided.
    /// The `points` of the curves or points prim `prim` posed by UsdSkel ([`crate::skel`])
    /// and where they go, when it is skinned under a `SkelRoot`. Authored ribbon `normals`
    /// are not skinned (said in a warning).
    fn pose_points(
        &mut self,
        prim: &Prim,
        gprim: Gprim,
        here: &Inherited,
    ) -> Result<Option<(Vec<glam::DVec3>, DMat4)>, LoadError> {
        if !here.skel_scope {
            return Ok(None);
        }
        let Some(points) = self.r.vec3_array(prim, "points")? else {
            return Ok(None);
        };
        let mut topo = Topology {
            points,
            triangles: Vec::new(),
            corners: Vec::new(),
            face_count: 0,
            faces: None,
        };
        let root = self.prototype_root(here.target);
        let pose = crate::skel::pose(
            &mut self.r,
            prim,
            gprim,
            &mut topo,
            &here.world,
            root.as_deref(),
        )?;
        let Some(pose) = pose else {
            return Ok(None);
        };
        self.scene.drawn.posed_meshes += 1;
        if self.r.raw(prim, "normals")?.is_some() {
            self.r.warn(
                prim,
                WarningKind::Unsupported,
                "UsdSkel poses the points of these curves; their authored normals are not \
                 skinned",
            );
        }
        Ok(Some((topo.points, pose.to_target)))
    }

    fn curves_or_points(
        &mut self,
        prim: &Prim,
        type_name: &str,
        here: &Inherited,
    ) -> Result<(), LoadError> {
        let points = type_name == "Points";
        let counts = self.counts(here.target);
        if points {
            counts.points += 1;
        } else {
            counts.curves += 1;
        }
        let gprim = match type_name {
            "BasisCurves" => Gprim::BasisCurves,
            "NurbsCurves" => Gprim::NurbsCurves,
            _ => Gprim::Points,
        };
        // UsdSkel poses every point-based gprim: its control points, before tessellation.
        let (posed, world) = match self.pose_points(prim, gprim, here)? {
            Some((points, to_target)) => (Some(points), to_target),
            None => (None, here.world),
        };
        let tess = match gprim {
            Gprim::BasisCurves => crate::curves::read_basis_curves(&mut self.r, prim, posed)?,
            Gprim::NurbsCurves => crate::curves::read_nurbs_curves(&mut self.r, prim, posed)?,
            _ => crate::points::read_points(&mut self.r, prim, posed)?,
        };
        let Some(t) = tess else {
            return Ok(());
        };
        let double_sided = self.r.bool_or(prim, "doubleSided", false)?;
        let material = match crate::binding::resolve(here.bindings.as_ref(), prim.path().as_str()) {
            Some(path) => Some(self.material(&path)?),
            None => None,
        };
        let spectral = crate::spectral::read_surface_spectral(&mut self.r, prim)?;
        let mesh = Mesh {
            path: prim.path().to_string(),
            positions: t.positions,
            triangles: t.triangles,
            normals: Some(t.normals),
            colors: t.colors,
            uvs: None,
            primvars: Vec::new(),
            double_sided: double_sided || t.double_sided,
            material,
            light: None,
            spectral,
            prototype: None,
            gprim,
            subdivision: None,
        }
        .transformed(&world);
        self.emit_mesh(mesh, None, here.target);
        if points {
            self.scene.drawn.points += 1;
        } else {
            self.scene.drawn.curves += 1;
        }
        Ok(())
    }

    /// Puts a mesh (and its `MeshLightAPI` light) where the walk is: the world, or the
    /// prototype being walked. A mesh light inside a prototype is kept apart and placed per
    /// instance as world geometry (a light needs world-space triangles).
    fn emit_mesh(&mut self, mut mesh: Mesh, light: Option<crate::Light>, target: Target) {
        match (target, light) {
            (Target::World, Some(l)) => {
                mesh.light = Some(self.scene.lights.len());
                self.scene.lights.push(l);
                self.scene.meshes.push(mesh);
            }
            (Target::World, None) => self.scene.meshes.push(mesh),
            (Target::Proto(pd), Some(l)) => {
                let d = &mut self.protos.data[pd];
                d.light_meshes.push((mesh, l));
            }
            (Target::Proto(pd), None) => {
                let p = self.protos.prototype_of(pd, &mut self.scene);
                mesh.prototype = Some(p);
                self.scene.prototypes[p]
                    .meshes
                    .push(self.scene.meshes.len());
                self.scene.meshes.push(mesh);
            }
        }
    }

    /// The index of the material at `path`, read on first use.
    pub(crate) fn material(&mut self, path: &str) -> Result<usize, LoadError> {
        if let Some(i) = self.material_index.get(path) {
            return Ok(*i);
        }
        let m = read_material(&mut self.r, path)?;
        let i = self.scene.materials.len();
        self.scene.materials.push(m);
        self.material_index.insert(path.to_owned(), i);
        Ok(i)
    }
}

/// Adds `other`'s counts to `into`, `times` times.
pub fn add_counts(into: &mut GprimCounts, other: &GprimCounts, times: usize) {
    into.meshes += other.meshes * times;
    into.implicit += other.implicit * times;
    into.curves += other.curves * times;
    into.points += other.points * times;
    into.native_instances += other.native_instances * times;
    into.point_instances += other.point_instances * times;
    into.unsupported_lights += other.unsupported_lights * times;
    for (k, v) in &other.skipped {
        *into.skipped.entry(k.clone()).or_insert(0) += v * times;
    }
}
