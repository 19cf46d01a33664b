//! The embedded MaterialX library (MaterialX Specification, "Custom Node Declaration NodeDef
//! Elements", "Custom Node Definition Using Node Graphs"): `stdlib_defs.mtlx`,
//! `pbrlib_defs.mtlx`, `standard_surface.mtlx`, `open_pbr_surface.mtlx` and
//! `usd_preview_surface.mtlx` from MaterialX 1.39 (`data/materialx/`, Apache-2.0), parsed once.

use std::collections::HashMap;
use std::path::Path;
use std::sync::OnceLock;

use super::MtlxError;
use super::document::{Ctx, NodeGraph, parse_document};
use super::parse_value;
use crate::shading::{Value, ValueType};

/// An input of a nodedef (MaterialX Specification, "NodeDef Input Elements").
#[derive(Clone, Debug, PartialEq)]
pub struct DefInput {
    /// `name`.
    pub name: String,
    /// `type`.
    pub ty: ValueType,
    /// `value`: the default (`None` when the nodedef states none, or for closures).
    pub default: Option<Value>,
    /// `defaultgeomprop`: the geometric property an unconnected input reads (`UV0`,
    /// `Nworld`, …).
    pub defaultgeomprop: Option<String>,
    /// `uniform="true"`.
    pub uniform: bool,
}

/// What a nodedef's output gives where its node is not evaluated.
#[derive(Clone, Debug, PartialEq)]
pub enum OutputFallback {
    /// `default="…"`: a constant of the output's type.
    Value(Value),
    /// `defaultinput="…"`: the value of that input (a pass-through).
    Input(String),
    /// `default="Nworld"`: a geometric property by its `geompropdef` name (`ND_flake2d`'s
    /// `flakenormal` falls back to the surface normal).
    Geomprop(String),
}

/// A `<nodedef>` (MaterialX Specification, "Custom Node Declaration NodeDef Elements"), with
/// the inputs of the nodedef it `inherit`s merged in (its own first, as MaterialX lists them).
#[derive(Clone, Debug, PartialEq)]
pub struct NodeDef {
    /// `name` (`ND_image_color3`).
    pub name: String,
    /// `node`: the category it defines (`image`).
    pub category: String,
    /// The inputs.
    pub inputs: Vec<DefInput>,
    /// The outputs: name and type.
    pub outputs: Vec<(String, ValueType)>,
    /// What outputs give where the node is not evaluated (an output's `default` or
    /// `defaultinput`, MaterialX Specification, "NodeDef Output Elements"): output name and
    /// fallback, for the outputs that state one.
    pub output_fallbacks: Vec<(String, OutputFallback)>,
    /// `version`.
    pub version: Option<String>,
    /// `isdefaultversion="true"`.
    pub default_version: bool,
    /// `inherit`: the nodedef this one extends.
    pub inherit: Option<String>,
}

impl NodeDef {
    /// The fallback of output `name`, if it states one.
    pub fn output_fallback(&self, name: &str) -> Option<&OutputFallback> {
        self.output_fallbacks
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, f)| f)
    }

    /// The input named `name`.
    pub fn input(&self, name: &str) -> Option<&DefInput> {
        self.inputs.iter().find(|i| i.name == name)
    }

    /// The index of the output named `name`; a single-output nodedef answers 0 for any name
    /// (MaterialX Specification, "Inputs": `output` is ignored for single-output nodes).
    pub fn output_index(&self, name: &str) -> Option<usize> {
        if self.outputs.len() == 1 {
            return Some(0);
        }
        self.outputs.iter().position(|(n, _)| n == name)
    }

    /// The output type of a single-output nodedef.
    pub fn ty(&self) -> Option<ValueType> {
        (self.outputs.len() == 1).then(|| self.outputs[0].1)
    }
}

/// A nodegraph of the library implementing a nodedef (its `nodedef` attribute, or an
/// `<implementation nodegraph="…">`).
pub type NodeGraphDef = NodeGraph;

pub(crate) fn parse_nodedef(ctx: &Ctx, e: roxmltree::Node) -> Result<NodeDef, MtlxError> {
    let name = ctx.name(e)?;
    let category = e
        .attribute("node")
        .ok_or_else(|| ctx.invalid(e, format!("nodedef \"{name}\""), "a `node` attribute"))?
        .to_string();
    let mut def = NodeDef {
        name,
        category,
        inputs: Vec::new(),
        outputs: Vec::new(),
        output_fallbacks: Vec::new(),
        version: e.attribute("version").map(str::to_string),
        default_version: e.attribute("isdefaultversion") == Some("true"),
        inherit: e.attribute("inherit").map(str::to_string),
    };
    for c in e.children().filter(|c| c.is_element()) {
        let kind = c.tag_name().name();
        if kind != "input" && kind != "output" {
            continue;
        }
        let iname = ctx.name(c)?;
        let Some(ty) = c.attribute("type").and_then(ValueType::parse) else {
            // A type lux does not model (`lightshader`): the nodedef keeps its other ports.
            continue;
        };
        if kind == "output" {
            if let Some(input) = c.attribute("defaultinput") {
                def.output_fallbacks
                    .push((iname.clone(), OutputFallback::Input(input.to_string())));
            } else if let Some(text) = c.attribute("default") {
                let fallback = match parse_value(ty, text) {
                    Some(v) => OutputFallback::Value(v),
                    None if text.chars().all(|ch| ch.is_ascii_alphanumeric()) => {
                        OutputFallback::Geomprop(text.to_string())
                    }
                    None => {
                        return Err(ctx.invalid(
                            c,
                            format!("output \"{iname}\" of nodedef \"{}\"", def.name),
                            &format!("a {} default, not \"{text}\"", ty.name()),
                        ));
                    }
                };
                def.output_fallbacks.push((iname.clone(), fallback));
            }
            def.outputs.push((iname, ty));
            continue;
        }
        let default = match c.attribute("value") {
            Some(text)
                if ty.components() > 0 || matches!(ty, ValueType::String | ValueType::Filename) =>
            {
                Some(parse_value(ty, text).ok_or_else(|| {
                    ctx.invalid(
                        c,
                        format!("input \"{iname}\" of nodedef \"{}\"", def.name),
                        &format!("a {} value, not \"{text}\"", ty.name()),
                    )
                })?)
            }
            _ => None,
        };
        def.inputs.push(DefInput {
            name: iname,
            ty,
            default,
            defaultgeomprop: c.attribute("defaultgeomprop").map(str::to_string),
            uniform: c.attribute("uniform") == Some("true"),
        });
    }
    if def.outputs.is_empty()
        && let Some(ty) = e.attribute("type").and_then(ValueType::parse)
    {
        def.outputs.push(("out".to_string(), ty));
    }
    Ok(def)
}

/// The MaterialX library lux knows: nodedefs and the nodegraphs implementing some of them.
#[derive(Debug)]
pub struct Library {
    nodedefs: Vec<NodeDef>,
    by_name: HashMap<String, usize>,
    by_category: HashMap<String, Vec<usize>>,
    graphs: Vec<NodeGraphDef>,
    implementations: HashMap<String, usize>,
}

const FILES: [(&str, &str); 5] = [
    (
        "stdlib_defs.mtlx",
        include_str!("../../data/materialx/stdlib_defs.mtlx"),
    ),
    (
        "pbrlib_defs.mtlx",
        include_str!("../../data/materialx/pbrlib_defs.mtlx"),
    ),
    (
        "standard_surface.mtlx",
        include_str!("../../data/materialx/standard_surface.mtlx"),
    ),
    (
        "open_pbr_surface.mtlx",
        include_str!("../../data/materialx/open_pbr_surface.mtlx"),
    ),
    (
        "usd_preview_surface.mtlx",
        include_str!("../../data/materialx/usd_preview_surface.mtlx"),
    ),
];

/// The embedded library, parsed on first use.
pub fn library() -> &'static Library {
    static LIBRARY: OnceLock<Library> = OnceLock::new();
    LIBRARY.get_or_init(|| {
        let docs = FILES.iter().map(|(name, text)| {
            parse_document(text, &Path::new("materialx/libraries").join(name))
                .expect("the embedded MaterialX library parses")
        });
        Library::from_documents(docs)
    })
}

impl Library {
    /// A library of the nodedefs and nodegraph implementations of `docs` (later documents'
    /// nodedefs of the same name replace earlier ones).
    pub fn from_documents(docs: impl IntoIterator<Item = super::Document>) -> Library {
        let mut lib = Library {
            nodedefs: Vec::new(),
            by_name: HashMap::new(),
            by_category: HashMap::new(),
            graphs: Vec::new(),
            implementations: HashMap::new(),
        };
        let mut impls = Vec::new();
        for doc in docs {
            for def in doc.nodedefs {
                match lib.by_name.get(&def.name) {
                    Some(&i) => lib.nodedefs[i] = def,
                    None => {
                        lib.by_name.insert(def.name.clone(), lib.nodedefs.len());
                        lib.nodedefs.push(def);
                    }
                }
            }
            lib.graphs.extend(doc.nodegraphs);
            impls.extend(doc.implementations);
        }
        // Inheritance: a nodedef gains the ports of its ancestors it does not redeclare.
        let raw = lib.nodedefs.clone();
        for def in &mut lib.nodedefs {
            let mut parent = def.inherit.clone();
            let mut depth = 0;
            while let Some(p) = parent.take() {
                depth += 1;
                let Some(&pi) = lib.by_name.get(&p) else {
                    break;
                };
                if depth > 16 {
                    break;
                }
                let pdef = &raw[pi];
                for i in &pdef.inputs {
                    if def.input(&i.name).is_none() {
                        def.inputs.push(i.clone());
                    }
                }
                for o in &pdef.outputs {
                    if !def.outputs.iter().any(|(n, _)| n == &o.0) {
                        def.outputs.push(o.clone());
                    }
                }
                for f in &pdef.output_fallbacks {
                    if !def.output_fallbacks.iter().any(|(n, _)| n == &f.0) {
                        def.output_fallbacks.push(f.clone());
                    }
                }
                parent = pdef.inherit.clone();
            }
        }
        for (i, def) in lib.nodedefs.iter().enumerate() {
            lib.by_category
                .entry(def.category.clone())
                .or_default()
                .push(i);
        }
        for (gi, g) in lib.graphs.iter().enumerate() {
            if let Some(nd) = &g.nodedef {
                lib.implementations.insert(nd.clone(), gi);
            }
        }
        for (nd, ng) in impls {
            if let Some(gi) = lib.graphs.iter().position(|g| g.name == ng) {
                lib.implementations.insert(nd, gi);
            }
        }
        lib
    }

    /// Every nodedef, in document order.
    pub fn nodedefs(&self) -> &[NodeDef] {
        &self.nodedefs
    }

    /// The nodedef named `name` (`ND_image_color3`).
    pub fn nodedef(&self, name: &str) -> Option<&NodeDef> {
        self.by_name.get(name).map(|&i| &self.nodedefs[i])
    }

    /// The nodedef a node of `category` with output type `output_type` (`None`: a
    /// `multioutput` node, any outputs) and the authored `inputs` (name, type) instantiates
    /// (MaterialX Specification, "Nodes" and "NodeDef Elements"): a nodedef of the category
    /// whose single output has that type and which declares every authored input with the
    /// same type (a `string` may feed a `filename`), of the default version (`isdefaultversion`,
    /// or unversioned). Without such a match, a nodedef matching only the output type (and
    /// then only the category) — MaterialX's "rough match".
    pub fn resolve(
        &self,
        category: &str,
        output_type: Option<ValueType>,
        inputs: &[(&str, ValueType)],
    ) -> Option<&NodeDef> {
        self.resolve_version(category, output_type, inputs, None)
    }

    /// [`Library::resolve`] for a node requesting nodedef version `version` (`version="1.0"`).
    pub fn resolve_version(
        &self,
        category: &str,
        output_type: Option<ValueType>,
        inputs: &[(&str, ValueType)],
        version: Option<&str>,
    ) -> Option<&NodeDef> {
        let candidates: Vec<&NodeDef> = self
            .by_category
            .get(category)?
            .iter()
            .map(|&i| &self.nodedefs[i])
            .filter(|d| match version {
                Some(v) => d.version.as_deref().map(version_key) == Some(version_key(v)),
                None => d.version.is_none() || d.default_version,
            })
            .collect();
        let type_ok = |d: &&&NodeDef| match output_type {
            Some(t) => d.ty() == Some(t),
            None => d.outputs.len() > 1,
        };
        let inputs_ok = |d: &&&NodeDef| {
            inputs.iter().all(|(n, t)| {
                d.input(n).is_some_and(|i| {
                    i.ty == *t || (i.ty == ValueType::Filename && *t == ValueType::String)
                })
            })
        };
        candidates
            .iter()
            .find(|d| type_ok(d) && inputs_ok(d))
            .or_else(|| candidates.iter().find(|d| type_ok(d)))
            .or_else(|| (candidates.len() == 1).then(|| &candidates[0]))
            .copied()
    }

    /// The nodegraph implementing `nodedef` (by name), found through the nodedef's `inherit`
    /// chain when it has none of its own; `None` for nodes a renderer implements natively.
    pub fn implementation(&self, nodedef: &str) -> Option<&NodeGraphDef> {
        let mut name = nodedef.to_string();
        for _ in 0..16 {
            if let Some(&g) = self.implementations.get(&name) {
                return Some(&self.graphs[g]);
            }
            name = self.nodedef(&name)?.inherit.clone()?;
        }
        None
    }
}

fn version_key(v: &str) -> (u32, u32, u32) {
    let mut it = v.split('.').map(|p| p.trim().parse::<u32>().unwrap_or(0));
    (
        it.next().unwrap_or(0),
        it.next().unwrap_or(0),
        it.next().unwrap_or(0),
    )
}

/// The MaterialX nodedef of a USD shader id (`info:id`) of the UsdPreviewSurface family
/// (`usd_preview_surface.mtlx`): `UsdPreviewSurface` → `ND_UsdPreviewSurface_surfaceshader`,
/// `UsdUVTexture` → `ND_UsdUVTexture`, `UsdPrimvarReader_float2` →
/// `ND_UsdPrimvarReader_vector2`, …, `UsdTransform2d` → `ND_UsdTransform2d`. Other ids
/// (`ND_*` names already) answer `None`.
pub fn nodedef_for_usd_id(id: &str) -> Option<&'static str> {
    Some(match id {
        "UsdPreviewSurface" => "ND_UsdPreviewSurface_surfaceshader",
        "UsdUVTexture" => "ND_UsdUVTexture",
        "UsdTransform2d" => "ND_UsdTransform2d",
        "UsdPrimvarReader_float" => "ND_UsdPrimvarReader_float",
        "UsdPrimvarReader_float2" => "ND_UsdPrimvarReader_vector2",
        "UsdPrimvarReader_float3"
        | "UsdPrimvarReader_normal"
        | "UsdPrimvarReader_point"
        | "UsdPrimvarReader_vector" => "ND_UsdPrimvarReader_vector3",
        "UsdPrimvarReader_float4" => "ND_UsdPrimvarReader_vector4",
        "UsdPrimvarReader_int" => "ND_UsdPrimvarReader_integer",
        "UsdPrimvarReader_string" => "ND_UsdPrimvarReader_string",
        "UsdPrimvarReader_matrix" => "ND_UsdPrimvarReader_matrix44",
        _ => return None,
    })
}
