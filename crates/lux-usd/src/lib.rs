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
//! triangulation, primvar expansion and implicit-gprim tessellation. [`load_usda_str`] loads
//! `.usda` text from memory.

#![warn(missing_docs)]

pub mod asset;
pub mod camera;
pub mod error;
pub mod light;
mod load;
pub mod material;
pub mod mesh;
pub mod path_guard;
pub mod reader;
mod resolver;
pub mod tessellate;
pub mod usda_fix;
mod value;
pub mod xform;

pub use camera::{Camera, Projection, RenderBase, RenderProduct, RenderSettings};
pub use error::{LoadError, Warning, WarningKind};
pub use light::{Light, PoleAxis, RawValue, ShadowInputs, ShapingInputs, SpectralAttributes};
pub use load::{LoadOptions, MEMORY_LAYER, load_stage, load_stage_with, load_usda_str};
pub use material::{Diffuse, Material, TextureInput};
pub use mesh::{Gprim, Instance, Mesh, Prototype};
pub use reader::AssetRef;

use std::path::PathBuf;

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
    /// `unitForWavelength` stage metadata of the LTESpectralAPI (`"nanometers"` when
    /// unauthored), as authored.
    pub unit_for_wavelength: Option<String>,
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
            unit_for_wavelength: None,
            time_code_range: None,
            meshes: Vec::new(),
            prototypes: Vec::new(),
            instances: Vec::new(),
            lights: Vec::new(),
            materials: Vec::new(),
            cameras: Vec::new(),
            render_settings: Vec::new(),
            warnings: Vec::new(),
            prim_count: 0,
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
