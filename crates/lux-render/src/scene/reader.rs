//! Typed attribute reads at the load frame, with file/prim/attribute context for errors.

use super::error::{LoadError, Warning, WarningKind};
use super::value;
use glam::{DMat4, DVec2, DVec3, DVec4};
use openusd::sdf::Value;
use openusd::usd::{Prim, Stage, TimeCode};
use std::path::PathBuf;

/// Upper bound on any array the loader copies (points, indices, primvars): 2^27 elements.
pub const MAX_ARRAY_LEN: usize = 1 << 27;

/// Reads attributes of a composed stage at one time code. Time samples are evaluated by
/// `openusd` (AOUSD §12.5): linear interpolation for numbers, vectors, matrices and quaternions
/// (slerp), held for everything else, clamped before the first and after the last sample.
pub struct Reader<'s> {
    /// The composed stage.
    pub stage: &'s Stage,
    /// The root layer (for error messages).
    pub file: PathBuf,
    /// The time code values are read at.
    pub time: f64,
    /// Collected warnings.
    pub warnings: Vec<Warning>,
}

impl<'s> Reader<'s> {
    /// Records a warning.
    pub fn warn(&mut self, prim: &Prim, kind: WarningKind, message: impl Into<String>) {
        self.warnings.push(Warning {
            prim: prim.path().to_string(),
            kind,
            message: message.into(),
        });
    }

    /// A `LoadError::Usd` for an `openusd` failure on `prim`.
    pub fn usd_error(&self, prim: &Prim, err: impl std::fmt::Display) -> LoadError {
        LoadError::Usd {
            file: self.file.clone(),
            prim: prim.path().to_string(),
            message: format!("{err:#}"),
        }
    }

    fn type_error(&self, prim: &Prim, name: &str, expected: &'static str, v: &Value) -> LoadError {
        LoadError::AttributeType {
            file: self.file.clone(),
            prim: prim.path().to_string(),
            attribute: name.to_owned(),
            expected,
            found: value::type_label(v),
        }
    }

    /// The raw composed value of `name` at the load time; `None` when unauthored or blocked.
    pub fn raw(&self, prim: &Prim, name: &str) -> Result<Option<Value>, LoadError> {
        prim.attribute(name)
            .get_at::<Value>(TimeCode::new(self.time))
            .map_err(|e| self.usd_error(prim, format_args!("attribute {name}: {e:#}")))
    }

    /// The raw composed value of `name`'s default (for `uniform` attributes and metadata-like
    /// reads), ignoring time samples.
    pub fn raw_default(&self, prim: &Prim, name: &str) -> Result<Option<Value>, LoadError> {
        prim.attribute(name)
            .get::<Value>()
            .map_err(|e| self.usd_error(prim, format_args!("attribute {name}: {e:#}")))
    }

    /// A string/token metadata field `key` of attribute `name`, if authored (any failure to
    /// read it counts as unauthored).
    pub fn metadata_text(&self, prim: &Prim, name: &str, key: &str) -> Option<String> {
        prim.attribute(name)
            .get_metadata::<Value>(key)
            .ok()
            .flatten()
            .and_then(|v| value::as_text(&v))
    }

    fn typed<T>(
        &self,
        prim: &Prim,
        name: &str,
        expected: &'static str,
        conv: impl Fn(&Value) -> Option<T>,
    ) -> Result<Option<T>, LoadError> {
        match self.raw(prim, name)? {
            None => Ok(None),
            Some(v) => conv(&v)
                .map(Some)
                .ok_or_else(|| self.type_error(prim, name, expected, &v)),
        }
    }

    /// A number, or `None` when unauthored. Wrong type → `LoadError::AttributeType`.
    pub fn f64(&self, prim: &Prim, name: &str) -> Result<Option<f64>, LoadError> {
        self.typed(prim, name, "a number", value::as_f64)
    }

    /// A number with its schema default when unauthored; a non-finite value is replaced by the
    /// default with an `InvalidValue` warning.
    pub fn f64_or(&mut self, prim: &Prim, name: &str, default: f64) -> Result<f64, LoadError> {
        match self.f64(prim, name)? {
            None => Ok(default),
            Some(x) if x.is_finite() => Ok(x),
            Some(x) => {
                self.warn(
                    prim,
                    WarningKind::InvalidValue,
                    format!("{name} = {x} is not finite; using the schema default {default}"),
                );
                Ok(default)
            }
        }
    }

    /// A non-negative size (radius, width…): default when unauthored or non-finite, absolute
    /// value (with a warning) when negative.
    pub fn size_or(&mut self, prim: &Prim, name: &str, default: f64) -> Result<f64, LoadError> {
        let x = self.f64_or(prim, name, default)?;
        if x < 0.0 {
            self.warn(
                prim,
                WarningKind::InvalidValue,
                format!("{name} = {x} is negative; using its absolute value"),
            );
            return Ok(-x);
        }
        Ok(x)
    }

    /// A boolean, or `None` when unauthored.
    pub fn bool(&self, prim: &Prim, name: &str) -> Result<Option<bool>, LoadError> {
        self.typed(prim, name, "a bool", value::as_bool)
    }

    /// A boolean with its default when unauthored.
    pub fn bool_or(&self, prim: &Prim, name: &str, default: bool) -> Result<bool, LoadError> {
        Ok(self.bool(prim, name)?.unwrap_or(default))
    }

    /// A token or string, or `None` when unauthored.
    pub fn text(&self, prim: &Prim, name: &str) -> Result<Option<String>, LoadError> {
        self.typed(prim, name, "a token or string", value::as_text)
    }

    /// A 2-vector.
    pub fn vec2(&self, prim: &Prim, name: &str) -> Result<Option<DVec2>, LoadError> {
        self.typed(prim, name, "a 2-vector", value::as_vec2)
    }

    /// A 3-vector (colour, point, vector).
    pub fn vec3(&self, prim: &Prim, name: &str) -> Result<Option<DVec3>, LoadError> {
        self.typed(prim, name, "a 3-vector", value::as_vec3)
    }

    /// A 3-vector with a default; non-finite components → default with a warning.
    pub fn vec3_or(&mut self, prim: &Prim, name: &str, default: DVec3) -> Result<DVec3, LoadError> {
        match self.vec3(prim, name)? {
            None => Ok(default),
            Some(v) if v.is_finite() => Ok(v),
            Some(v) => {
                self.warn(
                    prim,
                    WarningKind::InvalidValue,
                    format!("{name} = {v} is not finite; using the schema default {default}"),
                );
                Ok(default)
            }
        }
    }

    /// A 4-vector.
    pub fn vec4(&self, prim: &Prim, name: &str) -> Result<Option<DVec4>, LoadError> {
        self.typed(prim, name, "a 4-vector", value::as_vec4)
    }

    /// A `matrix4d`.
    pub fn matrix(&self, prim: &Prim, name: &str) -> Result<Option<DMat4>, LoadError> {
        self.typed(prim, name, "a matrix4d", value::as_matrix4)
    }

    /// An asset path with its resolution; `None` when unauthored or empty (`@@`).
    ///
    /// `openusd` 0.6 does not resolve asset paths held in time samples (nor in the arrays the
    /// `.usda` fix produces); those are resolved here against the directory of the strongest
    /// layer that authors the attribute (its property stack), when that layer is a plain file.
    pub fn asset(&self, prim: &Prim, name: &str) -> Result<Option<AssetRef>, LoadError> {
        let Some((authored, resolved)) = self
            .typed(prim, name, "an asset path", value::as_asset)?
            .filter(|(a, _)| !a.is_empty())
        else {
            return Ok(None);
        };
        let resolved = match resolved {
            Some(r) => Some(PathBuf::from(r)),
            None => self.resolve_fallback(prim, name, &authored),
        };
        Ok(Some(AssetRef { authored, resolved }))
    }

    fn resolve_fallback(&self, prim: &Prim, name: &str, authored: &str) -> Option<PathBuf> {
        let candidate = std::path::Path::new(authored);
        if candidate.is_absolute() {
            return candidate.is_file().then(|| candidate.to_path_buf());
        }
        let stack = prim.attribute(name).property_stack().ok()?;
        let (layer, _) = stack.first()?;
        if layer.contains('[') {
            return None; // inside a package: left unresolved
        }
        let dir = std::path::Path::new(layer).parent()?;
        let p = dir.join(candidate);
        p.is_file().then(|| p.canonicalize().unwrap_or(p))
    }

    fn capped<T>(&self, prim: &Prim, name: &'static str, v: Vec<T>) -> Result<Vec<T>, LoadError> {
        if v.len() > MAX_ARRAY_LEN {
            return Err(LoadError::TooLarge {
                file: self.file.clone(),
                prim: prim.path().to_string(),
                what: name,
                count: v.len(),
                limit: MAX_ARRAY_LEN,
            });
        }
        Ok(v)
    }

    /// A 3-vector array (points, normals, colours).
    pub fn vec3_array(
        &self,
        prim: &Prim,
        name: &'static str,
    ) -> Result<Option<Vec<DVec3>>, LoadError> {
        match self.typed(prim, name, "a 3-vector array", value::as_vec3_array)? {
            Some(v) => self.capped(prim, name, v).map(Some),
            None => Ok(None),
        }
    }

    /// A 2-vector array (texture coordinates).
    pub fn vec2_array(
        &self,
        prim: &Prim,
        name: &'static str,
    ) -> Result<Option<Vec<DVec2>>, LoadError> {
        match self.typed(prim, name, "a 2-vector array", value::as_vec2_array)? {
            Some(v) => self.capped(prim, name, v).map(Some),
            None => Ok(None),
        }
    }

    /// An integer array.
    pub fn int_array(
        &self,
        prim: &Prim,
        name: &'static str,
    ) -> Result<Option<Vec<i64>>, LoadError> {
        match self.typed(prim, name, "an int array", value::as_int_array)? {
            Some(v) => self.capped(prim, name, v).map(Some),
            None => Ok(None),
        }
    }

    /// A string metadata field of an attribute (e.g. a primvar's `interpolation`).
    pub fn attr_metadata_text(&self, prim: &Prim, name: &str, key: &str) -> Option<String> {
        prim.attribute(name)
            .get_metadata::<Value>(key)
            .ok()
            .flatten()
            .and_then(|v| value::as_text(&v))
    }

    /// Targets of a relationship (empty when unauthored).
    pub fn targets(&self, prim: &Prim, name: &str) -> Result<Vec<String>, LoadError> {
        prim.relationship(name)
            .targets()
            .map(|t| t.iter().map(|p| p.to_string()).collect())
            .map_err(|e| self.usd_error(prim, format_args!("relationship {name}: {e:#}")))
    }

    /// Connection sources of an attribute (empty when unauthored).
    pub fn connections(&self, prim: &Prim, name: &str) -> Result<Vec<String>, LoadError> {
        prim.attribute(name)
            .connections()
            .map(|t| t.iter().map(|p| p.to_string()).collect())
            .map_err(|e| self.usd_error(prim, format_args!("connection {name}: {e:#}")))
    }
}

/// An asset-valued attribute: the path as authored and, when it names an existing file, the
/// path resolved against the layer that authored it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AssetRef {
    /// The asset path as written between `@…@`.
    pub authored: String,
    /// The resolved filesystem path (`None` if the asset does not exist).
    pub resolved: Option<PathBuf>,
}
