//! # lux-render
//!
//! The lux reference renderer: lux-usd's typed scene in, direct lighting of every UsdLux light
//! out ([`render`]), written as EXR and PNG ([`image_io`]).
//!
//! It composes the small crates and adds no lighting formula of its own: base emission from
//! lux-math (or lux-spectral for physical units and spectra, [`physical`]), ShapingAPI factors
//! from lux-shaping, IES profiles from lux-ies and every sampling technique from lux-sample.
//! Its parts, pbrt-v4's, top-down (each imports only those below it; `tests/architecture.rs`
//! checks that no two import each other in a circle):
//!
//! | module | what |
//! |---|---|
//! | [`render`] | [`render::Renderer`]: prepare the scene, then render it tile by tile |
//! | [`settings`] | options and RenderSettings → camera, resolution, data window, crop |
//! | [`tiles`] | the tile loop (pbrt's image-tile integrator): pixels, passes, determinism |
//! | [`adaptive`] | where a pixel's samples go: adaptive sampling, the penumbra pilot |
//! | [`integrator`] | light transport: one file per integrator, next-event estimation shared |
//! | [`visibility`] | shadow rays, and the exact-visibility accelerations behind one switch |
//! | [`world`] | the prepared scene an integrator reads |
//! | [`film`] | the pixels and the splats |
//! | [`camera`] | UsdGeomCamera → rays |
//! | [`light`] | one type per light kind, the light set and its selection |
//! | [`material`] | BSDFs and the UsdPreviewSurface inputs that feed them |
//! | [`geometry`] | triangle BVHs with instancing |
//! | [`sampler`] | the deterministic sample stream and its named dimensions |
//! | [`stats`] | counters, importing nothing of the renderer |
//! | [`conformance`] | the conformance-profile chain |
//!
//! Where a newcomer adds things:
//! - **a light kind**: a file in `light/` with a type answering what [`light::Light`]'s
//!   methods ask (sample towards a point, pdf, emitted radiance, intersection, bounds), a
//!   variant in [`light::Light`] and its line in that enum's `dispatch!` macro, and its
//!   construction in `light/load.rs`;
//! - **an integrator**: a file in `integrator/` with a type that has `new(&Setup)` and
//!   implements [`integrator::Integrator`], and one line in `integrator/mod.rs`'s
//!   `integrators!` list (which also names it for `--integrator`);
//! - **a material**: a BSDF file in `material/` and its variant in `material::Bsdf` (each
//!   answers `f`, `sample`, `pdf`), its inputs read in `material/mod.rs`;
//! - **a visibility acceleration**: a file in `visibility/`, used inside the
//!   [`visibility::Visibility`] methods the integrators already call; nothing outside the
//!   folder changes.
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

pub mod adaptive;
pub mod assets;
pub mod camera;
pub mod conformance;
pub mod film;
pub mod geometry;
pub mod image_io;
pub mod integrator;
pub mod light;
pub mod material;
pub mod physical;
pub mod render;
pub mod sampler;
pub mod settings;
pub mod stats;
pub mod tiles;
pub mod visibility;
pub mod world;

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
    Camera(#[from] camera::CameraError),
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
