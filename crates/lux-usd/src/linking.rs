//! Light and shadow linking: UsdLux `LightAPI`'s `collection:lightLink` and
//! `collection:shadowLink` (two `UsdCollectionAPI` instances) resolved, at load, into plain
//! path rules a renderer asks "is this prim in the collection?".
//!
//! A collection in *relationship-mode* is flattened as usd-core's
//! `UsdCollectionAPI::ComputeMembershipQuery` flattens it into its path-expansion-rule map:
//! the `includes` targets in order (a target that is another collection, `</P.collection:n>`,
//! inserts that collection's rules, recursively; a collection met again while it is being
//! flattened is skipped with a warning, as usd-core skips a cycle), later entries for the same
//! path replacing earlier ones; then `</>` when `includeRoot` is true (ignored with
//! `explicitOnly`); then every `excludes` target as an exclusion, which beats any include of
//! the same path. A prim is then a member when its own path is an include (of any expansion
//! rule), or else when the nearest ancestor entry that is not `explicitOnly` is an include
//! ([`Membership::contains`], usd-core's `UsdCollectionMembershipQuery::IsPathIncluded`).
//!
//! *Expression-mode* (`membershipExpression`, pattern-based collections) is not evaluated: a
//! light whose collection uses one is linked to everything, with a warning.

use crate::error::{LoadError, WarningKind};
use crate::light::kind_of_type;
use crate::reader::{Reader, is_prim_path, is_property_name};
use openusd::usd::Prim;
use std::collections::BTreeMap;

/// How a path of a collection's rules brings in prims (UsdCollectionAPI
/// `collection:<name>:expansionRule`, or [`Rule::Exclude`] for an `excludes` target).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Rule {
    /// `expandPrims` (the schema default): the path and every prim below it.
    ExpandPrims,
    /// `expandPrimsAndProperties`: as `expandPrims` for prims (properties are not geometry).
    ExpandPrimsAndProperties,
    /// `explicitOnly`: the path itself, not its descendants.
    ExplicitOnly,
    /// An `excludes` target: the path and every prim below it are out (until a more specific
    /// include).
    Exclude,
}

impl Rule {
    /// The schema token (`exclude` is usd-core's token for excluded paths).
    pub fn token(self) -> &'static str {
        match self {
            Rule::ExpandPrims => "expandPrims",
            Rule::ExpandPrimsAndProperties => "expandPrimsAndProperties",
            Rule::ExplicitOnly => "explicitOnly",
            Rule::Exclude => "exclude",
        }
    }

    /// The expansion rule of a `collection:<name>:expansionRule` token; `None` for anything
    /// else.
    pub fn parse_expansion(token: &str) -> Option<Rule> {
        Some(match token {
            "expandPrims" => Rule::ExpandPrims,
            "expandPrimsAndProperties" => Rule::ExpandPrimsAndProperties,
            "explicitOnly" => Rule::ExplicitOnly,
            _ => return None,
        })
    }
}

/// Which prims a linking collection holds (UsdCollectionAPI membership of
/// `collection:lightLink` / `collection:shadowLink`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Membership {
    /// Every prim: `includeRoot` (LightAPI's fallback true) with `expandPrims` or
    /// `expandPrimsAndProperties` and nothing else authored — the default, and what an
    /// unsupported `membershipExpression` reads as.
    #[default]
    All,
    /// The flattened path → rule map (usd-core's `GetAsPathExpansionRuleMap`), absolute prim
    /// paths (`/` for `includeRoot`); an empty map holds nothing.
    Rules(BTreeMap<String, Rule>),
}

impl Membership {
    /// True for [`Membership::All`], the default that needs no test per prim.
    pub fn is_all(&self) -> bool {
        matches!(self, Membership::All)
    }

    /// Whether the prim at `path` is a member (UsdCollectionAPI `IsPathIncluded`): its own
    /// entry decides if it has one (any include rule: in; `exclude`: out); else the nearest
    /// ancestor entry that is not `explicitOnly` (an include: in; `exclude`: out); else out.
    pub fn contains(&self, path: &str) -> bool {
        let Membership::Rules(map) = self else {
            return true;
        };
        if let Some(r) = map.get(path) {
            return *r != Rule::Exclude;
        }
        let mut p = path;
        while let Some(parent) = parent_path(p) {
            p = parent;
            match map.get(p) {
                None | Some(Rule::ExplicitOnly) => {}
                Some(Rule::Exclude) => return false,
                Some(_) => return true,
            }
        }
        false
    }

    /// This membership with every rule path under `from` (itself included) moved under `to`
    /// (a light of an instancing prototype placed at an instance: its collection's paths
    /// inside the prototype follow it).
    pub fn reparented(&self, from: &str, to: &str) -> Membership {
        match self {
            Membership::All => Membership::All,
            Membership::Rules(map) => Membership::Rules(
                map.iter()
                    .map(|(p, r)| {
                        let moved = match p.strip_prefix(from) {
                            Some(rest) if rest.is_empty() || rest.starts_with('/') => {
                                format!("{to}{rest}")
                            }
                            _ => p.clone(),
                        };
                        (moved, *r)
                    })
                    .collect(),
            ),
        }
    }

    /// One line for `lux info`: `all`, `nothing`, or the includes and excludes, e.g.
    /// `includes /World/A, excludes /World/A/m1 (expandPrims)`; the rule in parentheses is
    /// the includes' (each include names its own when they differ).
    pub fn describe(&self) -> String {
        let Membership::Rules(map) = self else {
            return "all".to_owned();
        };
        let includes: Vec<(&String, Rule)> = map
            .iter()
            .filter(|(_, r)| **r != Rule::Exclude)
            .map(|(p, r)| (p, *r))
            .collect();
        let excludes: Vec<&String> = map
            .iter()
            .filter(|(_, r)| **r == Rule::Exclude)
            .map(|(p, _)| p)
            .collect();
        if includes.is_empty() {
            return "nothing".to_owned();
        }
        let same = includes.iter().all(|(_, r)| *r == includes[0].1);
        let inc: Vec<String> = includes
            .iter()
            .map(|(p, r)| {
                if same {
                    (*p).clone()
                } else {
                    format!("{p} ({})", r.token())
                }
            })
            .collect();
        let mut s = format!("includes {}", inc.join(", "));
        if !excludes.is_empty() {
            let exc: Vec<&str> = excludes.iter().map(|p| p.as_str()).collect();
            s.push_str(&format!(", excludes {}", exc.join(", ")));
        }
        if same {
            s.push_str(&format!(" ({})", includes[0].1.token()));
        }
        s
    }
}

/// A light's links (UsdLux `LightAPI`): which geometry it illuminates and which geometry
/// casts its shadows.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Linking {
    /// `collection:lightLink`: the geometry the light illuminates (others receive nothing
    /// from it).
    pub light: Membership,
    /// `collection:shadowLink`: the geometry that casts the light's shadows (others let its
    /// light through).
    pub shadow: Membership,
}

impl Linking {
    /// True when both collections hold everything (the default).
    pub fn is_all(&self) -> bool {
        self.light.is_all() && self.shadow.is_all()
    }
}

/// The parent of an absolute prim path (`/A/B` → `/A` → `/` → `None`).
fn parent_path(p: &str) -> Option<&str> {
    if p == "/" || p.is_empty() {
        return None;
    }
    match p.rfind('/') {
        Some(0) => Some("/"),
        Some(i) => Some(&p[..i]),
        None => None,
    }
}

/// A collection being flattened, or none (a collection's own result).
enum Flat {
    /// Relationship-mode rules (possibly empty).
    Rules(BTreeMap<String, Rule>),
    /// Expression-mode with a `membershipExpression`: not evaluated.
    Expression,
}

/// Reads both linking collections of the light `prim`. Anything lux cannot honour is a
/// warning naming the light and what it expected.
pub fn read_linking(r: &mut Reader<'_>, prim: &Prim) -> Result<Linking, LoadError> {
    let mut one = |name: &str| -> Result<Membership, LoadError> {
        let path = prim.path().to_string();
        let mut stack = Vec::new();
        Ok(match flatten(r, prim, prim, &path, name, &mut stack)? {
            Flat::Expression => {
                r.warn(
                    prim,
                    WarningKind::Unsupported,
                    format!(
                        "collection:{name}:membershipExpression (an expression-mode collection) \
                         is not supported: the light's {name} includes every prim"
                    ),
                );
                Membership::All
            }
            Flat::Rules(map) => {
                let all = map.len() == 1
                    && matches!(
                        map.get("/"),
                        Some(Rule::ExpandPrims | Rule::ExpandPrimsAndProperties)
                    );
                if all {
                    Membership::All
                } else {
                    Membership::Rules(map)
                }
            }
        })
    };
    let light = one("lightLink")?;
    let shadow = one("shadowLink")?;
    Ok(Linking { light, shadow })
}

/// The membership of `collection:<name>` on the prim at `owner_path` (any UsdCollectionAPI
/// instance, e.g. one a `material:binding:collection:*` relationship names), flattened as
/// [`read_linking`] flattens a light's; warnings name `user` (the prim whose property named
/// the collection). `None` for an expression-mode collection (not evaluated; warned) or a
/// missing owner prim (warned).
pub(crate) fn collection_membership(
    r: &mut Reader<'_>,
    user: &Prim,
    owner_path: &str,
    name: &str,
) -> Result<Option<Membership>, LoadError> {
    let owner = r.stage.prim(owner_path);
    if !owner.is_valid().map_err(|e| r.usd_error(user, e))? {
        r.warn(
            user,
            WarningKind::InvalidValue,
            format!("<{owner_path}.collection:{name}>: no prim <{owner_path}>; ignored"),
        );
        return Ok(None);
    }
    let mut stack = Vec::new();
    Ok(
        match flatten(r, user, &owner, owner_path, name, &mut stack)? {
            Flat::Rules(map) => Some(Membership::Rules(map)),
            Flat::Expression => {
                r.warn(
                    user,
                    WarningKind::Unsupported,
                    format!(
                        "<{owner_path}.collection:{name}> is an expression-mode collection \
                     (membershipExpression), which is not supported: it holds nothing here"
                    ),
                );
                None
            }
        },
    )
}

/// Whether `prim` carries UsdLux `LightAPI` (a concrete light type or an applied light API):
/// its `lightLink`/`shadowLink` collections have `includeRoot` fallback true.
fn is_light(r: &Reader<'_>, prim: &Prim) -> Result<bool, LoadError> {
    let type_name = prim
        .type_name()
        .map_err(|e| r.usd_error(prim, e))?
        .map(|t| t.as_str().to_owned())
        .unwrap_or_default();
    if kind_of_type(&type_name).is_some() || matches!(type_name.as_str(), "PluginLight") {
        return Ok(true);
    }
    let api = prim.api_schemas().map_err(|e| r.usd_error(prim, e))?;
    Ok(api.iter().any(|a| {
        matches!(
            a.as_str(),
            "LightAPI" | "MeshLightAPI" | "VolumeLightAPI" | "GeometryLightAPI"
        )
    }))
}

/// A relationship target split into its prim path and, for `</P.collection:n>`, the
/// collection name.
pub(crate) enum Target {
    Prim(String),
    Collection(String, String),
    Other(String),
}

pub(crate) fn target_kind(t: &str) -> Target {
    match t.split_once('.') {
        None if is_prim_path(t) => Target::Prim(t.to_owned()),
        Some((p, prop)) if is_prim_path(p) => match prop.strip_prefix("collection:") {
            Some(n) if is_property_name(n) && !n.contains(':') => {
                Target::Collection(p.to_owned(), n.to_owned())
            }
            _ => Target::Other(t.to_owned()),
        },
        _ => Target::Other(t.to_owned()),
    }
}

/// Raw targets of a relationship (collection paths included), as strings.
pub(crate) fn raw_targets(
    r: &Reader<'_>,
    prim: &Prim,
    name: &str,
) -> Result<Vec<String>, LoadError> {
    if !is_property_name(name) {
        return Ok(Vec::new());
    }
    prim.relationship(name)
        .targets()
        .map(|t| t.iter().map(|p| p.to_string()).collect())
        .map_err(|e| r.usd_error(prim, format_args!("relationship {name}: {e:#}")))
}

/// Flattens `collection:<name>` of `owner` (at `owner_path`) into its rule map; warnings go
/// to `light`. `stack` holds the collections being flattened (cycle guard).
fn flatten(
    r: &mut Reader<'_>,
    light: &Prim,
    owner: &Prim,
    owner_path: &str,
    name: &str,
    stack: &mut Vec<String>,
) -> Result<Flat, LoadError> {
    let id = format!("{owner_path}.collection:{name}");
    stack.push(id);
    let base = format!("collection:{name}");
    let fallback_root = matches!(name, "lightLink" | "shadowLink") && is_light(r, owner)? || {
        // LightFilter's filterLink has includeRoot fallback true as well.
        name == "filterLink"
            && owner
                .type_name()
                .map_err(|e| r.usd_error(owner, e))?
                .is_some_and(|t| t.as_str() == "LightFilter")
    };
    let include_root = r
        .bool(owner, &format!("{base}:includeRoot"))?
        .unwrap_or(fallback_root);
    let expansion = match r.text(owner, &format!("{base}:expansionRule"))? {
        None => Rule::ExpandPrims,
        Some(t) => Rule::parse_expansion(&t).unwrap_or_else(|| {
            r.warn(
                light,
                WarningKind::InvalidValue,
                format!(
                    "{owner_path}.{base}:expansionRule {t:?} is not expandPrims, \
                     expandPrimsAndProperties or explicitOnly; using expandPrims"
                ),
            );
            Rule::ExpandPrims
        }),
    };
    let includes = raw_targets(r, owner, &format!("{base}:includes"))?;
    let excludes = raw_targets(r, owner, &format!("{base}:excludes"))?;
    let expression = r
        .raw_default(owner, &format!("{base}:membershipExpression"))?
        .is_some();
    let mode = r.text(owner, &format!("{base}:mode"))?;
    let relationship_mode = match mode.as_deref() {
        Some("relationship") => true,
        Some("expression") => false,
        None | Some("automatic") => !includes.is_empty() || !excludes.is_empty() || include_root,
        Some(other) => {
            r.warn(
                light,
                WarningKind::InvalidValue,
                format!(
                    "{owner_path}.{base}:mode {other:?} is not automatic, relationship or \
                     expression; using automatic"
                ),
            );
            !includes.is_empty() || !excludes.is_empty() || include_root
        }
    };
    if !relationship_mode {
        stack.pop();
        // An expression-mode collection without an expression holds nothing (usd-core).
        return Ok(if expression {
            Flat::Expression
        } else {
            Flat::Rules(BTreeMap::new())
        });
    }
    let mut map = BTreeMap::new();
    for t in includes {
        match target_kind(&t) {
            Target::Prim(p) => {
                map.insert(p, expansion);
            }
            Target::Collection(p, n) => {
                let key = format!("{p}.collection:{n}");
                if stack.contains(&key) {
                    r.warn(
                        light,
                        WarningKind::InvalidValue,
                        format!(
                            "{owner_path}.{base}:includes <{key}> includes a collection that \
                             includes it (a cycle): skipped, as usd-core does"
                        ),
                    );
                    continue;
                }
                let other = r.stage.prim(p.as_str());
                let valid = other.is_valid().map_err(|e| r.usd_error(light, e))?;
                if !valid {
                    r.warn(
                        light,
                        WarningKind::InvalidValue,
                        format!(
                            "{owner_path}.{base}:includes <{key}>: no prim <{p}>; the included \
                             collection is skipped"
                        ),
                    );
                    continue;
                }
                match flatten(r, light, &other, &p, &n, stack)? {
                    Flat::Rules(m) => map.extend(m),
                    Flat::Expression => r.warn(
                        light,
                        WarningKind::Unsupported,
                        format!(
                            "{owner_path}.{base}:includes <{key}>, an expression-mode collection \
                             (membershipExpression), which is not supported: it adds nothing"
                        ),
                    ),
                }
            }
            Target::Other(o) => r.warn(
                light,
                WarningKind::Ignored,
                format!(
                    "{owner_path}.{base}:includes <{o}> is neither a prim nor a collection \
                     (a property is not geometry); ignored"
                ),
            ),
        }
    }
    if include_root && expansion != Rule::ExplicitOnly {
        map.insert("/".to_owned(), expansion);
    }
    for t in excludes {
        match target_kind(&t) {
            Target::Prim(p) => {
                map.insert(p, Rule::Exclude);
            }
            Target::Collection(..) | Target::Other(_) => r.warn(
                light,
                WarningKind::Ignored,
                format!(
                    "{owner_path}.{base}:excludes <{t}> is not a prim (excludes cannot target \
                     a collection or a property); ignored"
                ),
            ),
        }
    }
    stack.pop();
    Ok(Flat::Rules(map))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rules(entries: &[(&str, Rule)]) -> Membership {
        Membership::Rules(entries.iter().map(|(p, r)| ((*p).to_owned(), *r)).collect())
    }

    #[test]
    fn membership_follows_the_most_specific_entry() {
        use Rule::*;
        let m = rules(&[
            ("/W", ExpandPrims),
            ("/W/A", Exclude),
            ("/W/A/m1", ExpandPrims),
        ]);
        assert!(m.contains("/W"));
        assert!(m.contains("/W/B/m3"));
        assert!(!m.contains("/W/A"));
        assert!(!m.contains("/W/A/m2"));
        assert!(m.contains("/W/A/m1"));
        assert!(m.contains("/W/A/m1/child"));
        assert!(!m.contains("/X"));
        // explicitOnly: the path itself; its descendants ask the next ancestor entry.
        let e = rules(&[("/", ExpandPrims), ("/W/A", ExplicitOnly)]);
        assert!(e.contains("/W/A") && e.contains("/W/A/m1"));
        let e = rules(&[("/W/A", ExplicitOnly)]);
        assert!(e.contains("/W/A") && !e.contains("/W/A/m1") && !e.contains("/W"));
        assert!(!rules(&[]).contains("/W"));
        assert!(Membership::All.contains("/anything"));
        // A prefix that is not an ancestor does not count.
        assert!(!rules(&[("/W/A", ExpandPrims)]).contains("/W/AB"));
    }

    #[test]
    fn describe_and_reparent() {
        use Rule::*;
        let m = rules(&[("/World/A", ExpandPrims), ("/World/A/m1", Exclude)]);
        assert_eq!(
            m.describe(),
            "includes /World/A, excludes /World/A/m1 (expandPrims)"
        );
        assert_eq!(Membership::All.describe(), "all");
        assert_eq!(rules(&[]).describe(), "nothing");
        assert_eq!(
            rules(&[("/a", ExplicitOnly), ("/b", ExpandPrims)]).describe(),
            "includes /a (explicitOnly), /b (expandPrims)"
        );
        let moved = m.reparented("/World/A", "/World/I2");
        assert_eq!(
            moved,
            rules(&[("/World/I2", ExpandPrims), ("/World/I2/m1", Exclude)])
        );
        assert_eq!(parent_path("/a"), Some("/"));
        assert_eq!(parent_path("/"), None);
    }
}
