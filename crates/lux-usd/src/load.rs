//! Loading a stage: open the root layer with `openusd`, walk the composed prims
//! ([`crate::walk`]), then apply usd-core's error policy to what failed to compose
//! ([`crate::arcs`]).

use crate::arcs::{ArcProblem, arc_problem};
use crate::error::{LoadError, Warning, WarningKind};
use crate::reader::Reader;
use crate::resolver::LuxResolver;
use crate::walk::{Inherited, Walk};
use crate::{Scene, UpAxis};
use openusd::usd::Stage;
use std::path::Path;

/// Limits of a load: inputs beyond them are a [`LoadError::TooLarge`], never an allocation
/// failure or a stack overflow. `Default` gives the limits [`load_stage`] uses.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct LoadOptions {
    /// Largest array the loader copies (points, indices, primvars) and largest triangulation
    /// of one mesh, in elements (default 2^27).
    pub max_array_len: usize,
    /// Deepest prim namespace nesting walked (default 256), also the deepest nesting of
    /// instances within prototypes.
    pub max_depth: usize,
    /// usd-core's policy is the default (`false`): a sublayer, reference or payload that
    /// cannot be composed (missing file, unknown format, missing target prim, cycle) is a
    /// [`WarningKind::Composition`] warning and the stage composes without it. `true` makes
    /// the first such problem a [`LoadError::Composition`], for pipelines that want that.
    pub strict: bool,
}

impl Default for LoadOptions {
    fn default() -> LoadOptions {
        LoadOptions {
            max_array_len: crate::reader::MAX_ARRAY_LEN,
            max_depth: 256,
            strict: false,
        }
    }
}

/// The time code a stage is evaluated at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Time {
    /// The stage's `startTimeCode` (else the legacy `startFrame`, else 0): what usdrecord
    /// renders when no frame is given (`UsdStage::GetStartTimeCode`).
    Start,
    /// This time code.
    Code(f64),
}

impl From<f64> for Time {
    fn from(t: f64) -> Time {
        Time::Code(t)
    }
}

/// The identifier of the in-memory root layer of [`load_usda_str`] (also its `Scene::source`).
pub const MEMORY_LAYER: &str = "/__lux_memory__/stage.usda";

/// Loads the USD stage at `path` (`.usda`, `.usdc` or `.usdz`) and evaluates it at time code
/// `frame` into a plain [`Scene`], with the default [`LoadOptions`].
///
/// Composition (sublayers, references, payloads, inherits, variants, `over`s, layer offsets,
/// instancing) is `openusd`'s. As in usd-core, an arc that fails to compose (missing file,
/// unknown file format, missing prim, malformed layer, cycle) is a
/// [`WarningKind::Composition`] warning naming the arc, the layer that authored it and the
/// prim, and the stage composes without it (`LoadOptions::strict` makes it a
/// [`LoadError::Composition`]); only an unreadable root layer is fatal. Everything that is
/// merely ignored or unsupported becomes a [`Warning`] in `Scene::warnings`;
/// renderer-specific attributes and unknown prim types are skipped silently.
pub fn load_stage(path: impl AsRef<Path>, frame: impl Into<Time>) -> Result<Scene, LoadError> {
    load_stage_with(path, frame, &LoadOptions::default())
}

/// [`load_stage`] with explicit [`LoadOptions`].
pub fn load_stage_with(
    path: impl AsRef<Path>,
    frame: impl Into<Time>,
    options: &LoadOptions,
) -> Result<Scene, LoadError> {
    let path = path.as_ref();
    let frame = frame.into();
    if let Time::Code(frame) = frame
        && !frame.is_finite()
    {
        return Err(LoadError::InvalidFrame { frame });
    }
    if path.is_dir() {
        return Err(LoadError::IsDirectory {
            file: path.to_path_buf(),
        });
    }
    if !path.is_file() {
        return Err(LoadError::NotFound {
            file: path.to_path_buf(),
        });
    }
    let path_str = path.to_string_lossy().into_owned();
    let bytes = std::fs::read(path).ok();
    load_with(
        LuxResolver::new(),
        &path_str,
        path,
        frame,
        options,
        bytes.as_deref(),
    )
}

/// Loads a stage whose root layer is the `.usda` text `text` (no file involved), evaluated at
/// `frame`. Its `Scene::source` is [`MEMORY_LAYER`]; relative asset paths in it resolve
/// against that non-existent directory, so external arcs fail as unresolved (absolute paths
/// still work). Used by the fuzz target.
pub fn load_usda_str(
    text: &str,
    frame: impl Into<Time>,
    options: &LoadOptions,
) -> Result<Scene, LoadError> {
    let frame = frame.into();
    if let Time::Code(frame) = frame
        && !frame.is_finite()
    {
        return Err(LoadError::InvalidFrame { frame });
    }
    let resolver = LuxResolver::with_memory_layer(MEMORY_LAYER, text.as_bytes().to_vec());
    load_with(
        resolver,
        MEMORY_LAYER,
        Path::new(MEMORY_LAYER),
        frame,
        options,
        Some(text.as_bytes()),
    )
}

/// [`load_inner`] with `openusd`'s panics on malformed input (it has `todo!()`s and unchecked
/// indexing in places) turned into a [`LoadError::Malformed`] naming the file: bad input never
/// takes the caller down.
fn load_with(
    resolver: LuxResolver,
    identifier: &str,
    path: &Path,
    frame: Time,
    options: &LoadOptions,
    root_bytes: Option<&[u8]>,
) -> Result<Scene, LoadError> {
    let run = std::panic::AssertUnwindSafe(|| {
        load_inner(resolver, identifier, path, frame, options, root_bytes)
    });
    match std::panic::catch_unwind(run) {
        Ok(result) => result,
        Err(panic) => {
            let what = panic
                .downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| panic.downcast_ref::<&str>().copied())
                .unwrap_or("unknown failure");
            Err(LoadError::Malformed {
                file: path.to_path_buf(),
                message: format!("the USD reader failed on malformed data ({what})"),
            })
        }
    }
}

fn load_inner(
    resolver: LuxResolver,
    identifier: &str,
    path: &Path,
    frame: Time,
    options: &LoadOptions,
    root_bytes: Option<&[u8]>,
) -> Result<Scene, LoadError> {
    let stage = Stage::builder()
        .resolver(resolver)
        .open(identifier)
        .map_err(|e| LoadError::Malformed {
            file: path.to_path_buf(),
            // A text root layer's parse error names its line and column.
            message: match root_bytes.and_then(|b| crate::describe_usda_error(path, b)) {
                Some(located) => located,
                None => format!("{e:#}"),
            },
        })?;
    let root_layer = path.to_string_lossy().into_owned();
    // Layer-stack problems (a missing or malformed sublayer, a sublayer cycle) are known once
    // the stage is open: a strict load stops here.
    if options.strict {
        strict_check(&stage, path, &root_layer)?;
    }
    let frame = match frame {
        Time::Code(t) => t,
        Time::Start => start_time_code(&stage),
    };
    let mut scene = Scene::empty(path);
    scene.frame = frame;
    let up = stage
        .stage_metadata("upAxis")
        .ok()
        .flatten()
        .and_then(|v| crate::value::as_text(&v));
    let mut up_warning = None;
    scene.up_axis = match up.as_deref() {
        Some("Z") => UpAxis::Z,
        None | Some("Y") => UpAxis::Y,
        Some(other) => {
            up_warning = Some(Warning {
                prim: "/".into(),
                kind: WarningKind::InvalidValue,
                message: format!("upAxis {other:?} is not \"Y\" or \"Z\"; using Y"),
            });
            UpAxis::Y
        }
    };
    scene.meters_per_unit = stage
        .stage_metadata("metersPerUnit")
        .ok()
        .flatten()
        .and_then(|v| crate::value::as_f64(&v))
        .filter(|m| m.is_finite() && *m > 0.0)
        .unwrap_or(0.01);
    let unit = stage
        .stage_metadata("unitForWavelength")
        .ok()
        .flatten()
        .and_then(|v| crate::value::as_text(&v));
    let mut unit_warning = None;
    scene.unit_for_wavelength = match crate::spectral::stage_wavelength_unit(unit.as_deref()) {
        Ok(u) => u,
        Err(message) => {
            unit_warning = Some(Warning {
                prim: "/".into(),
                kind: WarningKind::InvalidValue,
                message: format!("{message}; using nanometers"),
            });
            lux_spectral::WavelengthUnit::Nanometers
        }
    };
    scene.time_code_range = stage
        .has_authored_time_code_range()
        .then(|| [stage.start_time_code(), stage.end_time_code()]);
    let reader = Reader {
        stage: &stage,
        file: path.to_path_buf(),
        time: frame,
        warnings: Vec::new(),
        type_warnings: Default::default(),
        limits: options.clone(),
    };
    let mut walk = Walk::new(reader, scene);
    let roots = stage.root_prims().map_err(|e| LoadError::Usd {
        file: path.to_path_buf(),
        prim: "/".into(),
        message: format!("{e:#}"),
    })?;
    for name in roots {
        let prim = stage.prim(format!("/{name}").as_str());
        walk.visit(&prim, &Inherited::root(), 0)?;
    }
    if options.strict {
        strict_check(&stage, path, &root_layer)?;
    }
    let (mut scene, warnings, problems) = walk.finish();
    // usd-core's policy: every arc that failed is reported once, the stage composed without it.
    let mut seen = std::collections::HashSet::new();
    let mut all = Vec::new();
    let mut other = Vec::new();
    let arc_problems = problems.into_iter().chain(
        stage
            .composition_errors()
            .iter()
            .filter_map(|e| match arc_problem(e, &root_layer) {
                Some(mut p) => {
                    locate_layer(e, &mut p);
                    Some(p)
                }
                None => {
                    other.push(Warning {
                        prim: "/".into(),
                        kind: WarningKind::Ignored,
                        message: format!("composition: {e}"),
                    });
                    None
                }
            })
            .collect::<Vec<_>>(),
    );
    for p in arc_problems {
        if seen.insert((p.prim.clone(), p.message.clone())) {
            all.push(arc_warning(&p));
        }
    }
    all.extend(up_warning);
    all.extend(unit_warning);
    all.extend(warnings);
    all.extend(other);
    scene.warnings = all;
    for s in &scene.render_settings {
        let targets =
            std::iter::once(&s.base.camera).chain(s.products.iter().map(|p| &p.base.camera));
        for cam in targets.flatten() {
            if !scene.cameras.iter().any(|c| &c.path == cam) {
                scene.warnings.push(Warning {
                    prim: s.path.clone(),
                    kind: WarningKind::InvalidValue,
                    message: format!(
                        "camera <{cam}> is not a drawn Camera; using the first camera"
                    ),
                });
            }
        }
    }
    Ok(scene)
}

/// The stage's `startTimeCode`, else its legacy `startFrame`, else 0 (as
/// `UsdStage::GetStartTimeCode`).
fn start_time_code(stage: &Stage) -> f64 {
    let meta = |k: &str| {
        stage
            .stage_metadata(k)
            .ok()
            .flatten()
            .and_then(|v| crate::value::as_f64(&v))
            .filter(|t| t.is_finite())
    };
    meta("startTimeCode")
        .or_else(|| meta("startFrame"))
        .unwrap_or(0.0)
}

/// A malformed `.usda` layer's problem with `openusd`'s reason ("failed to parse USDA layer:
/// …") replaced by `FILE:LINE:COLUMN: message`. A reference or payload names the resolved layer,
/// a sublayer the path as authored (anchored here at the layer that introduced it).
fn locate_layer(e: &openusd::pcp::Error, p: &mut ArcProblem) {
    use openusd::ar::{DefaultResolver, ResolvedPath, Resolver};
    let (located, reason) = match e {
        openusd::pcp::Error::MalformedLayer {
            asset_path, reason, ..
        } => (crate::describe_usda_layer_error(asset_path), reason),
        openusd::pcp::Error::MalformedSublayer {
            asset_path,
            introduced_by,
            reason,
        } => {
            let id = DefaultResolver::new()
                .create_identifier(asset_path, Some(&ResolvedPath::new(introduced_by)));
            (crate::describe_usda_layer_error(&id), reason)
        }
        _ => return,
    };
    // A MaterialX document's reason already names its file and line (`crate::mtlx`).
    if reason.contains(".mtlx:") {
        return;
    }
    if let Some(at) = located {
        p.message = match p.message.strip_suffix(reason.as_str()) {
            Some(head) => format!("{head}{at}"),
            None => format!("{}: {at}", p.message),
        };
    }
}

/// A composition problem as a warning: the arc, the layer that authored it, and that the stage
/// composed without it.
fn arc_warning(p: &ArcProblem) -> Warning {
    Warning {
        prim: p.prim.clone(),
        kind: WarningKind::Composition,
        message: format!(
            "{} (arc authored in {}); composed without it",
            p.message, p.layer
        ),
    }
}

/// The first composition problem `openusd` collected so far, as a
/// [`LoadError::Composition`] (strict loads only).
fn strict_check(stage: &Stage, file: &Path, root_layer: &str) -> Result<(), LoadError> {
    for e in stage.composition_errors() {
        if let Some(mut p) = arc_problem(&e, root_layer) {
            locate_layer(&e, &mut p);
            return Err(composition_error(file, p));
        }
    }
    Ok(())
}

/// A composition problem as the error of a strict load.
pub(crate) fn composition_error(file: &Path, p: ArcProblem) -> LoadError {
    LoadError::Composition {
        file: file.to_path_buf(),
        layer: p.layer,
        prim: p.prim,
        message: p.message,
    }
}
