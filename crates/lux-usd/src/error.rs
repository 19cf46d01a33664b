//! Load errors (fatal) and warnings (recorded in the [`crate::Scene`]).

use std::path::PathBuf;

/// Why a stage could not be loaded. Every variant names the file and, where one is involved, the
/// prim path and attribute.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The root layer does not exist (or is not a file).
    #[error("{file}: no such file")]
    NotFound {
        /// The path given to the loader.
        file: PathBuf,
    },
    /// The root layer path names a directory.
    #[error("{file}: is a directory, not a USD layer (.usda, .usdc, .usdz)")]
    IsDirectory {
        /// The path given to the loader.
        file: PathBuf,
    },
    /// The root layer exists but could not be read or parsed (malformed `.usda`, corrupt
    /// `.usdc`/`.usdz`). No prim is involved: the message carries the parser's position.
    #[error("{file}: cannot open stage: {message}")]
    Malformed {
        /// The root layer.
        file: PathBuf,
        /// The reader's diagnostic.
        message: String,
    },
    /// A composition arc failed: unresolved or malformed reference/payload/sublayer, a reference
    /// to a missing prim or to a layer without a usable `defaultPrim`, or a composition cycle
    /// (reference, payload, inherit or sublayer).
    #[error("{file}: composition error at <{prim}> (arc authored in {layer}): {message}")]
    Composition {
        /// The root layer.
        file: PathBuf,
        /// The layer that authored the failing arc (for a cycle, the layer the cycle was
        /// entered from).
        layer: String,
        /// The prim whose arc failed (`/` for layer-stack errors).
        prim: String,
        /// The composition engine's diagnostic (names the asset path that failed).
        message: String,
    },
    /// An attribute holds a value of the wrong type (e.g. a string `inputs:intensity`).
    #[error("{file}: <{prim}>.{attribute}: expected {expected}, found {found}")]
    AttributeType {
        /// The root layer.
        file: PathBuf,
        /// The prim path.
        prim: String,
        /// The attribute name.
        attribute: String,
        /// The expected USD type family.
        expected: &'static str,
        /// The value type found.
        found: String,
    },
    /// `openusd` failed while composing or reading a prim.
    #[error("{file}: <{prim}>: {message}")]
    Usd {
        /// The root layer.
        file: PathBuf,
        /// The prim path.
        prim: String,
        /// The crate's diagnostic.
        message: String,
    },
    /// An array or tessellation exceeds the loader's allocation cap.
    #[error("{file}: <{prim}>: {what} has {count} elements, more than the limit {limit}")]
    TooLarge {
        /// The root layer.
        file: PathBuf,
        /// The prim path.
        prim: String,
        /// What is too large.
        what: &'static str,
        /// The authored count.
        count: usize,
        /// The cap.
        limit: usize,
    },
    /// The requested frame (time code) is NaN or infinite.
    #[error("frame {frame} is not a finite time code")]
    InvalidFrame {
        /// The requested frame.
        frame: f64,
    },
}

/// The category of a [`Warning`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WarningKind {
    /// A light type lux does not render (`PluginLight`, `GeometryLight`, `VolumeLightAPI`).
    UnsupportedLight,
    /// A transform op, primvar interpolation or schema feature lux does not implement.
    Unsupported,
    /// A non-finite or out-of-range value replaced by its schema default or clamped.
    InvalidValue,
    /// Malformed geometry (bad indices, count mismatch): the prim or face is skipped.
    InvalidGeometry,
    /// An asset path (IES file, texture) that does not resolve to an existing file.
    UnresolvedAsset,
    /// `inputs:shaping:*` authored on a light without `ShapingAPI` applied: ignored.
    ShapingNotApplied,
    /// Something authored that lux deliberately ignores (GeomSubset bindings, light filters…).
    Ignored,
    /// A sublayer, reference or payload that could not be composed (missing file, unknown
    /// file format, missing target prim, cycle): the stage was composed without it, as
    /// usd-core does.
    Composition,
}

/// A non-fatal problem found while loading: what was ignored, replaced or unsupported.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    /// The prim path concerned.
    pub prim: String,
    /// The category.
    pub kind: WarningKind,
    /// A human-readable explanation.
    pub message: String,
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "<{}>: {}", self.prim, self.message)
    }
}
