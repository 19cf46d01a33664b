//! MaterialX looks, collections and material assignments in the prims usdMtlx makes of them
//! (`UsdMtlxRead`), so that a document's looks bind its materials when it is referenced
//! onto an asset (`@looks.mtlx@</ModelRoot>`):
//!
//! - `/MaterialX/Collections` carries one `UsdCollectionAPI` instance per `<collection>`
//!   (`includegeom` / `excludegeom` as includes / excludes, `includecollection` as included
//!   collections) and one `geom_<n>` per distinct `geom` list of a `<materialassign>`; every
//!   geometry path (with `geomprefix` applied) is re-rooted under `/MaterialX/Collections`, so
//!   that it lands below whatever prim references the look;
//! - `/MaterialX/Looks/<look>` references `/MaterialX/Collections` (and the look it
//!   `inherit`s), holds a Material per `<materialassign>` under `Materials` (referencing
//!   `/MaterialX/Materials/<material>`) and binds each with
//!   `material:binding:collection:<assign>` to its collection, or directly when the assign
//!   names no geometry, in assignment order (`reorder properties`);
//! - `/ModelRoot` has a variant set `LookVariant` with one variant per look, each
//!   referencing `/MaterialX/Looks/<look>`; the last look is selected.
//!
//! Geometry paths that are not plain absolute prim paths (MaterialX geometry expressions with
//! wildcards) are left out, as usdMtlx leaves them out. Material variants (`<variantset>`,
//! `<variantassign>`) are not translated.

use super::document::{Document, Look, Node};
use crate::reader::is_prim_path;

const COLLECTIONS: &str = "/MaterialX/Collections";
const LOOKS: &str = "/MaterialX/Looks";

/// A MaterialX name as a USD prim or property name (a namespace colon becomes `__`).
fn usd_name(name: &str) -> String {
    name.replace(':', "__")
}

/// A geometry path re-rooted under `/MaterialX/Collections`; `None` for anything that is not a
/// plain absolute prim path.
fn rerooted(path: &str) -> Option<String> {
    let p = path.trim();
    if p == "/" {
        return Some(COLLECTIONS.to_string());
    }
    is_prim_path(p).then(|| format!("{COLLECTIONS}{p}"))
}

/// One collection on `/MaterialX/Collections`.
struct Coll {
    name: String,
    includes: Vec<String>,
    excludes: Vec<String>,
}

/// The collections: the document's, then one per distinct `geom` list of an assign; and, per
/// (look, assign), the collection it binds to (`None`: bound directly).
fn collections(doc: &Document) -> (Vec<Coll>, Vec<Vec<Option<String>>>) {
    let mut out: Vec<Coll> = doc
        .collections
        .iter()
        .map(|c| Coll {
            name: usd_name(&c.name),
            includes: c
                .includegeom
                .iter()
                .filter_map(|p| rerooted(p))
                .chain(
                    c.includecollection
                        .iter()
                        .filter(|n| doc.collections.iter().any(|o| o.name == **n))
                        .map(|n| format!("{COLLECTIONS}.collection:{}", usd_name(n))),
                )
                .collect(),
            excludes: c.excludegeom.iter().filter_map(|p| rerooted(p)).collect(),
        })
        .collect();
    let mut geom_sets: Vec<(String, String)> = Vec::new();
    let mut next = 1;
    let mut per_look = Vec::new();
    for look in &doc.looks {
        let mut per_assign = Vec::new();
        for a in &look.assigns {
            let bound = if let Some(c) = &a.collection {
                doc.collections
                    .iter()
                    .any(|o| o.name == *c)
                    .then(|| usd_name(c))
            } else if let Some(geom) = &a.geom {
                let mut paths: Vec<String> = super::document::split_array(geom)
                    .into_iter()
                    .map(|p| format!("{}{p}", a.geomprefix))
                    .collect();
                paths.sort();
                paths.dedup();
                let key = paths.join(",");
                match geom_sets.iter().find(|(k, _)| *k == key) {
                    Some((_, name)) => Some(name.clone()),
                    None => {
                        let mut name = format!("geom_{next}");
                        while out.iter().any(|c| c.name == name) {
                            next += 1;
                            name = format!("geom_{next}");
                        }
                        next += 1;
                        out.push(Coll {
                            name: name.clone(),
                            includes: paths.iter().filter_map(|p| rerooted(p)).collect(),
                            excludes: Vec::new(),
                        });
                        geom_sets.push((key, name.clone()));
                        Some(name)
                    }
                }
            } else {
                None
            };
            per_assign.push(bound);
        }
        per_look.push(per_assign);
    }
    (out, per_look)
}

fn line(out: &mut String, depth: usize, text: &str) {
    for _ in 0..depth {
        out.push_str("    ");
    }
    out.push_str(text);
    out.push('\n');
}

fn targets(list: &[String]) -> String {
    let items: Vec<String> = list.iter().map(|t| format!("<{t}>")).collect();
    format!("[{}]", items.join(", "))
}

/// The looks in the order usdMtlx creates them: each look after the looks it inherits from.
fn look_order(doc: &Document) -> Vec<usize> {
    let mut order = Vec::new();
    for k in 0..doc.looks.len() {
        let mut stack = vec![k];
        let mut cur = k;
        while let Some(parent) = doc.looks[cur].inherit.as_deref() {
            match doc.looks.iter().position(|l| l.name == parent) {
                Some(p) if !stack.contains(&p) => {
                    stack.push(p);
                    cur = p;
                }
                _ => break,
            }
        }
        for &l in stack.iter().rev() {
            if !order.contains(&l) {
                order.push(l);
            }
        }
    }
    order
}

/// Writes `/MaterialX/Collections` and `/MaterialX/Looks` (at depth 1, inside
/// `def "MaterialX"`); nothing when the document has no looks.
pub(super) fn write_looks(out: &mut String, doc: &Document, materials: &[&Node]) {
    if doc.looks.is_empty() {
        return;
    }
    let (colls, per_look) = collections(doc);
    if !colls.is_empty() {
        out.push('\n');
        let schemas: Vec<String> = colls
            .iter()
            .map(|c| format!("\"CollectionAPI:{}\"", c.name))
            .collect();
        line(out, 1, "def \"Collections\" (");
        line(
            out,
            2,
            &format!("prepend apiSchemas = [{}]", schemas.join(", ")),
        );
        line(out, 1, ")");
        line(out, 1, "{");
        for c in &colls {
            line(
                out,
                2,
                &format!(
                    "rel collection:{}:includes = {}",
                    c.name,
                    targets(&c.includes)
                ),
            );
            if !c.excludes.is_empty() {
                line(
                    out,
                    2,
                    &format!(
                        "rel collection:{}:excludes = {}",
                        c.name,
                        targets(&c.excludes)
                    ),
                );
            }
        }
        line(out, 1, "}");
    }
    out.push('\n');
    line(out, 1, "def \"Looks\"");
    line(out, 1, "{");
    for (n, &k) in look_order(doc).iter().enumerate() {
        if n > 0 {
            out.push('\n');
        }
        write_look(
            out,
            doc,
            &doc.looks[k],
            &per_look[k],
            !colls.is_empty(),
            materials,
        );
    }
    line(out, 1, "}");
}

fn write_look(
    out: &mut String,
    doc: &Document,
    look: &Look,
    bound: &[Option<String>],
    has_collections: bool,
    materials: &[&Node],
) {
    let name = usd_name(&look.name);
    let path = format!("{LOOKS}/{name}");
    let mut refs = Vec::new();
    if let Some(parent) = &look.inherit
        && doc.looks.iter().any(|l| l.name == *parent)
    {
        refs.push(format!("{LOOKS}/{}", usd_name(parent)));
    }
    if has_collections {
        refs.push(COLLECTIONS.to_string());
    }
    line(out, 2, &format!("def \"{name}\" ("));
    line(out, 3, "prepend apiSchemas = [\"MaterialBindingAPI\"]");
    if !refs.is_empty() {
        line(out, 3, &format!("prepend references = {}", targets(&refs)));
    }
    line(out, 2, ")");
    line(out, 2, "{");
    // Each assign of a known material: a unique Material prim name and its binding.
    let mut used: Vec<String> = Vec::new();
    let mut bindings: Vec<(String, String)> = Vec::new();
    let mut prims: Vec<(String, String)> = Vec::new();
    for (a, coll) in look.assigns.iter().zip(bound) {
        if !materials.iter().any(|m| m.name == a.material) {
            continue;
        }
        let base = usd_name(&a.name);
        let mut prim = base.clone();
        let mut k = 1;
        while used.contains(&prim) {
            prim = format!("{base}_{k}");
            k += 1;
        }
        used.push(prim.clone());
        let mat_path = format!("{path}/Materials/{prim}");
        let (rel, value) = match coll {
            Some(c) => (
                format!("material:binding:collection:{prim}"),
                targets(&[format!("{path}.collection:{c}"), mat_path]),
            ),
            None => ("material:binding".to_string(), format!("<{mat_path}>")),
        };
        if !bindings.iter().any(|(r, _)| *r == rel) {
            bindings.push((rel, value));
        }
        prims.push((
            prim,
            format!("/MaterialX/Materials/{}", usd_name(&a.material)),
        ));
    }
    // The look's own bindings first, in assign order, then the inherited look's (usdMtlx's
    // property order).
    let mut names: Vec<String> = bindings.iter().map(|(r, _)| r.clone()).collect();
    let mut parent = look.inherit.as_deref();
    let mut seen = vec![look.name.as_str()];
    while let Some(p) = parent.and_then(|p| doc.looks.iter().find(|l| l.name == p)) {
        if seen.contains(&p.name.as_str()) {
            break;
        }
        seen.push(&p.name);
        for a in &p.assigns {
            let rel = format!("material:binding:collection:{}", usd_name(&a.name));
            if !names.contains(&rel) {
                names.push(rel);
            }
        }
        parent = p.inherit.as_deref();
    }
    if !bindings.is_empty() {
        let order: Vec<String> = names.iter().map(|r| format!("\"{r}\"")).collect();
        line(
            out,
            3,
            &format!("reorder properties = [{}]", order.join(", ")),
        );
    }
    for (rel, value) in &bindings {
        line(out, 3, &format!("rel {rel} = {value}"));
    }
    out.push('\n');
    line(out, 3, "def \"Materials\"");
    line(out, 3, "{");
    for (k, (prim, target)) in prims.iter().enumerate() {
        if k > 0 {
            out.push('\n');
        }
        line(out, 4, &format!("def Material \"{prim}\" ("));
        line(out, 5, &format!("prepend references = <{target}>"));
        line(out, 4, ")");
        line(out, 4, "{");
        line(out, 4, "}");
    }
    line(out, 3, "}");
    line(out, 2, "}");
}

/// Writes `/ModelRoot` with its `LookVariant` variant set (at depth 0, after
/// `def "MaterialX"`); nothing when the document has no looks.
pub(super) fn write_model_root(out: &mut String, doc: &Document) {
    let order = look_order(doc);
    let Some(&last) = order.last() else {
        return;
    };
    out.push('\n');
    line(out, 0, "def \"ModelRoot\" (");
    line(out, 1, "variants = {");
    line(
        out,
        2,
        &format!(
            "string LookVariant = \"{}\"",
            usd_name(&doc.looks[last].name)
        ),
    );
    line(out, 1, "}");
    line(out, 1, "prepend variantSets = \"LookVariant\"");
    line(out, 0, ")");
    line(out, 0, "{");
    line(out, 1, "variantSet \"LookVariant\" = {");
    for &k in &order {
        let name = usd_name(&doc.looks[k].name);
        line(out, 2, &format!("\"{name}\" ("));
        line(out, 3, &format!("prepend references = <{LOOKS}/{name}>"));
        line(out, 2, ") {");
        line(out, 2, "}");
    }
    line(out, 1, "}");
    line(out, 0, "}");
}
