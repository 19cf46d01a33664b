//! Work-arounds for what `openusd` 0.6 cannot read but usd-core (Pixar's reference
//! implementation) does, applied to the bytes of each layer before `openusd` parses it.
//!
//! `openusd` is pinned to 0.6.x (0.7 needs rustc 1.96) and is neither vendored nor patched, so
//! the loader's asset resolver (`LuxResolver::open_asset`, which serves every layer's bytes to
//! `openusd`) rewrites layers into a form 0.6 reads the same way usd-core reads the originals:
//!
//! - [`usda`]: one linear, tokenizer-aware pass over `.usda` text (any layer whose extension is
//!   `.usda` or whose bytes start with the `#usda` magic): `//` comments, text after the magic
//!   on line 1, quoted strings as asset values, the legacy `config` variability, legacy type
//!   names and scalar asset time samples. Line numbers never change.
//! - [`usdc`]: time-sample times of crate files older than version 0.7.0, which `openusd`
//!   reads with the wrong layout.
//! - [`locate`]: the `FILE:LINE:COLUMN` of a `.usda` parse failure, which `openusd` only
//!   reports as `failed to parse USDA layer`.
//!
//! Each is listed, with its symptom, in the crate README ("What `openusd` 0.6 lacks and
//! lux-usd works around"), so that it can be proposed upstream.

pub mod locate;
pub mod usda;
pub mod usdc;

pub use locate::{
    UsdaErrorLocation, describe_usda_error, describe_usda_layer_error, locate_usda_error,
    locate_usda_error_in_bytes,
};
