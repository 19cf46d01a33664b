//! # lux-usd
//!
//! USD scene loading: a composed `openusd` stage evaluated at one frame into a plain [`Scene`].
//!
//! The loader is the only part of lux that touches USD. It fills in every UsdLux schema default
//! (`openusd` supplies none), so a [`Light`] carries complete `LightAPI` / `ShapingAPI` /
//! `ShadowAPI` inputs. See the crate README for what is supported.
//!
//! What `openusd` 0.6 lacks and the loader adds: scalar asset-path time samples in `.usda`
//! (rewritten before parsing, [`usda_fix`]); interpolation of scalar time samples the `.usda`
//! parser reads type-blind ([`reader::Reader::raw`]); resolution of asset paths held in time
//! samples against their authoring layer ([`reader::Reader::asset`]); an error for references
//! to prims that do not exist; schema defaults; transform-op evaluation in f64 ([`xform`]);
//! triangulation, primvar expansion, implicit-gprim tessellation and curves and points swept
//! into triangles ([`curves`], [`points`]). [`load_usda_str`] loads
//! `.usda` text from memory.

#![warn(missing_docs)]

mod arcs;
pub mod asset;
pub mod binding;
pub mod camera;
pub mod compat;
pub mod curves;
pub mod defaults;
pub mod error;
pub mod instancing;
pub mod light;
pub mod linking;
mod load;
pub mod material;
pub mod mesh;
pub mod mtlx;
pub mod path_guard;
pub mod points;
mod preview_network;
pub mod reader;
mod resolver;
pub mod shade_network;
pub mod shading;
pub mod skel;
pub mod spectral;
pub mod subdiv;
pub mod tessellate;
pub mod usda_fix;
mod value;
mod walk;
pub mod xform;

pub use camera::{Camera, CameraExposure, Projection, RenderBase, RenderProduct, RenderSettings};
pub use compat::{
    UsdaErrorLocation, describe_usda_error, describe_usda_layer_error, locate_usda_error,
};
pub use error::{LoadError, Warning, WarningKind};
pub use light::{
    DomeTextureFormat, Light, MaterialSyncMode, PoleAxis, ShadowInputs, ShapingInputs,
};
pub use linking::{Linking, Membership, Rule};
pub use load::{LoadOptions, MEMORY_LAYER, Time, load_stage, load_stage_with, load_usda_str};
pub use material::{
    Diffuse, Input, Material, PrimvarInput, SourceColorSpace, TextureInput, Transform2d, Wrap,
};
pub use mesh::{CornerPrimvar, Gprim, Instance, Mesh, Prototype};
pub use reader::AssetRef;
pub use shade_network::read_network;
pub use spectral::{PhysicalLight, SurfaceSpectral};
pub use walk::SKIPPED_GPRIMS;

use std::collections::BTreeMap;
use std::path::PathBuf;

/// What the stage holds, counted as usd-core's traversal with instance proxies counts it: a
/// native instance's gprims once per instance, a PointInstancer's prototypes once (where they
/// are authored), only drawn prims (visible, purpose `default` or `render`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GprimCounts {
    /// `Mesh` prims.
    pub meshes: usize,
    /// Implicit surfaces (`Sphere`, `Cube`, `Cylinder`, `Cone`, `Capsule`, `Plane`), drawn
    /// tessellated.
    pub implicit: usize,
    /// `BasisCurves` and `NurbsCurves` prims (drawn as tubes or ribbons; counted whether or not
    /// their data let them be drawn).
    pub curves: usize,
    /// `Points` prims (drawn as spheres; counted whether or not their data let them be drawn).
    pub points: usize,
    /// Gprims lux does not draw, by type ([`SKIPPED_GPRIMS`]: HermiteCurves, NurbsPatch,
    /// TetMesh, volumes…).
    pub skipped: BTreeMap<String, usize>,
    /// Native instances (`instanceable` prims with a prototype).
    pub native_instances: usize,
    /// PointInstancer instances: `protoIndices` entries, masked ones included.
    pub point_instances: usize,
    /// Light prims lux recognises but does not render (`PluginLight`, `GeometryLight`).
    pub unsupported_lights: usize,
}

impl GprimCounts {
    /// Gprims other than `Mesh` (implicit surfaces, curves, points and skipped types):
    /// usd-core's count of non-mesh gprims.
    pub fn other_gprims(&self) -> usize {
        self.implicit + self.curves + self.points + self.skipped.values().sum::<usize>()
    }
}

/// What lux draws beyond plain polygons, for `lux info`: each count is of prims (a
/// prototype's once, however many instances draw it).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DrawnCounts {
    /// Meshes refined as subdivision surfaces (`subdivisionScheme` `catmullClark`, `loop` or
    /// `bilinear`) at a level above 0.
    pub refined_meshes: usize,
    /// Skinned gprims (meshes, and implicit surfaces bound rigidly) posed by their skeleton or
    /// blend shapes (UsdSkel) at the frame ([`skel`]).
    pub posed_meshes: usize,
    /// `BasisCurves` and `NurbsCurves` prims drawn.
    pub curves: usize,
    /// `Points` prims drawn.
    pub points: usize,
}

/// The stage's `upAxis` metadata.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UpAxis {
    /// `"Y"` (the USD fallback).
    Y,
    /// `"Z"`.
    Z,
}

/// A loaded scene: world-space geometry, lights, cameras and render settings at one frame, with
/// no `openusd` types inside (`Send + Sync`).
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The root layer path given to [`load_stage`].
    pub source: PathBuf,
    /// The time code the scene was evaluated at.
    pub frame: f64,
    /// `upAxis` stage metadata.
    pub up_axis: UpAxis,
    /// `metersPerUnit` stage metadata (0.01 when unauthored); recorded, not applied.
    pub meters_per_unit: f64,
    /// `unitForWavelength` stage metadata of the LTESpectralAPI (nanometres when unauthored;
    /// an unknown token is a warning and means nanometres).
    pub unit_for_wavelength: lux_spectral::WavelengthUnit,
    /// `[startTimeCode, endTimeCode]` when authored.
    pub time_code_range: Option<[f64; 2]>,
    /// Drawn gprims (visible, purpose default/render) as triangle meshes: in world space, or
    /// in a prototype's space (`Mesh::prototype`) for instanced geometry.
    pub meshes: Vec<Mesh>,
    /// Instancing prototypes: geometry stored once, drawn by every [`Instance`] of it.
    pub prototypes: Vec<Prototype>,
    /// Placements of prototypes (native instances and PointInstancer instances).
    pub instances: Vec<Instance>,
    /// Supported lights (mesh lights also appear in `meshes`).
    pub lights: Vec<Light>,
    /// Materials bound to the meshes (indexed by `Mesh::material`).
    pub materials: Vec<Material>,
    /// Every camera of the stage.
    pub cameras: Vec<Camera>,
    /// Every RenderSettings prim of the stage.
    pub render_settings: Vec<RenderSettings>,
    /// What was ignored, replaced or unsupported.
    pub warnings: Vec<Warning>,
    /// Drawn gprims and instances, counted as usd-core counts them.
    pub gprims: GprimCounts,
    /// What is drawn refined, posed, or as curves and points.
    pub drawn: DrawnCounts,
    /// Number of active, defined prims visited.
    pub prim_count: usize,
}

impl Scene {
    /// An empty scene (Y up, 1 metre per unit, frame 1), for scenes built in code.
    pub fn empty(source: impl Into<PathBuf>) -> Scene {
        Scene {
            source: source.into(),
            frame: 1.0,
            up_axis: UpAxis::Y,
            meters_per_unit: 1.0,
            unit_for_wavelength: lux_spectral::WavelengthUnit::Nanometers,
            time_code_range: None,
            meshes: Vec::new(),
            prototypes: Vec::new(),
            instances: Vec::new(),
            lights: Vec::new(),
            materials: Vec::new(),
            cameras: Vec::new(),
            render_settings: Vec::new(),
            warnings: Vec::new(),
            gprims: GprimCounts::default(),
            drawn: DrawnCounts::default(),
            prim_count: 0,
        }
    }

    /// usdrecord's defaults where the stage is silent ([`defaults`]): without a camera, a
    /// perspective camera framing the drawn bounds (upAxis-aware); without a light and when
    /// `camera_light` is set, a camera light (headlight) along the render camera's view.
    /// Returns one line per default added, for the render log and `lux info`.
    pub fn add_usdrecord_defaults(&mut self, camera_light: bool) -> Vec<String> {
        let mut notes = Vec::new();
        if self.cameras.is_empty() {
            let bounds = defaults::world_bounds(self);
            let cam = defaults::framing_camera(bounds, self.up_axis);
            let eye = cam.camera_to_world.transform_point3(glam::DVec3::ZERO);
            notes.push(match bounds {
                Some((lo, hi)) => format!(
                    "no camera on the stage: usdrecord's framing camera at ({:.4}, {:.4}, {:.4}) \
                     for the bounds ({:.4}, {:.4}, {:.4})..({:.4}, {:.4}, {:.4}), {:?} up",
                    eye.x, eye.y, eye.z, lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, self.up_axis
                ),
                None => "no camera and nothing drawn on the stage: usdrecord's default camera \
                         at the origin"
                    .to_owned(),
            });
            self.cameras.push(cam);
        }
        if camera_light
            && self.lights.is_empty()
            && let Some(cam) = self.render_camera()
        {
            {
                let l = defaults::camera_light(cam);
                let a = l.axis();
                notes.push(format!(
                    "no light on the stage: usdrecord's camera light (a DistantLight of \
                     illuminance π along the view ({:.4}, {:.4}, {:.4}); \
                     --disable-camera-light turns it off)",
                    a.x, a.y, a.z
                ));
                self.lights.push(l);
            }
        }
        notes
    }

    /// The camera `name` names: a full prim path, or — as usdrecord's `--camera` takes — a
    /// bare prim name when exactly one camera has it. The error says what matched.
    pub fn find_camera(&self, name: &str) -> Result<&Camera, String> {
        if let Some(c) = self.cameras.iter().find(|c| c.path == name) {
            return Ok(c);
        }
        let bare: Vec<&Camera> = self
            .cameras
            .iter()
            .filter(|c| !name.contains('/') && c.path.rsplit('/').next() == Some(name))
            .collect();
        match bare.as_slice() {
            [one] => Ok(one),
            [] => Err(format!(
                "no camera <{name}> in {} (cameras: {})",
                self.source.display(),
                if self.cameras.is_empty() {
                    "none".to_owned()
                } else {
                    self.cameras
                        .iter()
                        .map(|c| c.path.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                }
            )),
            many => Err(format!(
                "camera name {name:?} is ambiguous in {}: {}",
                self.source.display(),
                many.iter()
                    .map(|c| c.path.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
        }
    }

    /// The output resolution when none is given: the first RenderSettings' product's, else
    /// the settings' (`resolution`, schema fallback 1920 × 1080); without RenderSettings,
    /// usdrecord's: 960 pixels wide and `⌊960 / aspect⌋` high (at least 1), `aspect` the
    /// camera's `horizontalAperture / verticalAperture` (1 when degenerate).
    pub fn default_resolution(&self, camera: &Camera) -> [u32; 2] {
        if let Some(s) = self.render_settings.first() {
            return s
                .products
                .first()
                .and_then(|p| p.base.resolution)
                .unwrap_or_else(|| s.resolution());
        }
        let aspect = camera.horizontal_aperture / camera.vertical_aperture;
        let aspect = if aspect.is_finite() && (aspect as f32 - 0.0).abs() > 1e-4 {
            aspect as f32
        } else {
            1.0
        };
        let h = (960.0f32 / aspect) as u32;
        [960, h.clamp(1, 65536)]
    }

    /// The prim path light and shadow linking ([`Membership::contains`]) judge the mesh
    /// `mesh` by, drawn by `instance` (an index into `instances`) or in the world (`None`):
    /// a world mesh's own path; for a native instance, the instance-proxy path (the
    /// instance's path followed by the mesh's path inside the prototype, as usd-core's
    /// traversal of instance proxies names it); for a PointInstancer instance (whose path is
    /// not a prim path), the prototype mesh's own path where it is authored.
    pub fn geometry_path(&self, mesh: usize, instance: Option<usize>) -> std::borrow::Cow<'_, str> {
        let m = &self.meshes[mesh];
        let Some(inst) = instance.and_then(|i| self.instances.get(i)) else {
            return std::borrow::Cow::Borrowed(&m.path);
        };
        let Some(proto) = self.prototypes.get(inst.prototype) else {
            return std::borrow::Cow::Borrowed(&m.path);
        };
        match m.path.strip_prefix(proto.path.as_str()) {
            Some(rel)
                if (rel.is_empty() || rel.starts_with('/')) && reader::is_prim_path(&inst.path) =>
            {
                std::borrow::Cow::Owned(format!("{}{rel}", inst.path))
            }
            _ => std::borrow::Cow::Borrowed(&m.path),
        }
    }

    /// The light at a prim path.
    pub fn light(&self, path: &str) -> Option<&Light> {
        self.lights.iter().find(|l| l.path == path)
    }

    /// The camera a render uses: the first RenderSettings' (or its first product's) camera,
    /// else (also when that camera does not exist; the loader warns) the first camera of the
    /// stage.
    pub fn render_camera(&self) -> Option<&Camera> {
        let wanted = self.render_settings.first().and_then(|s| {
            s.products
                .iter()
                .find_map(|p| p.base.camera.clone())
                .or_else(|| s.base.camera.clone())
        });
        match wanted {
            Some(p) => self
                .cameras
                .iter()
                .find(|c| c.path == p)
                .or(self.cameras.first()),
            None => self.cameras.first(),
        }
    }
}

/// The README's examples, compiled as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

#[cfg(test)]
mod tests {
    #[test]
    fn scene_is_send_and_sync() {
        fn check<T: Send + Sync + 'static>() {}
        check::<super::Scene>();
        check::<super::LoadError>();
    }
}
