//! Material binding resolution: which Material a gprim is drawn with, as usd-core's
//! `UsdShadeMaterialBindingAPI::ComputeBoundMaterial` decides it for the `full` purpose
//! (UsdShade "Material Resolution"):
//!
//! - the `full`-purpose bindings (`material:binding:full`,
//!   `material:binding:collection:full:<name>`) are resolved first over the whole ancestry;
//!   only when none applies, the all-purpose ones (`material:binding`,
//!   `material:binding:collection:<name>`); other purposes (`preview`) are not lux's;
//! - walking from the gprim up to the root, the first binding that applies wins, unless a
//!   binding further up is authored `bindMaterialAs = "strongerThanDescendants"`, which then
//!   replaces it;
//! - on one prim the collection bindings come before the direct binding, in property order
//!   (names in dictionary order, an authored `reorder properties` listing its names first); a collection
//!   binding applies when the gprim is a member of its collection
//!   ([`Membership::contains`]), and only the first such one on a prim is considered.
//!
//! MaterialX looks reach lux this way: usdMtlx turns each `<materialassign>` into a collection
//! binding on the look's prim ([`crate::mtlx::usdmtlx`]).

use std::cmp::Ordering;
use std::sync::Arc;

use openusd::usd::Prim;

use crate::error::{LoadError, WarningKind};
use crate::linking::{Membership, Target, collection_membership, raw_targets, target_kind};
use crate::reader::Reader;

/// One binding relationship authored on a prim.
#[derive(Clone, Debug)]
struct Binding {
    /// The bound Material's path.
    material: String,
    /// `bindMaterialAs = "strongerThanDescendants"`.
    stronger: bool,
    /// The collection's membership for a collection binding; `None` for a direct binding.
    members: Option<Membership>,
}

/// The bindings authored on one prim, per purpose, in resolution order: the collection
/// bindings in property order, then the direct binding.
#[derive(Clone, Debug, Default)]
pub struct Site {
    full: Vec<Binding>,
    all: Vec<Binding>,
}

impl Site {
    fn is_empty(&self) -> bool {
        self.full.is_empty() && self.all.is_empty()
    }
}

/// The binding sites from a prim up to the root (only prims that author a binding appear).
#[derive(Debug)]
pub struct Chain {
    site: Site,
    parent: Option<Arc<Chain>>,
}

impl Chain {
    /// `parent` extended by the bindings authored on `prim` (the same chain when it authors
    /// none).
    pub(crate) fn extend(
        r: &mut Reader<'_>,
        prim: &Prim,
        parent: Option<&Arc<Chain>>,
    ) -> Result<Option<Arc<Chain>>, LoadError> {
        let site = read_site(r, prim)?;
        Ok(if site.is_empty() {
            parent.cloned()
        } else {
            Some(Arc::new(Chain {
                site,
                parent: parent.cloned(),
            }))
        })
    }
}

/// The Material bound to the prim at `path` given the binding sites on it and its ancestors
/// (`chain`, nearest first): usd-core's `ComputeBoundMaterial(prim, "full")`.
pub fn resolve(chain: Option<&Arc<Chain>>, path: &str) -> Option<String> {
    for full in [true, false] {
        let mut bound: Option<&Binding> = None;
        let mut c = chain;
        while let Some(node) = c {
            let list = if full {
                &node.site.full
            } else {
                &node.site.all
            };
            let by_collection = list
                .iter()
                .find(|b| b.members.as_ref().is_some_and(|m| m.contains(path)));
            let direct = list.iter().find(|b| b.members.is_none());
            for b in by_collection.into_iter().chain(direct) {
                if bound.is_none() || b.stronger {
                    bound = Some(b);
                }
            }
            c = node.parent.as_ref();
        }
        if let Some(b) = bound {
            return Some(b.material.clone());
        }
    }
    None
}

/// A binding relationship's name parsed: `(full purpose?, collection binding?)`; `None` for
/// another purpose or something that is not a binding.
fn parse_name(name: &str) -> Option<(bool, bool)> {
    let rest = name.strip_prefix("material:binding")?;
    match rest {
        "" => Some((false, false)),
        ":full" => Some((true, false)),
        _ => {
            let tail = rest.strip_prefix(":collection:")?;
            match tail.split_once(':') {
                None => Some((false, true)),
                Some(("full", _)) => Some((true, true)),
                Some(_) => None,
            }
        }
    }
}

/// Reads the bindings authored on `prim` (see the module docs); anything that cannot be
/// honoured is a warning naming the prim and the relationship.
fn read_site(r: &mut Reader<'_>, prim: &Prim) -> Result<Site, LoadError> {
    let names: Vec<String> = prim
        .property_names()
        .map_err(|e| r.usd_error(prim, e))?
        .iter()
        .map(|t| t.as_str().to_owned())
        .filter(|n| n.starts_with("material:binding"))
        .collect();
    let mut site = Site::default();
    if names.is_empty() {
        return Ok(site);
    }
    let names = property_order(r, prim, names);
    let mut direct: [Option<Binding>; 2] = [None, None];
    for name in names {
        let Some((full, collection)) = parse_name(&name) else {
            continue;
        };
        let stronger = match r.metadata_text(prim, &name, "bindMaterialAs").as_deref() {
            None | Some("weakerThanDescendants" | "fallbackStrength") => false,
            Some("strongerThanDescendants") => true,
            Some(other) => {
                r.warn(
                    prim,
                    WarningKind::InvalidValue,
                    format!(
                        "{name}: bindMaterialAs {other:?} is not weakerThanDescendants or \
                         strongerThanDescendants; read as weakerThanDescendants"
                    ),
                );
                false
            }
        };
        let list = if full { &mut site.full } else { &mut site.all };
        if !collection {
            if let Some(material) = r.targets(prim, &name)?.into_iter().next() {
                direct[usize::from(full)] = Some(Binding {
                    material,
                    stronger,
                    members: None,
                });
            }
            continue;
        }
        let targets = raw_targets(r, prim, &name)?;
        let mut coll = None;
        let mut material = None;
        for t in &targets {
            match target_kind(t) {
                Target::Collection(p, n) if coll.is_none() => coll = Some((p, n)),
                Target::Prim(p) if material.is_none() => material = Some(p),
                _ => {}
            }
        }
        let (Some((owner, cname)), Some(material), 2) = (coll, material, targets.len()) else {
            r.warn(
                prim,
                WarningKind::InvalidValue,
                format!(
                    "{name}: a collection binding needs two targets, a collection \
                     (</P.collection:name>) and a Material; found {targets:?}; ignored"
                ),
            );
            continue;
        };
        if let Some(members) = collection_membership(r, prim, &owner, &cname)? {
            list.push(Binding {
                material,
                stronger,
                members: Some(members),
            });
        }
    }
    let [all, full] = direct;
    site.all.extend(all);
    site.full.extend(full);
    Ok(site)
}

/// `names` in the prim's property order, as usd-core's `GetPropertyNames` gives it: dictionary
/// order (usd-core's `TfDictionaryLessThan`: letters compared without case, digit runs as
/// numbers), then, with an authored `propertyOrder` (`reorder properties = [...]`, the
/// strongest opinion), the names it lists first in its order and the others after them in
/// dictionary order (checked against usd-core 26.11: `[c, a]` over `a…e` gives
/// `c, a, b, d, e`).
fn property_order(r: &Reader<'_>, prim: &Prim, mut names: Vec<String>) -> Vec<String> {
    names.sort_by(|a, b| dictionary_cmp(a, b));
    let Some(order) = authored_order(r, prim) else {
        return names;
    };
    let mut out: Vec<String> = Vec::with_capacity(names.len());
    for o in &order {
        if let Some(i) = names.iter().position(|n| n == o) {
            out.push(names.remove(i));
        }
    }
    out.extend(names);
    out
}

/// The strongest `propertyOrder` authored on `prim`'s specs.
fn authored_order(r: &Reader<'_>, prim: &Prim) -> Option<Vec<String>> {
    let stack = prim.prim_stack().ok()?;
    for (layer, spec_path) in &stack {
        let Some(l) = r.stage.layer(layer) else {
            continue;
        };
        let Some(spec) = l.prim(spec_path.clone()) else {
            continue;
        };
        match spec.field("propertyOrder") {
            Ok(Some(openusd::sdf::Value::TokenVec(v))) => {
                return Some(v.iter().map(|t| t.as_str().to_owned()).collect());
            }
            Ok(Some(openusd::sdf::Value::StringVec(v))) => return Some(v),
            _ => {}
        }
    }
    None
}

/// usd-core's `TfDictionaryLessThan`: case-insensitive, digit runs compared as numbers; ties
/// broken by the plain byte order.
fn dictionary_cmp(a: &str, b: &str) -> Ordering {
    let (ab, bb) = (a.as_bytes(), b.as_bytes());
    let (mut i, mut j) = (0, 0);
    while i < ab.len() && j < bb.len() {
        if ab[i].is_ascii_digit() && bb[j].is_ascii_digit() {
            let si = i;
            while i < ab.len() && ab[i].is_ascii_digit() {
                i += 1;
            }
            let sj = j;
            while j < bb.len() && bb[j].is_ascii_digit() {
                j += 1;
            }
            let x = a[si..i].trim_start_matches('0');
            let y = b[sj..j].trim_start_matches('0');
            let o = x.len().cmp(&y.len()).then_with(|| x.cmp(y));
            if o != Ordering::Equal {
                return o;
            }
        } else {
            let o = ab[i].to_ascii_lowercase().cmp(&bb[j].to_ascii_lowercase());
            if o != Ordering::Equal {
                return o;
            }
            i += 1;
            j += 1;
        }
    }
    (ab.len() - i).cmp(&(bb.len() - j)).then_with(|| a.cmp(b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_by_purpose() {
        assert_eq!(parse_name("material:binding"), Some((false, false)));
        assert_eq!(parse_name("material:binding:full"), Some((true, false)));
        assert_eq!(parse_name("material:binding:preview"), None);
        assert_eq!(
            parse_name("material:binding:collection:a"),
            Some((false, true))
        );
        assert_eq!(
            parse_name("material:binding:collection:full:a"),
            Some((true, true))
        );
        assert_eq!(parse_name("material:binding:collection:preview:a"), None);
        assert_eq!(parse_name("material:bindingX"), None);
    }

    #[test]
    fn dictionary_order_compares_digit_runs_as_numbers() {
        let mut v = vec!["c10", "C2", "c1", "b", "c02x"];
        v.sort_by(|a, b| dictionary_cmp(a, b));
        assert_eq!(v, ["b", "c1", "C2", "c02x", "c10"]);
    }
}
