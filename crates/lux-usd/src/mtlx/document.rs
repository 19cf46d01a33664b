//! Reading MaterialX documents (MaterialX Specification, "MTLX File Format Definition",
//! "Nodes", "Node Graph Elements", "File Prefixes", "Color Spaces and Color Management
//! Systems", "Material Nodes").

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::library::{NodeDef, parse_nodedef};
use super::{MtlxError, parse_value};
use crate::reader::AssetRef;
use crate::shading::{Connection, NetInput, NetNode, NetSource, Network, Value, ValueType};

/// An `<input>` of a node, nodegraph interface or material, as authored (after upgrade).
#[derive(Clone, Debug, PartialEq)]
pub struct Input {
    /// `name`.
    pub name: String,
    /// `type`, parsed (`None` when absent or not a [`ValueType`]).
    pub ty: Option<ValueType>,
    /// `value`, parsed by type; `filename` values with `fileprefix` applied, resolved against
    /// the document's directory and carrying the inherited `colorspace`; colour values in
    /// `lin_rec709` (see [`Input::colorspace`]).
    pub value: Option<Value>,
    /// `nodename`: a node in the same scope.
    pub nodename: Option<String>,
    /// `nodegraph`: a nodegraph of the document.
    pub nodegraph: Option<String>,
    /// `output`: which output of the node or nodegraph.
    pub output: Option<String>,
    /// `interfacename`: an interface input of the enclosing nodegraph.
    pub interfacename: Option<String>,
    /// `channels` (MaterialX 1.37/1.38 swizzle on a connection; removed by [`super::upgrade`]).
    pub channels: Option<String>,
    /// The colour space a `color3`/`color4` value is still in: empty when it was converted
    /// from its active `colorspace` (its own, else the nearest enclosing element's, else the
    /// document's) to `lin_rec709`, lux's working space
    /// ([`crate::shading::color_space`]), or none applied; the name when lux does not know it.
    pub colorspace: String,
    /// 1-based line.
    pub line: u32,
}

impl Input {
    /// An input holding a constant.
    pub fn constant(name: &str, ty: ValueType, value: Value) -> Input {
        Input {
            value: Some(value),
            ..Input::unconnected(name, Some(ty))
        }
    }

    /// An input connected to node `node` (output `output`, when it has several).
    pub fn connected(name: &str, ty: Option<ValueType>, node: &str, output: Option<&str>) -> Input {
        Input {
            nodename: Some(node.to_string()),
            output: output.map(str::to_string),
            ..Input::unconnected(name, ty)
        }
    }

    /// An input with neither value nor connection, at line 0.
    fn unconnected(name: &str, ty: Option<ValueType>) -> Input {
        Input {
            name: name.to_string(),
            ty,
            value: None,
            nodename: None,
            nodegraph: None,
            output: None,
            interfacename: None,
            channels: None,
            colorspace: String::new(),
            line: 0,
        }
    }

    /// An input named `name` of type `ty` reading what the nodegraph output `out` reads.
    fn through_output(name: String, ty: Option<ValueType>, out: &Output) -> Input {
        Input {
            name,
            ty,
            value: None,
            nodename: out.nodename.clone(),
            nodegraph: None,
            output: out.output.clone(),
            interfacename: out.interfacename.clone(),
            channels: None,
            colorspace: String::new(),
            line: out.line,
        }
    }
}

/// A node element: `<category name="…" type="…">` with its inputs.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// `name`.
    pub name: String,
    /// The element name (`standard_surface`, `image`).
    pub category: String,
    /// `type` as written (`color3`, `multioutput`).
    pub type_name: String,
    /// `type`, parsed (`None` for `multioutput`).
    pub ty: Option<ValueType>,
    /// `nodedef`, when authored.
    pub nodedef: Option<String>,
    /// `version`, when authored.
    pub version: Option<String>,
    /// The inputs.
    pub inputs: Vec<Input>,
    /// 1-based line.
    pub line: u32,
}

impl Node {
    /// The input named `name`.
    pub fn input(&self, name: &str) -> Option<&Input> {
        self.inputs.iter().find(|i| i.name == name)
    }

    /// The (name, type) of each input whose type is known, which with the node's type selects
    /// the nodedef of its category.
    pub fn input_types(&self) -> Vec<(&str, ValueType)> {
        self.inputs
            .iter()
            .filter_map(|i| i.ty.map(|t| (i.name.as_str(), t)))
            .collect()
    }
}

/// An `<output>` of a nodegraph.
#[derive(Clone, Debug, PartialEq)]
pub struct Output {
    /// `name`.
    pub name: String,
    /// `type`, parsed.
    pub ty: Option<ValueType>,
    /// `nodename`.
    pub nodename: Option<String>,
    /// `output` of that node.
    pub output: Option<String>,
    /// `interfacename` (an output passing an interface input through).
    pub interfacename: Option<String>,
    /// `channels` (MaterialX 1.38 swizzle on an output's connection; removed by
    /// [`super::upgrade`]).
    pub channels: Option<String>,
    /// 1-based line.
    pub line: u32,
}

/// A `<nodegraph>` (MaterialX Specification, "Node Graph Elements").
#[derive(Clone, Debug, PartialEq)]
pub struct NodeGraph {
    /// `name`.
    pub name: String,
    /// `nodedef`: the nodedef this graph implements (a functional nodegraph).
    pub nodedef: Option<String>,
    /// Interface inputs declared on the graph (compound nodegraphs).
    pub inputs: Vec<Input>,
    /// The nodes.
    pub nodes: Vec<Node>,
    /// The outputs.
    pub outputs: Vec<Output>,
    /// 1-based line.
    pub line: u32,
}

impl NodeGraph {
    /// The node named `name`.
    pub fn node(&self, name: &str) -> Option<&Node> {
        self.nodes.iter().find(|n| n.name == name)
    }

    /// The output named `name`, or with `None` the only (else first) output.
    pub fn output(&self, name: Option<&str>) -> Option<&Output> {
        match name {
            Some(n) => self.outputs.iter().find(|o| o.name == n),
            None => self.outputs.first(),
        }
    }
}

/// A `<materialassign>` of a look (MaterialX Specification, "Material Nodes"; looks).
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialAssign {
    /// `name`.
    pub name: String,
    /// `material`: a material node of the document.
    pub material: String,
    /// `geom`: geometry paths, as written (comma-separated list).
    pub geom: Option<String>,
    /// `collection`: a collection name.
    pub collection: Option<String>,
    /// The active `geomprefix` (the assign's, else its look's, else the document's): prefixed
    /// to every `geom` path.
    pub geomprefix: String,
}

/// A `<collection>` (MaterialX Specification, "Collections"): geometry included and excluded,
/// and other collections included.
#[derive(Clone, Debug, PartialEq)]
pub struct Collection {
    /// `name`.
    pub name: String,
    /// `includegeom` paths, with the active `geomprefix` applied.
    pub includegeom: Vec<String>,
    /// `excludegeom` paths, with the active `geomprefix` applied.
    pub excludegeom: Vec<String>,
    /// `includecollection` names.
    pub includecollection: Vec<String>,
}

/// A `<look>`.
#[derive(Clone, Debug, PartialEq)]
pub struct Look {
    /// `name`.
    pub name: String,
    /// Its material assignments, in order.
    pub assigns: Vec<MaterialAssign>,
    /// `inherit`: the look it inherits assignments from.
    pub inherit: Option<String>,
}

/// A MaterialX document, upgraded to 1.39.
#[derive(Clone, Debug, PartialEq)]
pub struct Document {
    /// Where it was read from (messages, and the directory filenames resolve against).
    pub path: PathBuf,
    /// `version` as authored (`(1, 38)`); the content is upgraded to 1.39.
    pub version: (u32, u32),
    /// The document's `colorspace`.
    pub colorspace: String,
    /// Top-level nodes, including the material nodes (`surfacematerial`).
    pub nodes: Vec<Node>,
    /// Nodegraphs.
    pub nodegraphs: Vec<NodeGraph>,
    /// Nodedefs declared in the document.
    pub nodedefs: Vec<NodeDef>,
    /// `<implementation nodedef="…" nodegraph="…">` pairs: nodedef name, nodegraph name.
    pub implementations: Vec<(String, String)>,
    /// Looks.
    pub looks: Vec<Look>,
    /// Collections.
    pub collections: Vec<Collection>,
}

/// Reads and parses the document at `path` ([`parse_document`]).
pub fn read_document(path: &Path) -> Result<Document, MtlxError> {
    let text = std::fs::read_to_string(path).map_err(|e| MtlxError::Io {
        file: path.to_path_buf(),
        message: e.to_string(),
    })?;
    parse_document(&text, path)
}

/// Inherited attributes while descending the document (MaterialX Specification, "File
/// Prefixes", "Color Spaces…": document → nodegraph → node → input).
#[derive(Clone, Default)]
struct Scope {
    fileprefix: String,
    colorspace: String,
}

impl Scope {
    fn enter(&self, e: roxmltree::Node) -> Scope {
        Scope {
            fileprefix: e
                .attribute("fileprefix")
                .map(str::to_string)
                .unwrap_or_else(|| self.fileprefix.clone()),
            colorspace: e
                .attribute("colorspace")
                .map(str::to_string)
                .unwrap_or_else(|| self.colorspace.clone()),
        }
    }
}

pub(crate) struct Ctx<'a> {
    pub(crate) file: &'a Path,
    pub(crate) text: &'a roxmltree::Document<'a>,
}

impl Ctx<'_> {
    pub(crate) fn line(&self, e: roxmltree::Node) -> u32 {
        self.text.text_pos_at(e.range().start).row
    }

    pub(crate) fn invalid(&self, e: roxmltree::Node, element: String, expected: &str) -> MtlxError {
        MtlxError::Invalid {
            file: self.file.to_path_buf(),
            line: self.line(e),
            element,
            expected: expected.to_string(),
        }
    }

    pub(crate) fn name(&self, e: roxmltree::Node) -> Result<String, MtlxError> {
        e.attribute("name")
            .map(str::to_string)
            .ok_or_else(|| self.invalid(e, e.tag_name().name().to_string(), "a `name` attribute"))
    }
}

/// Parses MaterialX document text read from `path` (used for messages and as the directory
/// `filename` inputs resolve against), and upgrades it to 1.39 ([`super::upgrade`]).
///
/// Errors: malformed XML (with line and column), a root other than `<materialx>`, a version
/// older than 1.38 ([`MtlxError::Version`]), an element without `name`, a value that does not
/// parse as its type.
pub fn parse_document(text: &str, path: &Path) -> Result<Document, MtlxError> {
    let xml = roxmltree::Document::parse(text).map_err(|e| {
        let pos = e.pos();
        MtlxError::Xml {
            file: path.to_path_buf(),
            line: pos.row,
            column: pos.col,
            message: e.to_string(),
        }
    })?;
    let ctx = Ctx {
        file: path,
        text: &xml,
    };
    let root = xml.root_element();
    if root.tag_name().name() != "materialx" {
        return Err(ctx.invalid(
            root,
            root.tag_name().name().to_string(),
            "the root element <materialx>",
        ));
    }
    let version = match root.attribute("version") {
        None => (1, 39),
        Some(v) => parse_version(v)
            .ok_or_else(|| ctx.invalid(root, "materialx".into(), "version=\"major.minor\""))?,
    };
    if version < super::upgrade::OLDEST {
        return Err(MtlxError::Version {
            file: path.to_path_buf(),
            line: ctx.line(root),
            major: version.0,
            minor: version.1,
        });
    }
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let scope = Scope::default().enter(root);
    let mut doc = Document {
        path: path.to_path_buf(),
        version,
        colorspace: scope.colorspace.clone(),
        nodes: Vec::new(),
        nodegraphs: Vec::new(),
        nodedefs: Vec::new(),
        implementations: Vec::new(),
        looks: Vec::new(),
        collections: Vec::new(),
    };
    let geomprefix = root.attribute("geomprefix").unwrap_or("");
    for e in root.children().filter(|c| c.is_element()) {
        match e.tag_name().name() {
            "nodedef" => doc.nodedefs.push(parse_nodedef(&ctx, e)?),
            "nodegraph" => doc
                .nodegraphs
                .push(parse_nodegraph(&ctx, e, &scope.enter(e), &dir)?),
            "implementation" => {
                if let (Some(nd), Some(ng)) = (e.attribute("nodedef"), e.attribute("nodegraph")) {
                    doc.implementations.push((nd.to_string(), ng.to_string()));
                }
            }
            "look" => doc.looks.push(parse_look(&ctx, e, geomprefix)?),
            "collection" => doc.collections.push(parse_collection(&ctx, e, geomprefix)?),
            // Elements without shading content for lux: type, unit and geometric property
            // declarations, geometry info, UI backdrops, variants, lookgroups,
            // top-level outputs and tokens.
            "typedef" | "unittypedef" | "unitdef" | "geompropdef" | "geominfo" | "backdrop"
            | "variantset" | "lookgroup" | "propertyset" | "output" | "token" | "input"
            | "targetdef" | "attributedef" | "include" => {}
            _ => doc.nodes.push(parse_node(&ctx, e, &scope, &dir)?),
        }
    }
    if doc.version < (1, 39) {
        super::upgrade::upgrade(&mut doc);
    }
    Ok(doc)
}

fn parse_version(v: &str) -> Option<(u32, u32)> {
    let mut it = v.trim().split('.');
    let major = it.next()?.parse().ok()?;
    let minor = it.next().map_or(Some(0), |m| m.parse().ok())?;
    Some((major, minor))
}

fn parse_look(ctx: &Ctx, e: roxmltree::Node, geomprefix: &str) -> Result<Look, MtlxError> {
    let geomprefix = e.attribute("geomprefix").unwrap_or(geomprefix);
    let mut look = Look {
        name: ctx.name(e)?,
        assigns: Vec::new(),
        inherit: e.attribute("inherit").map(str::to_string),
    };
    for a in e.children().filter(|c| c.has_tag_name("materialassign")) {
        look.assigns.push(MaterialAssign {
            name: ctx.name(a)?,
            material: a
                .attribute("material")
                .map(str::to_string)
                .ok_or_else(|| ctx.invalid(a, "materialassign".into(), "a `material` attribute"))?,
            geom: a.attribute("geom").map(str::to_string),
            collection: a.attribute("collection").map(str::to_string),
            geomprefix: a.attribute("geomprefix").unwrap_or(geomprefix).to_string(),
        });
    }
    Ok(look)
}

/// A MaterialX string array (`"a, b,c"`): the comma-separated items, trimmed, empty ones
/// dropped.
pub fn split_array(s: &str) -> Vec<String> {
    s.split(',')
        .map(str::trim)
        .filter(|x| !x.is_empty())
        .map(str::to_string)
        .collect()
}

fn parse_collection(
    ctx: &Ctx,
    e: roxmltree::Node,
    geomprefix: &str,
) -> Result<Collection, MtlxError> {
    let geomprefix = e.attribute("geomprefix").unwrap_or(geomprefix);
    let paths = |attr: &str| -> Vec<String> {
        e.attribute(attr)
            .map(split_array)
            .unwrap_or_default()
            .into_iter()
            .map(|p| format!("{geomprefix}{p}"))
            .collect()
    };
    Ok(Collection {
        name: ctx.name(e)?,
        includegeom: paths("includegeom"),
        excludegeom: paths("excludegeom"),
        includecollection: e
            .attribute("includecollection")
            .map(split_array)
            .unwrap_or_default(),
    })
}

fn parse_nodegraph(
    ctx: &Ctx,
    e: roxmltree::Node,
    scope: &Scope,
    dir: &Path,
) -> Result<NodeGraph, MtlxError> {
    let mut g = NodeGraph {
        name: ctx.name(e)?,
        nodedef: e.attribute("nodedef").map(str::to_string),
        inputs: Vec::new(),
        nodes: Vec::new(),
        outputs: Vec::new(),
        line: ctx.line(e),
    };
    for c in e.children().filter(|c| c.is_element()) {
        match c.tag_name().name() {
            "input" => g.inputs.push(parse_input(ctx, c, scope, dir)?),
            "output" => g.outputs.push(Output {
                name: ctx.name(c)?,
                ty: c.attribute("type").and_then(ValueType::parse),
                nodename: c.attribute("nodename").map(str::to_string),
                output: c.attribute("output").map(str::to_string),
                interfacename: c.attribute("interfacename").map(str::to_string),
                channels: non_empty_attribute(c, "channels"),
                line: ctx.line(c),
            }),
            "token" | "backdrop" => {}
            _ => g.nodes.push(parse_node(ctx, c, scope, dir)?),
        }
    }
    Ok(g)
}

fn parse_node(ctx: &Ctx, e: roxmltree::Node, outer: &Scope, dir: &Path) -> Result<Node, MtlxError> {
    let scope = outer.enter(e);
    let type_name = e.attribute("type").unwrap_or("").to_string();
    let mut node = Node {
        name: ctx.name(e)?,
        category: e.tag_name().name().to_string(),
        ty: ValueType::parse(&type_name),
        type_name,
        nodedef: e.attribute("nodedef").map(str::to_string),
        version: e.attribute("version").map(str::to_string),
        inputs: Vec::new(),
        line: ctx.line(e),
    };
    for c in e.children().filter(|c| c.has_tag_name("input")) {
        node.inputs.push(parse_input(ctx, c, &scope, dir)?);
    }
    Ok(node)
}

fn parse_input(
    ctx: &Ctx,
    e: roxmltree::Node,
    outer: &Scope,
    dir: &Path,
) -> Result<Input, MtlxError> {
    let scope = outer.enter(e);
    let name = ctx.name(e)?;
    let ty = e.attribute("type").and_then(ValueType::parse);
    let mut unconverted = String::new();
    let value = match (e.attribute("value"), ty) {
        (Some(text), Some(ty)) => {
            if matches!(
                ty,
                ValueType::Bsdf
                    | ValueType::Edf
                    | ValueType::Vdf
                    | ValueType::SurfaceShader
                    | ValueType::DisplacementShader
                    | ValueType::VolumeShader
                    | ValueType::Material
            ) {
                None
            } else {
                let mut v = parse_value(ty, text).ok_or_else(|| {
                    ctx.invalid(
                        e,
                        format!("input \"{name}\""),
                        &format!("a {} value, not \"{text}\"", ty.name()),
                    )
                })?;
                if let Value::File(f) = &mut v {
                    let authored = if f.asset.authored.is_empty() {
                        String::new()
                    } else {
                        format!("{}{}", scope.fileprefix, f.asset.authored)
                    };
                    f.asset = resolve_file(&authored, dir);
                    f.colorspace = scope.colorspace.clone();
                }
                // A colour value is in its active colour space: converted to lin_rec709, lux's
                // working space (an unknown space is kept, see `Input::colorspace`).
                if let Value::Numbers(c) = &mut v
                    && matches!(ty, ValueType::Color3 | ValueType::Color4)
                    && !scope.colorspace.is_empty()
                    && !crate::shading::color_space::to_lin_rec709(&scope.colorspace, c)
                {
                    unconverted = scope.colorspace.clone();
                }
                Some(v)
            }
        }
        _ => None,
    };
    Ok(Input {
        name,
        ty,
        value,
        nodename: non_empty_attribute(e, "nodename"),
        nodegraph: non_empty_attribute(e, "nodegraph"),
        output: non_empty_attribute(e, "output"),
        interfacename: non_empty_attribute(e, "interfacename"),
        channels: non_empty_attribute(e, "channels"),
        colorspace: unconverted,
        line: ctx.line(e),
    })
}

/// Attribute `name` of `e`, unless absent or empty.
fn non_empty_attribute(e: roxmltree::Node, name: &str) -> Option<String> {
    e.attribute(name)
        .filter(|s| !s.is_empty())
        .map(str::to_string)
}

/// A filename as authored (fileprefix applied) resolved against the document's directory.
fn resolve_file(authored: &str, dir: &Path) -> AssetRef {
    let resolved = (!authored.is_empty())
        .then(|| {
            let p = Path::new(authored);
            if p.is_absolute() {
                p.to_path_buf()
            } else {
                dir.join(p)
            }
        })
        .filter(|p| p.is_file());
    AssetRef {
        authored: authored.to_string(),
        resolved,
    }
}

impl Document {
    /// The node graph named `name`.
    pub fn nodegraph(&self, name: &str) -> Option<&NodeGraph> {
        self.nodegraphs.iter().find(|g| g.name == name)
    }

    /// The top-level node named `name`.
    pub fn node(&self, name: &str) -> Option<&Node> {
        self.nodes.iter().find(|n| n.name == name)
    }

    /// The names of the document's `surfacematerial` nodes, in order.
    pub fn materials(&self) -> Vec<&str> {
        self.nodes
            .iter()
            .filter(|n| n.category == "surfacematerial")
            .map(|n| n.name.as_str())
            .collect()
    }

    /// The [`Network`] of the surfacematerial `material` (MaterialX Specification, "Material
    /// Nodes"): its `surfaceshader` input's node and every node upstream of it, nodegraph
    /// boundaries resolved away (a `nodegraph="NG" output="o"` connection leads to the node
    /// behind that output; an input with `interfacename` takes the nodegraph's interface
    /// input, its value or connection). Node names are `file:/node` or
    /// `file:/nodegraph/node`; [`Network::material`] is `file:/material`.
    pub fn network(&self, material: &str) -> Result<Network, MtlxError> {
        let mat = self
            .nodes
            .iter()
            .find(|n| n.name == material && n.category == "surfacematerial")
            .ok_or_else(|| {
                self.network_error(format!("no surfacematerial named \"{material}\""))
            })?;
        let file = self
            .path
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default();
        let mut b = Builder {
            doc: self,
            net: Network::default(),
            index: HashMap::new(),
            scopes: vec![ScopeInfo {
                graph: None,
                instance: None,
                path: format!("{file}:"),
            }],
            compound: HashMap::new(),
            instances: HashMap::new(),
            depth: 0,
        };
        b.net.material = format!("{file}:/{material}");
        let surface = match mat.input("surfaceshader") {
            Some(i) => match b.source(TOP, i)? {
                Some(NetSource::Connection(c)) => Some(c),
                _ => None,
            },
            None => None,
        };
        b.net.surface = surface;
        Ok(b.net)
    }

    /// The nodedef declared in this document for a node, and the document's nodegraph
    /// implementing it (a custom node defined by a functional nodegraph, MaterialX
    /// Specification, "Custom Node Definition Using Node Graphs").
    fn custom_node(&self, node: &Node) -> Option<(&NodeDef, usize)> {
        let def = self.nodedefs.iter().find(|d| match &node.nodedef {
            Some(n) => &d.name == n,
            None => d.category == node.category && (node.ty.is_none() || d.ty() == node.ty),
        })?;
        let graph = self
            .nodegraphs
            .iter()
            .position(|g| g.nodedef.as_deref() == Some(def.name.as_str()))
            .or_else(|| {
                let (_, ng) = self
                    .implementations
                    .iter()
                    .find(|(nd, _)| nd == &def.name)?;
                self.nodegraphs.iter().position(|g| &g.name == ng)
            })?;
        Some((def, graph))
    }

    fn network_error(&self, message: String) -> MtlxError {
        MtlxError::Network {
            file: self.path.clone(),
            message,
        }
    }
}

const TOP: usize = 0;

/// A scope nodes are looked up in while building a [`Network`]: the document's top level, a
/// compound nodegraph, or one instance of a custom node's functional nodegraph.
struct ScopeInfo {
    /// The nodegraph whose nodes the scope holds (`None`: top level).
    graph: Option<usize>,
    /// For an instance: the scope of the instantiating node, that node, and its nodedef.
    instance: Option<(usize, Node, NodeDef)>,
    /// Prefix of the names of the scope's nodes (`file.mtlx:/NG_wood`).
    path: String,
}

/// Builds a [`Network`]: nodes keyed by (scope, node name).
struct Builder<'d> {
    doc: &'d Document,
    net: Network,
    index: HashMap<(usize, String), usize>,
    scopes: Vec<ScopeInfo>,
    /// Compound nodegraph index → its scope.
    compound: HashMap<usize, usize>,
    /// (scope, custom node name) → the scope of its graph instance.
    instances: HashMap<(usize, String), usize>,
    depth: usize,
}

impl<'d> Builder<'d> {
    fn container(&self, scope: usize) -> &'d [Node] {
        match self.scopes[scope].graph {
            None => &self.doc.nodes,
            Some(g) => &self.doc.nodegraphs[g].nodes,
        }
    }

    fn compound_scope(&mut self, g: usize) -> usize {
        if let Some(&s) = self.compound.get(&g) {
            return s;
        }
        let path = format!("{}/{}", self.scopes[TOP].path, self.doc.nodegraphs[g].name);
        let s = self.push_scope(g, None, path);
        self.compound.insert(g, s);
        s
    }

    /// A new scope of nodegraph `graph`'s nodes: its index.
    fn push_scope(
        &mut self,
        graph: usize,
        instance: Option<(usize, Node, NodeDef)>,
        path: String,
    ) -> usize {
        self.scopes.push(ScopeInfo {
            graph: Some(graph),
            instance,
            path,
        });
        self.scopes.len() - 1
    }

    /// What a connection to output `output` of node `name` in `scope` reads.
    fn connect(
        &mut self,
        scope: usize,
        name: &str,
        output: Option<&str>,
    ) -> Result<Option<NetSource>, MtlxError> {
        let doc = self.doc;
        let Some(node) = self.container(scope).iter().find(|n| n.name == name) else {
            return Err(doc.network_error(format!("no node {}/{name}", self.scopes[scope].path)));
        };
        if let Some((def, g)) = doc.custom_node(node) {
            if self.depth > 32 {
                return Err(doc.network_error(format!(
                    "{}/{name}: custom nodes nested too deeply",
                    self.scopes[scope].path
                )));
            }
            let inst = match self.instances.get(&(scope, name.to_string())) {
                Some(&s) => s,
                None => {
                    let path = format!("{}/{name}", self.scopes[scope].path);
                    let s = self.push_scope(g, Some((scope, node.clone(), def.clone())), path);
                    self.instances.insert((scope, name.to_string()), s);
                    s
                }
            };
            let graph = &doc.nodegraphs[g];
            let Some(out) = graph.output(output) else {
                return Ok(None);
            };
            let inner = Input::through_output(out.name.clone(), out.ty, out);
            self.depth += 1;
            let r = self.source(inst, &inner);
            self.depth -= 1;
            return r;
        }
        let index = self.node(scope, node)?;
        Ok(Some(NetSource::Connection(Connection {
            node: index,
            output: output.unwrap_or("out").to_string(),
        })))
    }

    fn node(&mut self, scope: usize, node: &'d Node) -> Result<usize, MtlxError> {
        if let Some(&i) = self.index.get(&(scope, node.name.clone())) {
            return Ok(i);
        }
        let idx = self.net.nodes.len();
        // A node requesting a nodedef version resolves it here (Network carries no version).
        let nodedef = node.nodedef.clone().or_else(|| {
            let version = node.version.as_deref()?;
            super::library()
                .resolve_version(&node.category, node.ty, &node.input_types(), Some(version))
                .map(|d| d.name.clone())
        });
        self.net.nodes.push(NetNode {
            name: format!("{}/{}", self.scopes[scope].path, node.name),
            nodedef,
            category: node.category.clone(),
            ty: node.ty,
            inputs: Vec::new(),
        });
        self.index.insert((scope, node.name.clone()), idx);
        let mut inputs = Vec::new();
        for input in &node.inputs {
            if let Some(source) = self.source(scope, input)? {
                inputs.push(NetInput {
                    name: input.name.clone(),
                    ty: input.ty,
                    source,
                });
            }
        }
        self.net.nodes[idx].inputs = inputs;
        Ok(idx)
    }

    /// What feeds `input` (authored in `scope`): `None` when nothing does.
    fn source(&mut self, scope: usize, input: &Input) -> Result<Option<NetSource>, MtlxError> {
        let doc = self.doc;
        if let Some(iface) = &input.interfacename {
            let graph = self.scopes[scope].graph;
            if let Some((parent, node, def)) = &self.scopes[scope].instance {
                // A custom node's graph: the instantiating node's input, else the nodedef's
                // default.
                let (parent, outer, default) = (
                    *parent,
                    node.input(iface).cloned(),
                    def.input(iface).and_then(|d| d.default.clone()),
                );
                return match outer {
                    Some(outer) => self.source(parent, &outer),
                    None => Ok(default.map(NetSource::Value)),
                };
            }
            let Some(g) = graph else {
                return Ok(input.value.clone().map(NetSource::Value));
            };
            let graph = &doc.nodegraphs[g];
            return match graph.inputs.iter().find(|i| &i.name == iface) {
                Some(outer) => self.source(TOP, outer),
                None => Err(doc.network_error(format!(
                    "{}: no interface input \"{iface}\"",
                    self.scopes[scope].path
                ))),
            };
        }
        if let Some(n) = &input.nodename {
            // A compound nodegraph's interface input may read a top-level node.
            let scope = if self.container(scope).iter().any(|c| &c.name == n) {
                scope
            } else {
                TOP
            };
            return self.connect(scope, n, input.output.as_deref());
        }
        if let Some(gname) = &input.nodegraph {
            let g = doc
                .nodegraphs
                .iter()
                .position(|g| &g.name == gname)
                .ok_or_else(|| doc.network_error(format!("no nodegraph \"{gname}\"")))?;
            let graph = &doc.nodegraphs[g];
            let out = graph.output(input.output.as_deref()).ok_or_else(|| {
                doc.network_error(format!(
                    "{}/{gname}: no output \"{}\"",
                    self.scopes[TOP].path,
                    input.output.as_deref().unwrap_or("")
                ))
            })?;
            let inner = Input::through_output(input.name.clone(), input.ty, out);
            let s = self.compound_scope(g);
            return self.source(s, &inner);
        }
        Ok(input.value.clone().map(NetSource::Value))
    }
}
