//! A MaterialX document as a USD layer, in the prim layout of usd-core's usdMtlx file-format
//! plugin (`UsdMtlxRead`), so that `.mtlx` references, payloads and sublayers compose
//! (`@./gold.mtlx@</MaterialX/Materials>`, `@./looks.mtlx@</ModelRoot>`):
//!
//! - every material node (`<surfacematerial>`) is a `Material` at
//!   `/MaterialX/Materials/<name>` (with `config:mtlx:version`) whose interface inputs are the
//!   union of its shader nodes' nodedef inputs, carrying the values the document authors;
//!   its `outputs:mtlx:surface` (`:displacement`, `:volume`) connects to a child `Shader` per
//!   shader node, which references `/MaterialX/Shaders/<node>` (its `info:id`, the nodedef's
//!   name such as `ND_standard_surface_surfaceshader`, and `outputs:surface`) and connects
//!   every input to the Material's interface input of that name, or to the nodegraph output
//!   the document connects it to. So a Material's interface input overridden in USD reaches
//!   the shader, as with usd-core;
//! - a `<nodegraph>` is a `NodeGraph` at `/MaterialX/NodeGraphs/<name>` (interface inputs,
//!   nodes as `Shader`s with typed inputs and `.connect`s, outputs), referenced beneath each
//!   Material that uses it; the document's top-level pattern nodes live in
//!   `/MaterialX/NodeGraphs` itself (usdMtlx's implicit nodegraph), referenced beneath a
//!   Material as `NodeGraphs`;
//! - `filename` values are asset paths (with `fileprefix` applied, relative to the document),
//!   with a `colorSpace` when it differs from the document's;
//! - looks, collections and material assignments become `/MaterialX/Collections`,
//!   `/MaterialX/Looks/<look>` with collection bindings, and `/ModelRoot` with a
//!   `LookVariant` variant set (`super::looks`).
//!
//! Not translated: material variants (`<variantset>`), material `inherit` (usdMtlx's
//! specializes), nodegraphs that implement a nodedef of the document itself (lux's
//! flattening reads those from the document), UI attributes.

use std::fmt::Write;

use super::document::{Document, Input, Node, NodeGraph};
use super::library::NodeDef;
use super::library::library;
use crate::shading::{Value, ValueType};

/// The USD value type name of a MaterialX type (usdMtlx's `UsdMtlxGetUsdType`); shader and
/// closure types are `token`s.
pub fn usd_type(ty: ValueType) -> &'static str {
    match ty {
        ValueType::Integer => "int",
        ValueType::Boolean => "bool",
        ValueType::Float => "float",
        ValueType::Color3 => "color3f",
        ValueType::Color4 => "color4f",
        ValueType::Vector2 => "float2",
        ValueType::Vector3 => "float3",
        ValueType::Vector4 => "float4",
        ValueType::Matrix33 => "matrix3d",
        ValueType::Matrix44 => "matrix4d",
        ValueType::String => "string",
        ValueType::Filename => "asset",
        _ => "token",
    }
}

/// The USD name of a node output: `surface`, `displacement`, `volume` for shader outputs (as
/// usdMtlx names them), else the MaterialX name.
fn output_name(name: &str, ty: Option<ValueType>) -> String {
    match ty {
        Some(ValueType::SurfaceShader) => "surface".into(),
        Some(ValueType::DisplacementShader) => "displacement".into(),
        Some(ValueType::VolumeShader) => "volume".into(),
        _ => name.to_string(),
    }
}

/// A MaterialX name as a USD prim or property name (a namespace colon becomes `__`).
fn usd_name(name: &str) -> String {
    name.replace(':', "__")
}

fn quote(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn num(v: f64) -> String {
    format!("{v}")
}

/// A value in `.usda` syntax.
fn usda_value(ty: ValueType, v: &Value) -> Option<String> {
    Some(match v {
        Value::String(s) => quote(s),
        Value::File(f) => {
            if f.asset.authored.contains('@') {
                return None;
            }
            format!("@{}@", f.asset.authored)
        }
        Value::Numbers(n) => match ty {
            ValueType::Integer => format!("{}", n.first()?.round() as i64),
            ValueType::Boolean => (if *n.first()? != 0.0 { "true" } else { "false" }).into(),
            ValueType::Float => num(*n.first()?),
            ValueType::Matrix33 | ValueType::Matrix44 => {
                let k = if ty == ValueType::Matrix33 { 3 } else { 4 };
                if n.len() != k * k {
                    return None;
                }
                let rows: Vec<String> = n
                    .chunks(k)
                    .map(|r| {
                        format!(
                            "({})",
                            r.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ")
                        )
                    })
                    .collect();
                format!("({})", rows.join(", "))
            }
            _ => format!(
                "({})",
                n.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ")
            ),
        },
    })
}

/// The nodedef of a document node: the library's, else one the document declares.
fn node_def<'a>(doc: &'a Document, node: &Node) -> Option<&'a NodeDef>
where
    'static: 'a,
{
    let lib = library();
    let def = match &node.nodedef {
        Some(n) => lib.nodedef(n),
        None => lib.resolve_version(
            &node.category,
            node.ty,
            &node.input_types(),
            node.version.as_deref(),
        ),
    };
    def.or_else(|| {
        doc.nodedefs.iter().find(|d| {
            node.nodedef.as_deref() == Some(d.name.as_str())
                || (node.nodedef.is_none() && d.category == node.category)
        })
    })
}

/// The nodedef name and outputs (name, type) of a document node.
fn node_signature(
    doc: &Document,
    node: &Node,
) -> (Option<String>, Vec<(String, Option<ValueType>)>) {
    match node_def(doc, node) {
        Some(def) => (
            Some(def.name.clone()),
            def.outputs
                .iter()
                .map(|(n, t)| (n.clone(), Some(*t)))
                .collect(),
        ),
        None => (node.nodedef.clone(), vec![("out".into(), node.ty)]),
    }
}

/// Whether a node is a shader node (its output a surface, displacement or volume shader): usdMtlx writes those under the Materials that use them.
fn is_shader_node(node: &Node) -> bool {
    matches!(
        node.ty,
        Some(ValueType::SurfaceShader | ValueType::DisplacementShader | ValueType::VolumeShader)
    )
}

const ROOT: &str = "/MaterialX";
const NODEGRAPHS: &str = "/MaterialX/NodeGraphs";

struct Writer<'d> {
    doc: &'d Document,
    out: String,
}

impl Writer<'_> {
    fn line(&mut self, depth: usize, text: &str) {
        for _ in 0..depth {
            self.out.push_str("    ");
        }
        self.out.push_str(text);
        self.out.push('\n');
    }

    /// The output path of `node` (a prim in scope `base`) named `output`.
    fn node_output(&self, base: &str, node: &Node, output: Option<&str>) -> String {
        let (_, outs) = node_signature(self.doc, node);
        let (name, ty) = match output {
            Some(o) => outs
                .iter()
                .find(|(n, _)| n == o)
                .cloned()
                .unwrap_or((o.to_string(), None)),
            None => outs.first().cloned().unwrap_or(("out".into(), node.ty)),
        };
        format!(
            "{base}/{}.outputs:{}",
            usd_name(&node.name),
            output_name(&name, ty)
        )
    }

    /// The output of nodegraph `g` an input names (`output`, else the graph's first).
    fn graph_output(g: &NodeGraph, output: Option<&str>) -> String {
        g.output(output)
            .map(|o| o.name.clone())
            .or_else(|| output.map(str::to_string))
            .unwrap_or_else(|| "out".into())
    }

    /// An authored value line (`decl = value`), with a `colorSpace` when the value is not in
    /// `lin_rec709`: a file's when it differs from the document's, a colour value's when lux
    /// could not convert it (`colorspace`, [`Input::colorspace`]).
    fn value(&mut self, depth: usize, decl: &str, ty: ValueType, v: &Value, colorspace: &str) {
        let Some(text) = usda_value(ty, v) else {
            return;
        };
        let space = match v {
            Value::File(f) if !f.colorspace.is_empty() && f.colorspace != self.doc.colorspace => {
                f.colorspace.as_str()
            }
            Value::Numbers(_) => colorspace,
            _ => "",
        };
        if space.is_empty() {
            self.line(depth, &format!("{decl} = {text}"));
        } else {
            self.line(depth, &format!("{decl} = {text} ("));
            self.line(depth + 1, &format!("colorSpace = {}", quote(space)));
            self.line(depth, ")");
        }
    }

    /// An input of a node inside nodegraph `graph` at `scope`, or of a top-level pattern node
    /// (`graph` `None`, `scope` the implicit nodegraph `/MaterialX/NodeGraphs`).
    fn input(&mut self, depth: usize, input: &Input, scope: &str, graph: Option<&NodeGraph>) {
        let ty = input.ty.unwrap_or(ValueType::Float);
        let decl = format!("{} inputs:{}", usd_type(ty), usd_name(&input.name));
        if let Some(iface) = &input.interfacename
            && graph.is_some()
        {
            self.line(
                depth,
                &format!("{decl}.connect = <{scope}.inputs:{}>", usd_name(iface)),
            );
            return;
        }
        if let Some(n) = &input.nodename {
            let inside = graph.and_then(|g| g.node(n));
            let path = match inside {
                Some(node) => Some(self.node_output(scope, node, input.output.as_deref())),
                None => self
                    .doc
                    .node(n)
                    .map(|node| self.node_output(NODEGRAPHS, node, input.output.as_deref())),
            };
            if let Some(path) = path {
                self.line(depth, &format!("{decl}.connect = <{path}>"));
            }
            return;
        }
        if let Some(gname) = &input.nodegraph
            && let Some(g) = self.doc.nodegraph(gname)
        {
            let out = Self::graph_output(g, input.output.as_deref());
            self.line(
                depth,
                &format!(
                    "{decl}.connect = <{NODEGRAPHS}/{}.outputs:{}>",
                    usd_name(gname),
                    usd_name(&out)
                ),
            );
            return;
        }
        if let Some(v) = &input.value {
            self.value(depth, &decl, ty, v, &input.colorspace);
        }
    }

    /// A pattern node as a `Shader` (inside a nodegraph, or in the implicit nodegraph).
    fn shader(&mut self, depth: usize, node: &Node, scope: &str, graph: Option<&NodeGraph>) {
        let (id, outs) = node_signature(self.doc, node);
        self.line(depth, &format!("def Shader \"{}\"", usd_name(&node.name)));
        self.line(depth, "{");
        if let Some(id) = id {
            self.line(
                depth + 1,
                &format!("uniform token info:id = {}", quote(&id)),
            );
        }
        for input in &node.inputs {
            self.input(depth + 1, input, scope, graph);
        }
        self.outputs(depth + 1, &outs);
        self.line(depth, "}");
    }

    fn outputs(&mut self, depth: usize, outs: &[(String, Option<ValueType>)]) {
        for (name, ty) in outs {
            self.line(
                depth,
                &format!(
                    "{} outputs:{}",
                    usd_type(ty.unwrap_or(ValueType::Float)),
                    output_name(name, *ty)
                ),
            );
        }
    }

    fn nodegraph(&mut self, depth: usize, g: &NodeGraph) {
        let path = format!("{NODEGRAPHS}/{}", usd_name(&g.name));
        self.line(depth, &format!("def NodeGraph \"{}\"", usd_name(&g.name)));
        self.line(depth, "{");
        for input in &g.inputs {
            // Interface inputs: values, or connections to top-level nodes.
            self.input(depth + 1, input, NODEGRAPHS, None);
        }
        for o in &g.outputs {
            let ty = o.ty.unwrap_or(ValueType::Float);
            let decl = format!("{} outputs:{}", usd_type(ty), usd_name(&o.name));
            if let Some(n) = o.nodename.as_deref().and_then(|n| g.node(n)) {
                let target = self.node_output(&path, n, o.output.as_deref());
                self.line(depth + 1, &format!("{decl}.connect = <{target}>"));
            } else if let Some(i) = &o.interfacename {
                self.line(
                    depth + 1,
                    &format!("{decl}.connect = <{path}.inputs:{}>", usd_name(i)),
                );
            } else {
                self.line(depth + 1, &decl);
            }
        }
        for node in &g.nodes {
            self.out.push('\n');
            self.shader(depth + 1, node, &path, Some(g));
        }
        self.line(depth, "}");
    }

    /// A `<surfacematerial>` (or other material node) as usdMtlx's Material: the interface
    /// inputs (every input of its shader nodes' nodedefs, with the values the document
    /// authors), its `outputs:mtlx:*` terminals, one `Shader` per shader node referencing
    /// `/MaterialX/Shaders/<node>` with every input connected to the interface (or to the
    /// nodegraph output the document connects it to), and the nodegraphs it uses referenced
    /// beneath it.
    fn material(&mut self, depth: usize, mat: &Node) {
        let name = usd_name(&mat.name);
        let path = format!("{ROOT}/Materials/{name}");
        let shaders: Vec<(&Node, &'static str)> = [
            ("surfaceshader", "surface"),
            ("displacementshader", "displacement"),
            ("volumeshader", "volume"),
        ]
        .into_iter()
        .filter_map(|(input, terminal)| {
            let i = mat.input(input)?;
            let n = self.doc.node(i.nodename.as_deref()?)?;
            Some((n, terminal))
        })
        .collect();
        // Each shader node's inputs: its nodedef's (else what the node authors).
        let inputs_of = |node: &Node| -> Vec<(String, ValueType)> {
            match node_def(self.doc, node) {
                Some(def) => def.inputs.iter().map(|i| (i.name.clone(), i.ty)).collect(),
                None => node
                    .inputs
                    .iter()
                    .map(|i| (i.name.clone(), i.ty.unwrap_or(ValueType::Float)))
                    .collect(),
            }
        };
        self.line(depth, &format!("def Material \"{name}\""));
        self.line(depth, "{");
        self.line(
            depth + 1,
            &format!(
                "string config:mtlx:version = \"{}.{}\"",
                self.doc.version.0, self.doc.version.1
            ),
        );
        // The interface: the union of the shader nodes' inputs (the first type wins), with
        // the values the document authors.
        let mut declared: Vec<String> = Vec::new();
        for (node, _) in &shaders {
            for (n, ty) in inputs_of(node) {
                if declared.contains(&n) {
                    continue;
                }
                let decl = format!("{} inputs:{}", usd_type(ty), usd_name(&n));
                match node
                    .input(&n)
                    .and_then(|i| Some((i.value.as_ref()?, &i.colorspace)))
                {
                    Some((v, space)) => self.value(depth + 1, &decl, ty, v, space),
                    None => self.line(depth + 1, &decl),
                }
                declared.push(n);
            }
        }
        for (node, terminal) in &shaders {
            let target = self.node_output(&path, node, None);
            self.line(
                depth + 1,
                &format!("token outputs:mtlx:{terminal}.connect = <{target}>"),
            );
        }
        // Nodegraphs referenced beneath the material: named ones by name, the implicit one
        // (top-level pattern nodes) as `NodeGraphs`.
        let mut graphs: Vec<String> = Vec::new();
        for (node, _) in &shaders {
            self.out.push('\n');
            let sname = usd_name(&node.name);
            self.referencing(
                depth + 1,
                "Shader ",
                &sname,
                &format!("{ROOT}/Shaders/{sname}"),
            );
            self.line(depth + 1, "{");
            for (n, ty) in inputs_of(node) {
                let decl = format!("{} inputs:{}", usd_type(ty), usd_name(&n));
                let source = match self.graph_source(node.input(&n)) {
                    Some((graph, output)) => {
                        if !graphs.contains(&graph) {
                            graphs.push(graph);
                        }
                        format!("{path}/{output}")
                    }
                    None => format!("{path}.inputs:{}", usd_name(&n)),
                };
                self.line(depth + 2, &format!("{decl}.connect = <{source}>"));
            }
            self.line(depth + 1, "}");
        }
        for g in &graphs {
            self.out.push('\n');
            let target = if g == "NodeGraphs" {
                NODEGRAPHS.to_string()
            } else {
                format!("{NODEGRAPHS}/{g}")
            };
            self.referencing(depth + 1, "", g, &target);
            self.line(depth + 1, "{");
            self.line(depth + 1, "}");
        }
        self.line(depth, "}");
    }

    /// Where a shader node's input is connected, as (the nodegraph prim beneath the material,
    /// the output's path relative to the material): a named nodegraph's output (`nodegraph` +
    /// `output`), or a top-level node's (`nodename`), which lives in the implicit nodegraph
    /// `NodeGraphs`.
    fn graph_source(&self, input: Option<&Input>) -> Option<(String, String)> {
        let input = input?;
        if let Some(g) = input
            .nodegraph
            .as_deref()
            .and_then(|g| self.doc.nodegraph(g))
        {
            let out = Self::graph_output(g, input.output.as_deref());
            let g = usd_name(&g.name);
            let output = format!("{g}.outputs:{}", usd_name(&out));
            return Some((g, output));
        }
        let node = self.doc.node(input.nodename.as_deref()?)?;
        let output = self.node_output("NodeGraphs", node, input.output.as_deref());
        Some(("NodeGraphs".to_string(), output))
    }

    /// `def <type>"name" (prepend references = <target>)`.
    fn referencing(&mut self, depth: usize, ty: &str, name: &str, target: &str) {
        self.line(depth, &format!("def {ty}\"{name}\" ("));
        self.line(depth + 1, &format!("prepend references = <{target}>"));
        self.line(depth, ")");
    }
}

/// The `.usda` text of `doc` in usdMtlx's layout (see the module docs).
pub fn to_usda(doc: &Document) -> String {
    let mut w = Writer {
        doc,
        out: String::new(),
    };
    let _ = writeln!(
        w.out,
        "#usda 1.0\n(\n    doc = {}\n)\n",
        quote(&format!(
            "MaterialX document {} (version {}.{}) translated by lux-usd in usdMtlx's layout",
            doc.path.display(),
            doc.version.0,
            doc.version.1
        ))
    );
    let materials: Vec<&Node> = doc
        .nodes
        .iter()
        .filter(|n| n.ty == Some(ValueType::Material))
        .collect();
    w.line(0, "def \"MaterialX\"");
    w.line(0, "{");
    w.line(1, "def \"Materials\"");
    w.line(1, "{");
    for (k, mat) in materials.iter().enumerate() {
        if k > 0 {
            w.out.push('\n');
        }
        w.material(2, mat);
    }
    w.line(1, "}");
    // The shader nodes' implementations the materials reference.
    w.out.push('\n');
    w.line(1, "def \"Shaders\"");
    w.line(1, "{");
    let mut first = true;
    for node in doc.nodes.iter().filter(|n| is_shader_node(n)) {
        if !first {
            w.out.push('\n');
        }
        first = false;
        let (id, outs) = node_signature(doc, node);
        w.line(2, &format!("def Shader \"{}\"", usd_name(&node.name)));
        w.line(2, "{");
        if let Some(id) = id {
            w.line(3, &format!("uniform token info:id = {}", quote(&id)));
        }
        w.outputs(3, &outs);
        w.line(2, "}");
    }
    w.line(1, "}");
    // Nodegraphs, and the document's top-level pattern nodes (usdMtlx's implicit nodegraph).
    w.out.push('\n');
    w.line(1, "def \"NodeGraphs\"");
    w.line(1, "{");
    let mut first = true;
    for g in &doc.nodegraphs {
        if !first {
            w.out.push('\n');
        }
        first = false;
        w.nodegraph(2, g);
    }
    for node in doc
        .nodes
        .iter()
        .filter(|n| !is_shader_node(n) && n.ty != Some(ValueType::Material))
    {
        if !first {
            w.out.push('\n');
        }
        first = false;
        w.shader(2, node, NODEGRAPHS, None);
    }
    w.line(1, "}");
    super::looks::write_looks(&mut w.out, doc, &materials);
    w.line(0, "}");
    super::looks::write_model_root(&mut w.out, doc);
    w.out
}

/// What a resolved MaterialX document's path is suffixed with to make the `.usda` stand-in
/// layer openusd reads it as (it picks a layer's format by the resolved path's extension).
pub const STAND_IN_SUFFIX: &str = "#usdMtlx.usda";

/// Whether a resolved path names a MaterialX document (`.mtlx`, any case), also inside a
/// `.usdz` package.
pub fn is_mtlx(path: &str) -> bool {
    // A package entry (`pkg.usdz[looks/gold.mtlx]`) counts by the entry's own extension.
    std::path::Path::new(path.trim_end_matches(']'))
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("mtlx"))
}

/// The resolved path openusd is handed for a resolved asset: a `.mtlx` document's stand-in
/// (`gold.mtlx#usdMtlx.usda`; inside a package the suffix goes on the entry,
/// `pkg.usdz[gold.mtlx#usdMtlx.usda]`, so that asset paths the document holds anchor inside
/// the package), any other path unchanged.
pub fn stand_in(resolved: openusd::ar::ResolvedPath) -> openusd::ar::ResolvedPath {
    let name = resolved.to_string_lossy();
    if !is_mtlx(&name) {
        return resolved;
    }
    match name.strip_suffix(']') {
        Some(entry) => openusd::ar::ResolvedPath::new(format!("{entry}{STAND_IN_SUFFIX}]")),
        None => openusd::ar::ResolvedPath::new(format!("{name}{STAND_IN_SUFFIX}")),
    }
}

/// The MaterialX document behind a stand-in path ([`stand_in`]), `None` for other paths.
pub fn stand_in_source(resolved: &str) -> Option<String> {
    let source = match resolved.strip_suffix(']') {
        Some(entry) => format!("{}]", entry.strip_suffix(STAND_IN_SUFFIX)?),
        None => resolved.strip_suffix(STAND_IN_SUFFIX)?.to_string(),
    };
    is_mtlx(&source).then_some(source)
}

/// The `.usda` bytes serving the MaterialX document `bytes` read from `path` as a layer
/// ([`to_usda`]).
pub fn layer_bytes(path: &str, bytes: &[u8]) -> Result<Vec<u8>, super::MtlxError> {
    let file = std::path::Path::new(path);
    let text = std::str::from_utf8(bytes).map_err(|e| super::MtlxError::Io {
        file: file.to_path_buf(),
        message: format!("not UTF-8 text: {e}"),
    })?;
    let doc = super::parse_document(text, file)?;
    Ok(to_usda(&doc).into_bytes())
}

#[cfg(test)]
mod tests {
    use crate::resolver::LuxResolver;
    use openusd::sdf::Value;
    use openusd::usd::Stage;

    #[test]
    fn referenced_documents_compose_with_connections_mapped() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/mtlx/stage.usda");
        let stage = Stage::builder()
            .resolver(LuxResolver::new())
            .open(path)
            .unwrap();
        let shader = stage.prim("/Looks/M_wood/SR_wood");
        assert!(shader.is_valid().unwrap());
        let id = shader.attribute("info:id").get::<Value>().unwrap();
        assert_eq!(
            format!("{id:?}"),
            format!(
                "{:?}",
                Some(Value::Token("ND_standard_surface_surfaceshader".into()))
            )
        );
        let connections = |prim: &str, attribute: &str| -> Vec<String> {
            stage
                .prim(prim)
                .attribute(attribute)
                .connections()
                .unwrap()
                .iter()
                .map(|p| p.to_string())
                .collect()
        };
        assert_eq!(
            connections("/Looks/M_wood/SR_wood", "inputs:base_color"),
            ["/Looks/M_wood/NG_wood.outputs:base_color_out"]
        );
        assert_eq!(
            connections("/Looks/M_wood", "outputs:mtlx:surface"),
            ["/Looks/M_wood/SR_wood.outputs:surface"]
        );
        assert_eq!(
            connections("/Looks/M_wood/NG_wood/uv_scaled", "inputs:in2"),
            ["/Looks/M_wood/NG_wood.inputs:uvscale"]
        );
        // Values live on the Material's interface, which the shader's inputs connect to.
        assert_eq!(
            connections("/Gold/mtlxstandard_surface1", "inputs:base_color"),
            ["/Gold.inputs:base_color"]
        );
        let color = stage
            .prim("/Gold")
            .attribute("inputs:base_color")
            .get::<Value>()
            .unwrap();
        assert!(format!("{color:?}").contains("0.910751"), "{color:?}");
    }
}
