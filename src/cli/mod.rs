//! Command-line front end of the `lux` binary.

pub mod demo;
pub mod farm;
pub mod ies;
pub mod info;
pub mod merge;
pub mod out;
pub mod render;
pub mod tile;
