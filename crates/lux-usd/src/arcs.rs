//! Composition-arc problems (usd-core's error policy): what failed, which layer authored the
//! arc, which prim it was on.
//!
//! usd-core composes a stage whose sublayers, references or payloads cannot be opened (a missing
//! file, a format it has no plugin for such as MaterialX `.mtlx`, a reference to a prim that does
//! not exist, a cycle): it reports each problem and composes the stage without that arc. The
//! loader does the same — every problem becomes a [`crate::Warning`] of kind
//! [`crate::WarningKind::Composition`] — unless `LoadOptions::strict` asks for the first one to
//! be a [`crate::LoadError::Composition`]. Only an unreadable root layer is always fatal.

use openusd::ar::{DefaultResolver, ResolvedPath, Resolver};
use openusd::pcp::Error as PcpError;
use openusd::sdf::{Path as SdfPath, Value};
use openusd::usd::{Prim, Stage};

/// One composition problem, located.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ArcProblem {
    /// The prim whose arc failed (`/` for layer-stack problems such as sublayers).
    pub prim: String,
    /// The layer that authored the failing arc.
    pub layer: String,
    /// What failed (names the asset path or target prim).
    pub message: String,
}

/// The located form of one of `openusd`'s composition diagnostics that drops an arc
/// (unresolved or malformed layer, missing prim or `defaultPrim`, cycle); `None` for the
/// diagnostics that drop no arc (e.g. inconsistent property types), which the loader records
/// as plain warnings.
pub fn arc_problem(e: &PcpError, root_layer: &str) -> Option<ArcProblem> {
    let root = || root_layer.to_owned();
    let (prim, layer) = match e {
        PcpError::UnresolvedLayer {
            site_path,
            introduced_by,
            ..
        }
        | PcpError::MalformedLayer {
            site_path,
            introduced_by,
            ..
        }
        | PcpError::UnresolvedPrimPath {
            site_path,
            introduced_by,
            ..
        } => (site_path.to_string(), introduced_by.clone()),
        PcpError::InvalidPrimPath { site_path, .. }
        | PcpError::MissingDefaultPrim { site_path, .. }
        | PcpError::InvalidDefaultPrim { site_path, .. } => (site_path.to_string(), root()),
        PcpError::ArcCycle(chain) => (chain.composing.to_string(), chain.root_layer.clone()),
        PcpError::UnresolvedSublayer { introduced_by, .. }
        | PcpError::MalformedSublayer { introduced_by, .. } => {
            ("/".to_owned(), introduced_by.clone())
        }
        PcpError::SublayerCycle { root_layer, .. } => ("/".to_owned(), root_layer.clone()),
        _ => return None,
    };
    Some(ArcProblem {
        prim,
        layer,
        message: e.to_string(),
    })
}

/// Whether the prim `path` has a spec in the layer `id` or (recursively, a few levels) in one
/// of its sublayers; `None` when the layer is not loaded on the stage.
fn layer_stack_has_prim(stage: &Stage, id: &str, path: &SdfPath, depth: usize) -> Option<bool> {
    let layer = stage.layer(id)?;
    if layer.prim(path.clone()).is_some() {
        return Some(true);
    }
    if depth == 0 {
        return Some(false);
    }
    let subs = layer
        .pseudo_root()
        .and_then(|r| r.sublayers())
        .unwrap_or_default();
    drop(layer);
    let resolver = DefaultResolver::new();
    Some(subs.iter().any(|sub| {
        let sub_id = resolver.create_identifier(sub, Some(&ResolvedPath::new(id)));
        layer_stack_has_prim(stage, &sub_id, path, depth - 1) == Some(true)
    }))
}

/// Added check: `openusd` 0.6 reports a reference whose target prim does not exist only for
/// payloads; the prim then silently composes without the referenced opinions. Every
/// `references` entry authored on `prim`'s specs is checked: an external target layer
/// (anchored at the authoring layer; an unresolvable one is reported by `openusd` itself) must
/// hold a spec at the target path (its `defaultPrim` when none is given); an internal
/// reference (`references = </Proto>`) must find its target in the layer stack of the layer
/// that authored it — the stage's own layer stack when that layer is in it, else the authoring
/// layer and its sublayers (the stack the reference was composed in).
pub fn missing_reference_targets(stage: &Stage, prim: &Prim) -> Result<Vec<ArcProblem>, String> {
    let resolver = DefaultResolver::new();
    let root_stack = stage.layer_stack();
    let mut out = Vec::new();
    for (layer_id, spec_path) in prim.prim_stack().map_err(message)? {
        let refs = {
            let Some(layer) = stage.layer(&layer_id) else {
                continue;
            };
            let Some(spec) = layer.prim(spec_path.clone()) else {
                continue;
            };
            match spec.field("references") {
                Ok(Some(Value::ReferenceListOp(op))) => op
                    .explicit_items
                    .into_iter()
                    .chain(op.prepended_items)
                    .chain(op.appended_items)
                    .chain(op.added_items)
                    .collect::<Vec<_>>(),
                _ => continue,
            }
        };
        for r in refs {
            let target = r.prim_path.as_str();
            let missing = if !target.is_empty() && !crate::reader::is_prim_path(target) {
                true
            } else if r.asset_path.is_empty() {
                if target.is_empty() {
                    false
                } else if root_stack.iter().any(|l| l == &layer_id) {
                    !stage
                        .prim(r.prim_path.clone())
                        .is_valid()
                        .map_err(message)?
                } else {
                    layer_stack_has_prim(stage, &layer_id, &r.prim_path, 8) == Some(false)
                }
            } else {
                let id =
                    resolver.create_identifier(&r.asset_path, Some(&ResolvedPath::new(&layer_id)));
                let target = if r.prim_path.is_empty() {
                    let default = stage
                        .layer(&id)
                        .and_then(|l| l.pseudo_root().and_then(|p| p.default_prim()));
                    match default.and_then(|d| SdfPath::new(&format!("/{}", d.as_str())).ok()) {
                        Some(p) => p,
                        None => continue, // reported by openusd (missing defaultPrim)
                    }
                } else {
                    r.prim_path.clone()
                };
                layer_stack_has_prim(stage, &id, &target, 8) == Some(false)
            };
            if missing {
                out.push(ArcProblem {
                    prim: prim.path().to_string(),
                    layer: layer_id.clone(),
                    message: format!(
                        "unresolved reference prim path @{}@<{}>: the target prim does not exist",
                        r.asset_path, r.prim_path
                    ),
                });
            }
        }
    }
    Ok(out)
}

/// An `openusd` error's full message (its causes joined).
fn message(e: impl std::fmt::Display) -> String {
    format!("{e:#}")
}
