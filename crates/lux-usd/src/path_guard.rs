//! Refuses layers holding an SdfPath that `openusd` 0.6's composition cannot walk.
//!
//! `openusd` 0.6.0's `sdf::Path::parent` returns the path itself for a prim path that ends in
//! `}` without being a variant selection (its last `/` or `}` is the final character), so every
//! loop that walks a path's ancestors up to the root — the prim indexer's relocation check does
//! so for each reference target — never ends. The `.usda` parser accepts such paths inside
//! `<…>`, and a `.usdc` can hold them as tokens. Found by the `usda` fuzz target (a 413-byte
//! layer that hung `lux info`).
//!
//! The loader's resolver runs [`first_unwalkable_path`] on every layer it serves before
//! `openusd` composes it, and refuses the layer with the offending path; text layers are first
//! screened by [`usda_may_hold_unwalkable_path`] so that ordinary scenes are parsed only once.

use openusd::sdf::{self, AbstractData, Value};

/// Whether walking `p`'s ancestors with `openusd`'s [`sdf::Path::parent`] ends (at the root,
/// at a relative path's first element, or at the empty path). Every proper step shortens the
/// path, so a walk longer than the path's length, or a step that returns the path itself,
/// never ends.
pub fn parents_terminate(p: &sdf::Path) -> bool {
    let mut cur = p.clone();
    for _ in 0..=p.as_str().len() {
        match cur.parent() {
            None => return true,
            Some(next) if next.is_abs_root() => return true,
            Some(next) if next.as_str().len() >= cur.as_str().len() => return false,
            Some(next) => cur = next,
        }
    }
    false
}

/// The first composition-arc target of `data` whose ancestor walk never ends
/// ([`parents_terminate`]): reference and payload prim paths, inherits and specializes. (Spec
/// paths and relationship targets with such names are left to the loader, which skips prims
/// whose names are not identifiers before composing them, and reads relationship targets
/// itself.)
pub fn first_unwalkable_path(data: &dyn AbstractData) -> Option<String> {
    let bad = |p: &sdf::Path| (!parents_terminate(p)).then(|| p.as_str().to_owned());
    for spec in data.spec_paths() {
        for field in data.list_fields(&spec).unwrap_or_default() {
            let Ok(Some(value)) = data.try_field(&spec, &field) else {
                continue;
            };
            let found = match value.as_ref() {
                Value::ReferenceListOp(op) => op.iter().find_map(|r| bad(&r.prim_path)),
                Value::PayloadListOp(op) => op.iter().find_map(|r| bad(&r.prim_path)),
                Value::PathListOp(op) if field == "inheritPaths" || field == "specializes" => {
                    op.iter().find_map(bad)
                }
                _ => None,
            };
            if found.is_some() {
                return found;
            }
        }
    }
    None
}

/// A cheap screen of `.usda` text: whether a path literal `<…>` contains a `}` — the only way
/// such a layer can hold an arc target [`first_unwalkable_path`] refuses. False positives (a
/// `}` in an ordinary variant-selection path, or in a relationship target) only cost a second
/// parse.
pub fn usda_may_hold_unwalkable_path(text: &str) -> bool {
    let mut rest = text;
    while let Some(open) = rest.find('<') {
        let after = &rest[open + 1..];
        let close = after.find('>').unwrap_or(after.len());
        if after[..close].contains('}') {
            return true;
        }
        rest = &after[close..];
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parent_walks() {
        for ok in ["/A/B/C", "/A{v=s}B", "/A.attr", "A/B", "", "/", "/A{v=s}"] {
            assert!(parents_terminate(&sdf::Path::from(ok)), "{ok}");
        }
        for bad in ["/A}", "/A/B}}", "/x}y}"] {
            assert!(!parents_terminate(&sdf::Path::from(bad)), "{bad}");
        }
    }

    #[test]
    fn usda_screen() {
        assert!(!usda_may_hold_unwalkable_path(
            "#usda 1.0\ndef Xform \"A\" (\n references = </B>\n)\n{\n}\n"
        ));
        assert!(usda_may_hold_unwalkable_path(
            "def Xform \"A\" (\n references = </B}>\n)\n{}\n"
        ));
        // a brace in a doc string or a prim name is not an arc target
        assert!(!usda_may_hold_unwalkable_path(
            "def \"A}\" (\n doc = \"x}\"\n)\n{}\n"
        ));
    }
}
