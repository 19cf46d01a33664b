//! # lux-render
//!
//! The lux reference renderer: real USD stages in ([`scene`]), direct lighting of every UsdLux
//! light out ([`render`]), written as EXR and PNG ([`image_io`]).
//!
//! It composes the small crates and adds no lighting formula of its own: base emission from
//! lux-math (or lux-spectral for physical units and spectra), ShapingAPI factors from
//! lux-shaping, IES profiles from lux-ies and every sampling technique from lux-sample. What it
//! adds is geometry (an obvhs CWBVH, [`geometry`]), cameras ([`view`]), materials
//! ([`surface`]), the integrator and the deterministic tiled loop ([`render`]), and the
//! conformance-profile chain ([`conformance`]).
//!
//! ```no_run
//! use lux_render::conformance::{default_config_paths, resolve_profile};
//! use lux_render::render::{RenderOptions, Renderer};
//! use lux_usd::load_stage;
//!
//! let scene = load_stage("scene.usda", 1.0)?;
//! let profile = resolve_profile(None, &scene, None, &default_config_paths())?;
//! let mut options = RenderOptions::new(profile);
//! options.spp = 64;
//! let renderer = Renderer::new(&scene, options)?;
//! let (image, stats) = renderer.render(&|_pixels_done| {});
//! lux_render::image_io::write_exr("out.exr".as_ref(), &image)?;
//! println!("{} samples in {:.2} s", stats.samples, stats.seconds);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

pub mod assets;
pub mod conformance;
pub mod geometry;
pub mod image_io;
pub mod lights;
pub mod physical;
pub mod render;
pub mod rng;
pub mod surface;
pub mod view;

use std::path::PathBuf;

/// Why a render could not be prepared.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The stage failed to load.
    #[error(transparent)]
    Load(#[from] lux_usd::LoadError),
    /// An asset a light or material references (IES profile, texture) is missing or malformed.
    #[error("{}: {message}", file.display())]
    Asset {
        /// The file.
        file: PathBuf,
        /// What is wrong with it.
        message: String,
    },
    /// A light's inputs cannot be converted (physical units, spectra).
    #[error("light {light}: {message}")]
    Light {
        /// Light prim path.
        light: String,
        /// What is wrong.
        message: String,
    },
    /// A surface's spectral inputs cannot be converted.
    #[error("{prim}: {message}")]
    Surface {
        /// Gprim or material prim path.
        prim: String,
        /// What is wrong.
        message: String,
    },
    /// The camera cannot produce rays.
    #[error(transparent)]
    View(#[from] view::ViewError),
    /// No usable camera.
    #[error("{0}")]
    NoCamera(String),
    /// An invalid render setting (sample count, resolution, crop…).
    #[error("{0}")]
    Settings(String),
    /// The conformance profile setting is invalid.
    #[error(transparent)]
    Profile(#[from] conformance::ProfileError),
    /// Writing an image failed.
    #[error(transparent)]
    Image(#[from] image_io::ImageError),
}

/// The README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
