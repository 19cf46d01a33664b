//! A MaterialX document as a USD layer, in the prim layout of usd-core's usdMtlx file-format
//! plugin, so that `.mtlx` references, payloads and sublayers compose
//! (`@./gold.mtlx@</MaterialX/Materials>`):
//!
//! - every `<surfacematerial>` is a `Material` at `/MaterialX/Materials/<name>` whose
//!   `outputs:mtlx:surface` (`:displacement`, `:volume`) connects to its shader node;
//! - a node is a `Shader` whose `info:id` is its nodedef's name (`ND_standard_surface_surfaceshader`),
//!   with typed inputs (`color3f inputs:base_color`, `asset inputs:file`, `token` for closures),
//!   its outputs (`outputs:surface` for a surfaceshader, as usdMtlx names them, else the
//!   nodedef's output names), connections as `.connect`;
//! - a `<nodegraph>` is a `NodeGraph` with its interface inputs, its nodes and its outputs
//!   connected to them; `interfacename` connects to the graph's input;
//! - `filename` values are asset paths (with `fileprefix` applied, relative to the document),
//!   with a `colorSpace` when one is stated.
//!
//! Unlike usdMtlx, shader nodes and nodegraphs a material uses are written under the Material
//! itself with their values authored on them (usdMtlx authors the values on the Material's
//! interface inputs and references shared prims under `/MaterialX/Shaders` and
//! `/MaterialX/NodeGraphs`); looks, collections and variants are not translated.

use std::collections::HashSet;
use std::fmt::Write;

use super::document::{Document, Input, Node, NodeGraph};
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

/// The nodedef name and outputs (name, type) of a document node.
fn node_signature(
    doc: &Document,
    node: &Node,
) -> (Option<String>, Vec<(String, Option<ValueType>)>) {
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
    if let Some(def) = def {
        let outs = def
            .outputs
            .iter()
            .map(|(n, t)| (n.clone(), Some(*t)))
            .collect();
        return (Some(def.name.clone()), outs);
    }
    // A nodedef declared in the document itself.
    if let Some(def) = doc.nodedefs.iter().find(|d| {
        node.nodedef.as_deref() == Some(d.name.as_str())
            || (node.nodedef.is_none() && d.category == node.category)
    }) {
        let outs = def
            .outputs
            .iter()
            .map(|(n, t)| (n.clone(), Some(*t)))
            .collect();
        return (Some(def.name.clone()), outs);
    }
    (node.nodedef.clone(), vec![("out".into(), node.ty)])
}

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

    /// The output path of `node` (in scope `base`) named `output`.
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

    /// Writes the input as a property of a prim in scope `scope` (the material's path for
    /// top-level nodes, the nodegraph's path inside it), collecting the top-level nodes and
    /// nodegraphs it reaches.
    fn input(
        &mut self,
        depth: usize,
        input: &Input,
        scope: &str,
        graph: Option<&NodeGraph>,
        mat: &str,
        reach: &mut Reach,
    ) {
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
            let node = match graph {
                Some(g) => g.node(n),
                None => self.doc.node(n),
            };
            if let Some(node) = node {
                if graph.is_none() {
                    reach.nodes.push(node.name.clone());
                }
                let path = self.node_output(scope, node, input.output.as_deref());
                self.line(depth, &format!("{decl}.connect = <{path}>"));
            } else if graph.is_some() {
                // A nodegraph interface input connected to a top-level node.
                if let Some(node) = self.doc.node(n) {
                    reach.nodes.push(node.name.clone());
                    let path = self.node_output(mat, node, input.output.as_deref());
                    self.line(depth, &format!("{decl}.connect = <{path}>"));
                }
            }
            return;
        }
        if let Some(gname) = &input.nodegraph
            && let Some(g) = self.doc.nodegraph(gname)
        {
            reach.graphs.push(g.name.clone());
            let out = g
                .output(input.output.as_deref())
                .map(|o| o.name.clone())
                .unwrap_or_else(|| input.output.clone().unwrap_or_else(|| "out".into()));
            self.line(
                depth,
                &format!(
                    "{decl}.connect = <{mat}/{}.outputs:{}>",
                    usd_name(gname),
                    usd_name(&out)
                ),
            );
            return;
        }
        if let Some(v) = &input.value
            && let Some(text) = usda_value(ty, v)
        {
            match v {
                Value::File(f)
                    if !f.colorspace.is_empty() && f.colorspace != self.doc.colorspace =>
                {
                    self.line(depth, &format!("{decl} = {text} ("));
                    self.line(depth + 1, &format!("colorSpace = {}", quote(&f.colorspace)));
                    self.line(depth, ")");
                }
                _ => self.line(depth, &format!("{decl} = {text}")),
            }
        }
    }

    fn shader(
        &mut self,
        depth: usize,
        node: &Node,
        scope: &str,
        graph: Option<&NodeGraph>,
        mat: &str,
        reach: &mut Reach,
    ) {
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
            self.input(depth + 1, input, scope, graph, mat, reach);
        }
        for (name, ty) in &outs {
            self.line(
                depth + 1,
                &format!(
                    "{} outputs:{}",
                    usd_type(ty.unwrap_or(ValueType::Float)),
                    output_name(name, *ty)
                ),
            );
        }
        self.line(depth, "}");
    }

    fn nodegraph(&mut self, depth: usize, g: &NodeGraph, mat: &str, reach: &mut Reach) {
        let path = format!("{mat}/{}", usd_name(&g.name));
        self.line(depth, &format!("def NodeGraph \"{}\"", usd_name(&g.name)));
        self.line(depth, "{");
        for input in &g.inputs {
            // Interface inputs: values, or connections to top-level nodes.
            self.input(depth + 1, input, mat, None, mat, reach);
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
            self.shader(depth + 1, node, &path, Some(g), mat, reach);
        }
        self.line(depth, "}");
    }
}

#[derive(Default)]
struct Reach {
    nodes: Vec<String>,
    graphs: Vec<String>,
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
    w.line(0, "def \"MaterialX\"");
    w.line(0, "{");
    w.line(1, "def \"Materials\"");
    w.line(1, "{");
    let mut first = true;
    for mat in doc.nodes.iter().filter(|n| n.category == "surfacematerial") {
        if !first {
            w.out.push('\n');
        }
        first = false;
        let path = format!("/MaterialX/Materials/{}", usd_name(&mat.name));
        w.line(2, &format!("def Material \"{}\"", usd_name(&mat.name)));
        w.line(2, "{");
        let mut reach = Reach::default();
        for (input, terminal) in [
            ("surfaceshader", "surface"),
            ("displacementshader", "displacement"),
            ("volumeshader", "volume"),
        ] {
            let Some(i) = mat.input(input) else { continue };
            if let Some(n) = i.nodename.as_deref().and_then(|n| doc.node(n)) {
                reach.nodes.push(n.name.clone());
                let target = w.node_output(&path, n, i.output.as_deref());
                w.line(
                    3,
                    &format!("token outputs:mtlx:{terminal}.connect = <{target}>"),
                );
            } else if let Some(g) = i.nodegraph.as_deref().and_then(|g| doc.nodegraph(g)) {
                reach.graphs.push(g.name.clone());
                let out = g
                    .output(i.output.as_deref())
                    .map(|o| o.name.clone())
                    .unwrap_or_else(|| "out".into());
                w.line(
                    3,
                    &format!(
                        "token outputs:mtlx:{terminal}.connect = <{path}/{}.outputs:{}>",
                        usd_name(&g.name),
                        usd_name(&out)
                    ),
                );
            }
        }
        // Everything the material reaches, each once.
        let mut done_nodes = HashSet::new();
        let mut done_graphs = HashSet::new();
        loop {
            if let Some(n) = reach.nodes.pop() {
                if done_nodes.insert(n.clone())
                    && let Some(node) = doc.node(&n)
                {
                    w.out.push('\n');
                    w.shader(3, node, &path, None, &path, &mut reach);
                }
                continue;
            }
            if let Some(g) = reach.graphs.pop() {
                if done_graphs.insert(g.clone())
                    && let Some(graph) = doc.nodegraph(&g)
                {
                    w.out.push('\n');
                    w.nodegraph(3, graph, &path, &mut reach);
                }
                continue;
            }
            break;
        }
        w.line(2, "}");
    }
    w.line(1, "}");
    w.line(0, "}");
    w.out
}

/// What a resolved MaterialX document's path is suffixed with to make the `.usda` stand-in
/// layer openusd reads it as (it picks a layer's format by the resolved path's extension).
pub const STAND_IN_SUFFIX: &str = "#usdMtlx.usda";

/// Whether a resolved path names a MaterialX document (`.mtlx`, any case).
pub fn is_mtlx(path: &str) -> bool {
    std::path::Path::new(path)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("mtlx"))
}

/// The resolved path openusd is handed for a resolved asset: a `.mtlx` document's stand-in
/// (`gold.mtlx#usdMtlx.usda`), any other path unchanged.
pub fn stand_in(resolved: openusd::ar::ResolvedPath) -> openusd::ar::ResolvedPath {
    let name = resolved.to_string_lossy();
    if is_mtlx(&name) {
        openusd::ar::ResolvedPath::new(format!("{name}{STAND_IN_SUFFIX}"))
    } else {
        resolved
    }
}

/// The MaterialX document behind a stand-in path ([`stand_in`]), `None` for other paths.
pub fn stand_in_source(resolved: &str) -> Option<&str> {
    resolved
        .strip_suffix(STAND_IN_SUFFIX)
        .filter(|p| is_mtlx(p))
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
        let gold = stage.prim("/Gold/mtlxstandard_surface1");
        let color = gold.attribute("inputs:base_color").get::<Value>().unwrap();
        assert!(format!("{color:?}").contains("0.910751"), "{color:?}");
    }
}
