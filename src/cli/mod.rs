//! Command-line front end of the `lux` binary.

pub mod ies;
