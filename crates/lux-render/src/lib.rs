//! lux reference renderer: USD scene loading, BVH, direct-lighting integrators, EXR/PNG output.
//!
//! The [`scene`] module loads a USD stage into a plain [`scene::Scene`].

pub mod scene;
