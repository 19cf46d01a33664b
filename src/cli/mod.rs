//! Command-line front end of the `lux` binary.

pub mod demo;
pub mod ies;
pub mod info;
pub mod out;
pub mod render;
