//! # lux-ies
//!
//! IES LM-63 photometric files for UsdLux `shaping:ies:file`: parse every edition (1986, 1991,
//! 1995, 2002, 2019 and common real-world variants), validate with precise errors, write back
//! (LM-63-2002 / LM-63-2019), expand every symmetry into a [`PhotometricWeb`], interpolate
//! (bilinear reference, bicubic option) in constant time, integrate flux exactly or by the
//! reference's midpoint rule, and derive the `ies:normalize` mean intensity, peak, beam and field
//! angles.
//!
//! Conventions (spec §3): θ is measured from the light's −Z (IES vertical angle 0 = nadir), φ is
//! the IES horizontal angle (0 towards light −X, 90° towards −Y); see [`lux_math::light_polar`].
//!
//! ```
//! use lux_ies::{IesFile, PhotometricWeb};
//! use lux_math::Profile;
//!
//! let text = "IESNA:LM-63-2002\n[TEST] demo\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n\
//!             0 45 90\n0\n100 50 0\n";
//! let file = IesFile::parse(text)?;
//! let web = PhotometricWeb::new(&file, Profile::Spec)?;
//! assert_eq!(web.intensity(0.0, 0.0), 100.0);
//! assert_eq!(web.intensity(22.5f64.to_radians(), 1.0), 75.0);
//! let normalizer = web.mean_intensity(); // flux / 2π (hemisphere profile)
//! assert!(normalizer > 0.0);
//! # Ok::<(), lux_ies::IesError>(())
//! ```

// `!(x >= a)` is used on purpose: it is true for NaN, which must take the "outside" branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
#![warn(missing_docs)]

mod derived;
mod edition;
mod error;
mod file;
pub mod flux;
mod header;
mod interp;
mod lexer;
mod opening;
mod parse;
mod tilt;
mod warning;
mod web;
mod write;

pub use derived::{SpreadAngles, spread_angle};
pub use edition::Edition;
pub use error::{IesError, Position};
pub use file::{IesFile, PhotometricType, Units};
pub use header::HeaderLine;
pub use opening::LuminousOpening;
pub use parse::{MAX_ANGLES, MAX_TILT_ANGLES, MAX_VALUES, ParseOptions, Parsed, TiltResolver};
pub use tilt::{LampGeometry, Tilt, TiltData};
pub use warning::Warning;
pub use web::{Interpolation, PhotometricWeb, Symmetry};

/// The README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
