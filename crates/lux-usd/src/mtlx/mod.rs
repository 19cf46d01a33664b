//! MaterialX documents (MaterialX Specification 1.39, "MTLX File Format Definition"): the
//! embedded standard library ([`library()`]), documents read from `.mtlx` text
//! ([`parse_document`]), their upgrade from 1.38 ([`upgrade`]) and the [`Network`] of a
//! document's `<surfacematerial>` ([`Document::network`]), which
//! [`crate::shading::flatten`] flattens against the library.
//!
//! [`Network`]: crate::shading::Network

pub mod document;
pub mod library;
mod looks;
pub mod upgrade;
pub mod usdmtlx;

use std::path::PathBuf;

pub use document::{
    Collection, Document, Input, Look, MaterialAssign, Node, NodeGraph, Output, parse_document,
    read_document, split_array,
};
pub use library::{
    DefInput, Library, NodeDef, NodeGraphDef, OutputFallback, library, nodedef_for_usd_id,
};

use crate::shading::{Value, ValueType};

/// What went wrong reading a MaterialX document: the file, where in it, and what was expected.
#[derive(Debug, thiserror::Error)]
pub enum MtlxError {
    /// The file could not be read.
    #[error("{file}: cannot read: {message}")]
    Io {
        /// The document.
        file: PathBuf,
        /// The operating system's message.
        message: String,
    },
    /// The text is not well-formed XML.
    #[error("{file}:{line}:{column}: not well-formed XML: {message}")]
    Xml {
        /// The document.
        file: PathBuf,
        /// 1-based line.
        line: u32,
        /// 1-based column.
        column: u32,
        /// The XML parser's message.
        message: String,
    },
    /// An element does not have the form the MaterialX Specification gives it.
    #[error("{file}:{line}: <{element}>: expected {expected}")]
    Invalid {
        /// The document.
        file: PathBuf,
        /// 1-based line of the element.
        line: u32,
        /// The element (`input "base_color"`, `materialx`).
        element: String,
        /// What the specification requires there.
        expected: String,
    },
    /// The document is older than MaterialX 1.38. lux upgrades 1.38 documents to 1.39
    /// ([`upgrade`]) but not older ones: their upgrade (MaterialX's
    /// `Document::upgradeVersion`, 1.37 → 1.38 and earlier steps) rewrites `<material>` /
    /// `<shaderref>` / `<bindinput>` elements into shader and material nodes, `<parameter>`s into
    /// inputs, `color2` into `vector2` and the 1.37 BSDF nodes, which lux does not implement;
    /// read as they are, such documents would have no materials.
    #[error(
        "{file}:{line}: a MaterialX {major}.{minor} document: lux reads MaterialX 1.38 and 1.39 \
         documents, not older ones"
    )]
    Version {
        /// The document.
        file: PathBuf,
        /// 1-based line of the `<materialx>` element.
        line: u32,
        /// The document's major version.
        major: u32,
        /// The document's minor version.
        minor: u32,
    },
    /// [`Document::network`] was asked for a material the document does not declare, or a
    /// connection names a node or nodegraph output that does not exist.
    #[error("{file}: {message}")]
    Network {
        /// The document.
        file: PathBuf,
        /// What is missing.
        message: String,
    },
}

/// Parses a MaterialX value string of type `ty` (MaterialX Specification, "MaterialX Data
/// Types": comma-separated components, `true`/`false` booleans, matrices row by row).
/// `filename` values come back as [`Value::File`] with the path as written and unresolved
/// (documents resolve them, [`document`]). `None` when the text does not hold a value of
/// the type or the type has no values (closures, shaders).
pub fn parse_value(ty: ValueType, text: &str) -> Option<Value> {
    let text = text.trim();
    match ty {
        ValueType::String => Some(Value::String(text.to_string())),
        ValueType::Filename => Some(Value::File(crate::shading::FileValue {
            asset: crate::reader::AssetRef {
                authored: text.to_string(),
                resolved: None,
            },
            colorspace: String::new(),
        })),
        ValueType::Boolean => match text {
            "true" | "1" => Some(Value::Numbers(vec![1.0])),
            "false" | "0" => Some(Value::Numbers(vec![0.0])),
            _ => None,
        },
        ValueType::Integer => text
            .parse::<i64>()
            .ok()
            .map(|i| Value::Numbers(vec![i as f64])),
        _ => {
            let n = ty.components();
            if n == 0 {
                return None;
            }
            let parts: Option<Vec<f64>> = text
                .split(',')
                .map(|s| s.trim().parse::<f64>().ok())
                .collect();
            let parts = parts?;
            (parts.len() == n && parts.iter().all(|v| v.is_finite()))
                .then_some(Value::Numbers(parts))
        }
    }
}

/// The value MaterialX gives an input of type `ty` that states none (MaterialX
/// Specification, "Inputs": 0 in every channel, `""` for strings and filenames, `false`,
/// the identity matrix); `None` for closures and shaders.
pub fn zero_value(ty: ValueType) -> Option<Value> {
    match ty {
        ValueType::String => Some(Value::String(String::new())),
        ValueType::Filename => parse_value(ty, ""),
        ValueType::Matrix33 | ValueType::Matrix44 => {
            let n = if ty == ValueType::Matrix33 { 3 } else { 4 };
            Some(Value::Numbers(
                (0..n * n)
                    .map(|i| if i / n == i % n { 1.0 } else { 0.0 })
                    .collect(),
            ))
        }
        _ => {
            let n = ty.components();
            (n > 0).then(|| Value::Numbers(vec![0.0; n]))
        }
    }
}
