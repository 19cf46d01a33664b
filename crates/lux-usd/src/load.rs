//! The stage walk: composition via `openusd`, then one pass over the composed prims that
//! accumulates transforms, visibility, purpose and material bindings.

use crate::camera::{read_camera, read_render_settings};
use crate::error::{LoadError, Warning, WarningKind};
use crate::light::{is_unsupported_light_type, kind_of_type, read_light};
use crate::material::read_material;
use crate::mesh::{
    Mesh, Topology, expand_primvar, mesh_topology, mirror_corners, normals_to_world, to_world,
};
use crate::reader::Reader;
use crate::resolver::LuxResolver;
use crate::tessellate::{self, Axis};
use crate::xform::local_transform;
use crate::{Scene, UpAxis};
use glam::DMat4;
use lux_math::LightKind;
use openusd::sdf::Path as SdfPath;
use openusd::usd::{Prim, Stage};
use std::collections::HashMap;
use std::path::Path;

/// Limits of a load: inputs beyond them are a [`LoadError::TooLarge`], never an allocation
/// failure or a stack overflow. `Default` gives the limits [`load_stage`] uses.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct LoadOptions {
    /// Largest array the loader copies (points, indices, primvars) and largest triangulation
    /// of one mesh, in elements (default 2^27).
    pub max_array_len: usize,
    /// Deepest prim namespace nesting walked (default 256).
    pub max_depth: usize,
}

impl Default for LoadOptions {
    fn default() -> LoadOptions {
        LoadOptions {
            max_array_len: crate::reader::MAX_ARRAY_LEN,
            max_depth: 256,
        }
    }
}

/// The identifier of the in-memory root layer of [`load_usda_str`] (also its `Scene::source`).
pub const MEMORY_LAYER: &str = "/__lux_memory__/stage.usda";

/// Inherited state of the walk.
#[derive(Clone)]
struct Inherited {
    world: DMat4,
    visible: bool,
    purpose: String,
    /// Whether `purpose` was authored on this prim or an ancestor (UsdGeomImageable
    /// `PurposeInfo::isInheritable`): children without their own purpose inherit it.
    purpose_inheritable: bool,
    binding: Option<String>,
}

struct Walk<'s> {
    r: Reader<'s>,
    scene: Scene,
    material_index: HashMap<String, usize>,
}

/// Loads the USD stage at `path` (`.usda`, `.usdc` or `.usdz`) and evaluates it at time code
/// `frame` into a plain [`Scene`], with the default [`LoadOptions`].
///
/// Composition (sublayers, references, payloads, inherits, variants, `over`s, layer offsets) is
/// `openusd`'s; an arc that fails to compose (missing file, missing prim, malformed layer,
/// cycle) is a [`LoadError::Composition`] naming the prim and the layer that authored the arc.
/// Everything that is merely ignored or unsupported becomes a [`Warning`] in
/// `Scene::warnings`; renderer-specific attributes and unknown prim types are skipped silently.
pub fn load_stage(path: impl AsRef<Path>, frame: f64) -> Result<Scene, LoadError> {
    load_stage_with(path, frame, &LoadOptions::default())
}

/// [`load_stage`] with explicit [`LoadOptions`].
pub fn load_stage_with(
    path: impl AsRef<Path>,
    frame: f64,
    options: &LoadOptions,
) -> Result<Scene, LoadError> {
    let path = path.as_ref();
    if !frame.is_finite() {
        return Err(LoadError::InvalidFrame { frame });
    }
    if !path.is_file() {
        return Err(LoadError::NotFound {
            file: path.to_path_buf(),
        });
    }
    let path_str = path.to_string_lossy().into_owned();
    load_with(LuxResolver::new(), &path_str, path, frame, options)
}

/// Loads a stage whose root layer is the `.usda` text `text` (no file involved), evaluated at
/// `frame`. Its `Scene::source` is [`MEMORY_LAYER`]; relative asset paths in it resolve
/// against that non-existent directory, so external arcs fail as unresolved (absolute paths
/// still work). Used by the fuzz target.
pub fn load_usda_str(text: &str, frame: f64, options: &LoadOptions) -> Result<Scene, LoadError> {
    if !frame.is_finite() {
        return Err(LoadError::InvalidFrame { frame });
    }
    let resolver = LuxResolver::with_memory_layer(MEMORY_LAYER, text.as_bytes().to_vec());
    load_with(
        resolver,
        MEMORY_LAYER,
        Path::new(MEMORY_LAYER),
        frame,
        options,
    )
}

fn load_with(
    resolver: LuxResolver,
    identifier: &str,
    path: &Path,
    frame: f64,
    options: &LoadOptions,
) -> Result<Scene, LoadError> {
    let stage = Stage::builder()
        .resolver(resolver)
        .open(identifier)
        .map_err(|e| LoadError::Malformed {
            file: path.to_path_buf(),
            message: format!("{e:#}"),
        })?;
    // Layer-stack errors (a missing or malformed sublayer, a sublayer cycle) are known once the
    // stage is open; report them before walking.
    composition_errors(&stage, path)?;
    let up_axis = match stage
        .stage_metadata("upAxis")
        .ok()
        .flatten()
        .and_then(|v| crate::value::as_text(&v))
        .as_deref()
    {
        Some("Z") => UpAxis::Z,
        _ => UpAxis::Y,
    };
    let meters_per_unit = stage
        .stage_metadata("metersPerUnit")
        .ok()
        .flatten()
        .and_then(|v| crate::value::as_f64(&v))
        .filter(|m| m.is_finite() && *m > 0.0)
        .unwrap_or(0.01);
    let unit_for_wavelength = stage
        .stage_metadata("unitForWavelength")
        .ok()
        .flatten()
        .and_then(|v| crate::value::as_text(&v));
    let mut walk = Walk {
        r: Reader {
            stage: &stage,
            file: path.to_path_buf(),
            time: frame,
            warnings: Vec::new(),
            limits: options.clone(),
        },
        scene: Scene {
            source: path.to_path_buf(),
            frame,
            up_axis,
            meters_per_unit,
            unit_for_wavelength,
            time_code_range: stage
                .has_authored_time_code_range()
                .then(|| [stage.start_time_code(), stage.end_time_code()]),
            meshes: Vec::new(),
            prototypes: Vec::new(),
            instances: Vec::new(),
            lights: Vec::new(),
            materials: Vec::new(),
            cameras: Vec::new(),
            render_settings: Vec::new(),
            warnings: Vec::new(),
            prim_count: 0,
        },
        material_index: HashMap::new(),
    };
    let root = Inherited {
        world: DMat4::IDENTITY,
        visible: true,
        purpose: "default".into(),
        purpose_inheritable: false,
        binding: None,
    };
    let roots = stage.root_prims().map_err(|e| LoadError::Usd {
        file: path.to_path_buf(),
        prim: "/".into(),
        message: format!("{e:#}"),
    })?;
    for name in roots {
        let prim = stage.prim(format!("/{name}").as_str());
        walk.visit(&prim, &root, 0)?;
    }
    composition_errors(&stage, path)?;
    let mut scene = walk.scene;
    scene.warnings = walk.r.warnings;
    for e in stage.composition_errors() {
        scene.warnings.push(Warning {
            prim: "/".into(),
            kind: WarningKind::Ignored,
            message: format!("composition: {e}"),
        });
    }
    for s in &scene.render_settings {
        let targets =
            std::iter::once(&s.base.camera).chain(s.products.iter().map(|p| &p.base.camera));
        for cam in targets.flatten() {
            if !scene.cameras.iter().any(|c| &c.path == cam) {
                scene.warnings.push(Warning {
                    prim: s.path.clone(),
                    kind: WarningKind::InvalidValue,
                    message: format!(
                        "camera <{cam}> is not a drawn Camera; using the first camera"
                    ),
                });
            }
        }
    }
    Ok(scene)
}

/// Turns the first fatal composition error `openusd` collected into a
/// [`LoadError::Composition`]: unresolved or malformed layers (sublayer, reference, payload),
/// references to missing prims or missing/invalid `defaultPrim`s, and cycles. Other,
/// recoverable diagnostics (e.g. inconsistent property types) are left for the caller to
/// record as warnings.
fn composition_errors(stage: &Stage, file: &Path) -> Result<(), LoadError> {
    use openusd::pcp::Error as E;
    let root = || file.to_string_lossy().into_owned();
    for e in stage.composition_errors() {
        let (prim, layer) = match &e {
            E::UnresolvedLayer {
                site_path,
                introduced_by,
                ..
            }
            | E::MalformedLayer {
                site_path,
                introduced_by,
                ..
            }
            | E::UnresolvedPrimPath {
                site_path,
                introduced_by,
                ..
            } => (site_path.to_string(), introduced_by.clone()),
            E::InvalidPrimPath { site_path, .. }
            | E::MissingDefaultPrim { site_path, .. }
            | E::InvalidDefaultPrim { site_path, .. } => (site_path.to_string(), root()),
            E::ArcCycle(chain) => (chain.composing.to_string(), chain.root_layer.clone()),
            E::UnresolvedSublayer { introduced_by, .. }
            | E::MalformedSublayer { introduced_by, .. } => ("/".to_owned(), introduced_by.clone()),
            E::SublayerCycle { root_layer, .. } => ("/".to_owned(), root_layer.clone()),
            _ => continue,
        };
        return Err(LoadError::Composition {
            file: file.to_path_buf(),
            layer,
            prim,
            message: e.to_string(),
        });
    }
    Ok(())
}

/// Whether the prim `path` has a spec in the layer `id` or (recursively, a few levels) in one
/// of its sublayers; `None` when the layer is not loaded on the stage.
fn layer_stack_has_prim(stage: &Stage, id: &str, path: &SdfPath, depth: usize) -> Option<bool> {
    use openusd::ar::{DefaultResolver, ResolvedPath, Resolver};
    let layer = stage.layer(id)?;
    if layer.prim(path.clone()).is_some() {
        return Some(true);
    }
    if depth == 0 {
        return Some(false);
    }
    let subs = layer
        .pseudo_root()
        .and_then(|r| r.sublayers())
        .unwrap_or_default();
    drop(layer);
    let resolver = DefaultResolver::new();
    Some(subs.iter().any(|sub| {
        let sub_id = resolver.create_identifier(sub, Some(&ResolvedPath::new(id)));
        layer_stack_has_prim(stage, &sub_id, path, depth - 1) == Some(true)
    }))
}

impl Walk<'_> {
    fn usd<T, E: std::fmt::Display>(&self, prim: &Prim, r: Result<T, E>) -> Result<T, LoadError> {
        r.map_err(|e| self.r.usd_error(prim, e))
    }

    /// Added check: `openusd` 0.6 reports a reference whose target prim does not exist only
    /// for payloads; the prim then silently composes without the referenced opinions. Every
    /// `references` entry authored on this prim's specs is checked here: the target layer
    /// (anchored at the authoring layer; an unresolvable layer is reported by `openusd`
    /// itself) must hold a spec at the target path (its `defaultPrim` when none is given);
    /// an internal reference's target must exist on the stage.
    fn check_reference_targets(&self, prim: &Prim) -> Result<(), LoadError> {
        use openusd::ar::{DefaultResolver, ResolvedPath, Resolver};
        use openusd::sdf::Value;
        let stage = self.r.stage;
        let resolver = DefaultResolver::new();
        for (layer_id, spec_path) in self.usd(prim, prim.prim_stack())? {
            let refs = {
                let Some(layer) = stage.layer(&layer_id) else {
                    continue;
                };
                let Some(spec) = layer.prim(spec_path.clone()) else {
                    continue;
                };
                match spec.field("references") {
                    Ok(Some(Value::ReferenceListOp(op))) => op
                        .explicit_items
                        .into_iter()
                        .chain(op.prepended_items)
                        .chain(op.appended_items)
                        .chain(op.added_items)
                        .collect::<Vec<_>>(),
                    _ => continue,
                }
            };
            for r in refs {
                let target = r.prim_path.as_str();
                let missing = if !target.is_empty() && !crate::reader::is_prim_path(target) {
                    true
                } else if r.asset_path.is_empty() {
                    !target.is_empty()
                        && !self.usd(prim, stage.prim(r.prim_path.clone()).is_valid())?
                } else {
                    let id = resolver
                        .create_identifier(&r.asset_path, Some(&ResolvedPath::new(&layer_id)));
                    let target = if r.prim_path.is_empty() {
                        let default = stage
                            .layer(&id)
                            .and_then(|l| l.pseudo_root().and_then(|p| p.default_prim()));
                        match default.and_then(|d| SdfPath::new(&format!("/{}", d.as_str())).ok()) {
                            Some(p) => p,
                            None => continue, // reported by openusd (missing defaultPrim)
                        }
                    } else {
                        r.prim_path.clone()
                    };
                    layer_stack_has_prim(stage, &id, &target, 8) == Some(false)
                };
                if missing {
                    return Err(LoadError::Composition {
                        file: self.r.file.clone(),
                        layer: layer_id.clone(),
                        prim: prim.path().to_string(),
                        message: format!(
                            "unresolved reference prim path @{}@<{}>: the target prim does not exist",
                            r.asset_path, r.prim_path
                        ),
                    });
                }
            }
        }
        Ok(())
    }

    fn visit(&mut self, prim: &Prim, parent: &Inherited, depth: usize) -> Result<(), LoadError> {
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
        let defined = self.usd(prim, prim.is_defined())?;
        let abstract_ = self.usd(prim, prim.is_abstract())?;
        if !active || !defined || abstract_ {
            return Ok(());
        }
        self.check_reference_targets(prim)?;
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
        let binding = {
            let full = self.r.targets(prim, "material:binding:full")?;
            let all = self.r.targets(prim, "material:binding")?;
            full.into_iter()
                .chain(all)
                .next()
                .or_else(|| parent.binding.clone())
        };
        let here = Inherited {
            world,
            visible,
            purpose,
            purpose_inheritable,
            binding,
        };
        let drawn = here.visible && matches!(here.purpose.as_str(), "default" | "render");
        if drawn {
            self.prim_of_type(prim, &type_name, &api, &here)?;
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
    ) -> Result<(), LoadError> {
        if let Some(kind) = kind_of_type(type_name) {
            let light = read_light(&mut self.r, prim, type_name, kind, here.world, api, None)?;
            self.scene.lights.push(light);
            return Ok(());
        }
        if is_unsupported_light_type(type_name) {
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
                self.scene.cameras.push(cam);
            }
            "RenderSettings" => {
                let s = read_render_settings(&mut self.r, prim)?;
                self.scene.render_settings.push(s);
            }
            "Mesh" | "Sphere" | "Cube" | "Cylinder" | "Cone" | "Capsule" | "Plane" => {
                self.gprim(prim, type_name, api, here)?;
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
        let topo = if type_name == "Mesh" {
            match mesh_topology(&mut self.r, prim)? {
                Some(t) => t,
                None => return Ok(()),
            }
        } else {
            self.implicit(prim, type_name)?
        };
        let (positions, triangles, mirror) = to_world(&topo, &here.world);
        let mut normals = None;
        if type_name == "Mesh" {
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
                        .map(|c| normals_to_world(c, &here.world, mirror));
                    break;
                }
            }
        } else {
            // Implicit gprims are smooth surfaces: shade them with crease-angle normals.
            normals = Some(normals_to_world(
                tessellate::crease_normals(&topo, 60.0),
                &here.world,
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
        let material = match &here.binding {
            Some(path) => Some(self.material(path)?),
            None => None,
        };
        let mut uvs = None;
        if let Some(m) = material
            && let crate::material::Diffuse::Texture(t) = &self.scene.materials[m].diffuse
        {
            let name = format!("primvars:{}", t.st_primvar);
            if let Some(v) = self.r.raw(prim, &name)?
                && let Some(st) = crate::value::as_vec2_array(&v)
            {
                uvs = expand_primvar(&mut self.r, prim, &name, st, "constant", &topo)?
                    .map(|c| mirror_corners(c, mirror));
            }
        }
        // UsdGeomPlane overrides the Gprim fallback: planes are double-sided unless authored.
        let double_sided = self.r.bool_or(prim, "doubleSided", type_name == "Plane")?;
        let spectral = crate::light::read_spectral_attributes(
            &mut self.r,
            prim,
            &crate::light::SURFACE_NAMESPACES,
        )?;
        let mut light = None;
        if api.iter().any(|a| a == "MeshLightAPI") {
            let tris = topo
                .triangles
                .iter()
                .map(|t| t.map(|k| topo.points[k as usize]))
                .collect();
            let l = read_light(
                &mut self.r,
                prim,
                type_name,
                LightKind::Mesh,
                here.world,
                api,
                Some(tris),
            )?;
            light = Some(self.scene.lights.len());
            self.scene.lights.push(l);
        } else if api.iter().any(|a| a == "VolumeLightAPI") {
            self.r.warn(
                prim,
                WarningKind::UnsupportedLight,
                "VolumeLightAPI is not supported",
            );
        }
        self.scene.meshes.push(Mesh {
            path: prim.path().to_string(),
            positions,
            triangles,
            normals,
            colors,
            uvs,
            double_sided,
            material,
            light,
            spectral,
            prototype: None,
            gprim: crate::mesh::Gprim::of_type(type_name).unwrap_or(crate::mesh::Gprim::Mesh),
        });
        Ok(())
    }

    fn material(&mut self, path: &str) -> Result<usize, LoadError> {
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
