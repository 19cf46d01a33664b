//! Typed attribute reads at the load frame, with file/prim/attribute context for errors.

use crate::error::{LoadError, Warning, WarningKind};
use crate::value;
use glam::{DMat4, DVec2, DVec3, DVec4};
use openusd::sdf::{FieldKey, Value};
use openusd::usd::{Prim, Stage, TimeCode};
use std::path::PathBuf;

/// Default upper bound on any array the loader copies (points, indices, primvars) and on one
/// mesh's triangulation: 2^27 elements ([`crate::LoadOptions::max_array_len`]).
pub const MAX_ARRAY_LEN: usize = 1 << 27;

/// Reads attributes of a composed stage at one time code. A property name that is not a USD
/// property name ([`is_property_name`]; e.g. an `xformOpOrder` entry or a primvar name taken
/// from authored text) reads as unauthored: `openusd` 0.6 does not validate such names and can
/// loop without end resolving them. Time samples are evaluated by
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
    /// Attributes of the wrong type, read as unauthored (taken into `warnings` by
    /// [`Reader::take_type_warnings`]).
    pub type_warnings: std::cell::RefCell<Vec<Warning>>,
    /// Size limits of this load.
    pub limits: crate::LoadOptions,
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
    ///
    /// Scalar floating-point time samples are re-evaluated here (the `.usda` parser reads them
    /// type-blind; they are interpolated with the attribute's declared type), so a `.usda` and
    /// a `.usdc` of the same stage give the same value at every time.
    pub fn raw(&self, prim: &Prim, name: &str) -> Result<Option<Value>, LoadError> {
        if !is_property_name(name) {
            return Ok(None);
        }
        let attr = prim.attribute(name);
        let v = attr
            .get_at::<Value>(TimeCode::new(self.time))
            .map_err(|e| self.usd_error(prim, format_args!("attribute {name}: {e:#}")))?;
        match v {
            Some(v @ (Value::Int64(_) | Value::Double(_))) => {
                self.typed_scalar_sample(prim, &attr, name, v).map(Some)
            }
            other => Ok(other),
        }
    }

    /// Work-around for `openusd` 0.6's text parser, which reads scalar time samples type-blind:
    /// `float inputs:intensity.timeSamples = { 1: 10, 3: 20 }` holds `Int64` samples (and
    /// `0.5` a `Double`), which its evaluator does not interpolate (nor a mix of the two), so
    /// frame 2 would read 10 instead of 15. For an attribute declared `half`, `float` or
    /// `double`, the bracketing samples are read back and interpolated in the declared
    /// precision, exactly as the evaluator does for typed samples (`a + (b − a)·t`, `f32`
    /// arithmetic for `float`/`half`); a value at or outside the samples is converted to the
    /// declared type. Any other declared type (`int`, `bool`…) keeps the evaluator's held value,
    /// as USD prescribes.
    fn typed_scalar_sample(
        &self,
        prim: &Prim,
        attr: &openusd::usd::Attribute,
        name: &str,
        v: Value,
    ) -> Result<Value, LoadError> {
        let err = |e: &dyn std::fmt::Display| {
            self.usd_error(prim, format_args!("attribute {name}: {e:#}"))
        };
        let declared = attr.type_name().map_err(|e| err(&e))?;
        let Some(declared) = declared.as_ref().map(|t| t.as_str()) else {
            return Ok(v);
        };
        if !matches!(declared, "half" | "float" | "double") {
            return Ok(v);
        }
        let Some(x) = value::as_f64(&v) else {
            return Ok(v);
        };
        let mut x = x;
        if let Some((lo, hi)) = attr
            .bracketing_time_samples(self.time)
            .map_err(|e| err(&e))?
            && lo < hi
        {
            let at = |t: f64| -> Result<Option<f64>, LoadError> {
                Ok(attr
                    .get_at::<Value>(TimeCode::new(t))
                    .map_err(|e| err(&e))?
                    .as_ref()
                    .and_then(value::as_f64))
            };
            if let (Some(a), Some(b)) = (at(lo)?, at(hi)?) {
                let t = (self.time - lo) / (hi - lo);
                x = match declared {
                    "double" => openusd::gf::lerp(a, b, t),
                    _ => f64::from(openusd::gf::lerp(a as f32, b as f32, t as f32)),
                };
            }
        }
        Ok(match declared {
            "half" => Value::Half(openusd::gf::f16::from_f64(x)),
            "float" => Value::Float(x as f32),
            _ => Value::Double(x),
        })
    }

    /// The raw composed value of `name`'s default (for `uniform` attributes and metadata-like
    /// reads), ignoring time samples.
    pub fn raw_default(&self, prim: &Prim, name: &str) -> Result<Option<Value>, LoadError> {
        if !is_property_name(name) {
            return Ok(None);
        }
        prim.attribute(name)
            .get::<Value>()
            .map_err(|e| self.usd_error(prim, format_args!("attribute {name}: {e:#}")))
    }

    /// A string/token metadata field `key` of attribute `name`, if authored (any failure to
    /// read it counts as unauthored).
    pub fn metadata_text(&self, prim: &Prim, name: &str, key: &str) -> Option<String> {
        if !is_property_name(name) {
            return None;
        }
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
            Some(v) => match conv(&v) {
                Some(x) => Ok(Some(x)),
                // usd-core opens such a stage without complaint (a renderer ignores the value):
                // a warning naming the attribute, the value read as unauthored; an error in a
                // strict load.
                None if self.limits.strict => Err(self.type_error(prim, name, expected, &v)),
                None => {
                    self.type_warnings.borrow_mut().push(Warning {
                        prim: prim.path().to_string(),
                        kind: WarningKind::InvalidValue,
                        message: format!(
                            "{name}: expected {expected}, found {}; ignored (read as unauthored)",
                            value::type_label(&v)
                        ),
                    });
                    Ok(None)
                }
            },
        }
    }

    /// Moves the wrong-type warnings into `warnings`.
    pub fn take_type_warnings(&mut self) {
        let w = std::mem::take(self.type_warnings.get_mut());
        self.warnings.extend(w);
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
    /// `.usda` fix produces); those are resolved here against the strongest layer of the
    /// attribute's property stack that authors a value (a weaker-than-value, metadata-only
    /// opinion does not re-anchor it), with `openusd`'s own anchoring rules: the layer's
    /// directory, or inside the package for a `.usdz` layer (`pkg.usdz[assets/a.ies]`).
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
        use openusd::ar::{DefaultResolver, ResolvedPath, Resolver};
        let stack = prim.attribute(name).property_stack().ok()?;
        // The strongest layer whose spec holds a value (a default or time samples); a weaker
        // spec that only adds metadata does not author the path.
        let (layer, _) = stack
            .iter()
            .find(|(layer, spec)| {
                self.stage.layer(layer).is_some_and(|l| {
                    l.attribute(spec.clone()).is_some_and(|a| {
                        a.has_field(FieldKey::Default.as_str())
                            || a.has_field(FieldKey::TimeSamples.as_str())
                    })
                })
            })
            .or(stack.first())?;
        // Anchor and resolve exactly as `openusd` does for the asset paths it resolves itself:
        // relative to the layer's directory, or inside the package for a `.usdz` layer
        // (`pkg.usdz[assets/a.ies]`, only when the package has that entry).
        let resolver = DefaultResolver::new();
        let id = resolver.create_identifier(authored, Some(&ResolvedPath::new(layer)));
        let resolved = resolver.resolve(&id)?;
        let path = PathBuf::from(resolved.to_string_lossy().into_owned());
        let packaged = openusd::ar::is_package_relative_path(&path.to_string_lossy());
        (packaged || path.is_file()).then_some(path)
    }

    fn capped<T>(&self, prim: &Prim, name: &'static str, v: Vec<T>) -> Result<Vec<T>, LoadError> {
        if v.len() > self.limits.max_array_len {
            return Err(LoadError::TooLarge {
                file: self.file.clone(),
                prim: prim.path().to_string(),
                what: name,
                count: v.len(),
                limit: self.limits.max_array_len,
            });
        }
        Ok(v)
    }

    /// An array attribute of at most `limits.max_array_len` elements, converted by `conv`.
    fn array<T>(
        &self,
        prim: &Prim,
        name: &'static str,
        expected: &'static str,
        conv: impl Fn(&Value) -> Option<Vec<T>>,
    ) -> Result<Option<Vec<T>>, LoadError> {
        match self.typed(prim, name, expected, conv)? {
            Some(v) => self.capped(prim, name, v).map(Some),
            None => Ok(None),
        }
    }

    /// A 3-vector array (points, normals, colours).
    pub fn vec3_array(
        &self,
        prim: &Prim,
        name: &'static str,
    ) -> Result<Option<Vec<DVec3>>, LoadError> {
        self.array(prim, name, "a 3-vector array", value::as_vec3_array)
    }

    /// A numeric array (`float[]`, `double[]`, `half[]`, `int[]`) as `f64`s (widths, knots,
    /// weights).
    pub fn f64_array(
        &self,
        prim: &Prim,
        name: &'static str,
    ) -> Result<Option<Vec<f64>>, LoadError> {
        self.array(prim, name, "a number array", value::as_f64_array)
    }

    /// A 2-vector array (texture coordinates).
    pub fn vec2_array(
        &self,
        prim: &Prim,
        name: &'static str,
    ) -> Result<Option<Vec<DVec2>>, LoadError> {
        self.array(prim, name, "a 2-vector array", value::as_vec2_array)
    }

    /// A quaternion array (`quath[]`, `quatf[]`, `quatd[]`).
    pub fn quat_array(
        &self,
        prim: &Prim,
        name: &'static str,
    ) -> Result<Option<Vec<glam::DQuat>>, LoadError> {
        self.array(prim, name, "a quaternion array", value::as_quat_array)
    }

    /// An `int64` list-op metadata field of `prim` (e.g. a PointInstancer's `inactiveIds`),
    /// composed over the prim's layer stack (strongest opinion last applied): the resulting
    /// list.
    pub fn int64_list_metadata(&self, prim: &Prim, key: &str) -> Result<Vec<i64>, LoadError> {
        let stack = prim.prim_stack().map_err(|e| self.usd_error(prim, e))?;
        let mut list: Vec<i64> = Vec::new();
        for (layer, spec_path) in stack.iter().rev() {
            let Some(l) = self.stage.layer(layer) else {
                continue;
            };
            let Some(spec) = l.prim(spec_path.clone()) else {
                continue;
            };
            match spec.field(key) {
                Ok(Some(Value::Int64ListOp(op))) => list = op.compose_over(&list),
                // `openusd` 0.6's text parser keeps an unregistered prim metadata list
                // (`inactiveIds = [3]`) as a plain array: an explicit list.
                Ok(Some(Value::Int64Vec(v))) => list = v,
                Ok(Some(Value::IntVec(v))) => list = v.into_iter().map(i64::from).collect(),
                Ok(Some(Value::IntListOp(op))) => {
                    let weaker: Vec<i32> =
                        list.iter().filter_map(|x| i32::try_from(*x).ok()).collect();
                    list = op
                        .compose_over(&weaker)
                        .into_iter()
                        .map(i64::from)
                        .collect();
                }
                _ => {}
            }
        }
        Ok(list)
    }

    /// An integer array.
    pub fn int_array(
        &self,
        prim: &Prim,
        name: &'static str,
    ) -> Result<Option<Vec<i64>>, LoadError> {
        self.array(prim, name, "an int array", value::as_int_array)
    }

    /// A string metadata field of an attribute (e.g. a primvar's `interpolation`).
    pub fn attr_metadata_text(&self, prim: &Prim, name: &str, key: &str) -> Option<String> {
        if !is_property_name(name) {
            return None;
        }
        prim.attribute(name)
            .get_metadata::<Value>(key)
            .ok()
            .flatten()
            .and_then(|v| value::as_text(&v))
    }

    /// Prim-path targets of a relationship (empty when unauthored). A target that is not a
    /// plain prim path ([`is_prim_path`]) is dropped with an `InvalidValue` warning.
    pub fn targets(&mut self, prim: &Prim, name: &str) -> Result<Vec<String>, LoadError> {
        if !is_property_name(name) {
            return Ok(Vec::new());
        }
        let all: Vec<String> = prim
            .relationship(name)
            .targets()
            .map(|t| t.iter().map(|p| p.to_string()).collect())
            .map_err(|e| self.usd_error(prim, format_args!("relationship {name}: {e:#}")))?;
        let mut out = Vec::with_capacity(all.len());
        for t in all {
            if is_prim_path(&t) {
                out.push(t);
            } else {
                self.warn(
                    prim,
                    WarningKind::InvalidValue,
                    format!("{name}: target {t:?} is not a prim path; ignored"),
                );
            }
        }
        Ok(out)
    }

    /// Connection sources of an attribute (empty when unauthored).
    pub fn connections(&self, prim: &Prim, name: &str) -> Result<Vec<String>, LoadError> {
        if !is_property_name(name) {
            return Ok(Vec::new());
        }
        prim.attribute(name)
            .connections()
            .map(|t| t.iter().map(|p| p.to_string()).collect())
            .map_err(|e| self.usd_error(prim, format_args!("connection {name}: {e:#}")))
    }
}

/// Whether `name` is a USD identifier (a prim name, or one namespace segment of a property
/// name): a letter or `_` followed by letters, digits or `_`.
fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_alphabetic() || c == '_')
        && chars.all(|c| c.is_alphanumeric() || c == '_')
}

/// Whether `path` is a plain absolute prim path (`/A/B`, no variant selections or
/// properties).
///
/// `openusd` 0.6 accepts any text between `<` and `>` as a path (newlines, spaces and braces
/// included), and looking such a path up on the stage recurses without end in its instancing
/// code (a stack overflow found by the `usda` fuzz target). Every authored path the loader
/// looks up (relationship targets, connection sources, reference targets) is checked here
/// first.
pub fn is_prim_path(path: &str) -> bool {
    path.strip_prefix('/')
        .is_some_and(|rest| rest.split('/').all(is_identifier))
}

/// Whether `name` is a (possibly namespaced) property name: identifiers joined by `:`.
pub fn is_property_name(name: &str) -> bool {
    name.split(':').all(is_identifier)
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
