//! Upgrading MaterialX 1.38 documents to 1.39 (MaterialX Specification, "MTLX File Format
//! Definition": "The MaterialX library automatically upgrades older-versioned documents to the
//! current MaterialX version at load time"). The definition followed is MaterialX's own,
//! `Document::upgradeVersion` (`source/MaterialXCore/Version.cpp`, "Upgrade from 1.38 to
//! 1.39", as released in MaterialX 1.39.5, the version `tests/data/mtlx/oracle.py` checks lux
//! against), in its order:
//!
//! 1. **`channels` on a connection** (an input of a node, or a nodegraph output) becomes a
//!    `swizzle` node (named `swizzle`, `swizzle2`, … in its scope, placed before the element
//!    holding the port) reading what the port read, with `in` typed as the upstream node's
//!    type (when there is none or it is `multioutput`: `float` for `xx`/`xxx`/`xxxx`,
//!    `vector3` for `xyz`/`x`/`y`/`z`, `color4` for `rgba`/`a`, else `color4` for a `color3`
//!    port and `color3` otherwise); the port then reads the swizzle node alone. A `float`
//!    port reading a `float` just loses its `channels`.
//! 2. Then every node, in document order:
//!    - **`layer` whose `top` is a `thin_film_bsdf`** (and which has a `base`): every
//!      `dielectric_bsdf`, `conductor_bsdf` and `generalized_schlick_bsdf` upstream of the
//!      layer (through nodegraph connections too), except a dielectric whose `scatter_mode`
//!      is `T`, gets the thin film's `thickness` and `ior` inputs (value or binding, as
//!      authored) as `thinfilm_thickness` and `thinfilm_ior`; the ports reading the layer read
//!      its `base` node instead; the layer and the thin-film node are removed once every node
//!      is done;
//!    - **`subsurface_bsdf` with a `vector3` `radius`**: a `convert` node (`color3`, named
//!      `convert`, `convert2`, …) takes the old `radius` as its `in`, and `radius` becomes a
//!      `color3` reading it;
//!    - **`switch` whose constant `which` is 5 or more** (`integer` or `float`): `which`
//!      becomes 0;
//!    - **`swizzle`** (removed in 1.39), by its `in` type and its own type (each `float`,
//!      `colorN` or `vectorN`; other swizzles stay as they are):
//!      - a constant `in` (or none), or channels that are all `0`/`1`: a `constant` node whose
//!        `value` holds the swizzled channels (a letter picks that channel of `in`'s value, `0`
//!        and `1` are themselves, a missing or unknown channel takes the value's first one);
//!      - one output channel: `extract` with `index` the channel's (none for an unknown
//!        letter);
//!      - `rgb`/`xyz` from 3 or 4 channels, `rgba`/`xyzw` from 4, `rr`/`rrr`/`xx`/`xxx` from a
//!        scalar, between different types: `convert`;
//!      - from a scalar (`rrrr`, `r0r`, …): `combineN` whose `in1`…`inN` read what `in` read
//!        (or hold the `0`/`1` constants);
//!      - otherwise a `separateM` (named `separate`, `separate2`, …, placed before the node)
//!        reading `in`, feeding a `combineN` channel by channel (output `out` + the letter as
//!        written, a constant for `0`/`1`, `outr`/`outx` for a missing or unknown channel);
//!
//!      a `nodedef` string follows the new node (`ND_constant_color3`, `ND_extract_color3`,
//!      `ND_convert_color3_vector3`, `ND_combine3_color3`);
//!    - **`atan2`**: inputs `in1`/`in2` become `iny`/`inx`;
//!    - **`normalmap`**: with `space` = `object`, the node becomes
//!      `normalize(subtract(multiply(in, 2), 1))` (new `multiply` and `subtract` nodes,
//!      `vector3`, scalar second operands; the node's other inputs dropped; `nodedef` →
//!      `ND_normalize_vector3`); otherwise `space` is dropped and, when `normal` or `tangent`
//!      is authored but `bitangent` is not, `bitangent` reads
//!      `normalize(crossproduct(normal, tangent))` (nodes `normalmap_cross`,
//!      `normalmap_cross_norm`; `in1`/`in2` copy `normal`/`tangent` where authored); `nodedef`
//!      `ND_normalmap` → `ND_normalmap_float`.
//!
//! New nodes are named as MaterialX names them (the base name, else with 2, 3, … appended,
//! unique among the scope's children: a nodegraph's nodes, interface inputs and outputs; the
//! document's nodes, nodegraphs, nodedefs, looks and collections), so the upgraded document
//! has MaterialX's node names.
//!
//! Where lux differs: a thin-film layer whose `base` is read through a nodegraph output or an
//! interface input has its ports read that same binding (MaterialX names the node behind it,
//! which is not in the ports' scope); the value of a constant swizzled colour was already
//! converted from its colour space when the document was read ([`super::document`]), so it is
//! swizzled after that conversion, not before.
//!
//! Documents older than 1.38 ([`OLDEST`]) are refused: [`super::parse_document`] returns
//! [`super::MtlxError::Version`] naming the file and the version (inside a USD stage, the
//! layer does not compose and the stage loads with a composition warning). MaterialX's upgrade
//! of them (1.37 → 1.38 and earlier) rewrites `<material>`/`<shaderref>` elements, parameters,
//! `color2` and the 1.37 BSDF nodes, which lux does not implement.

use std::collections::HashSet;

use super::document::{Document, Input, Node};
use crate::shading::{Value, ValueType};

/// The oldest MaterialX version lux reads (upgraded by [`upgrade`]).
pub const OLDEST: (u32, u32) = (1, 38);

/// Upgrades a MaterialX 1.38 document to 1.39 in place (see the module docs);
/// [`Document::version`] keeps the version as authored.
pub fn upgrade(doc: &mut Document) {
    for block in blocks(doc) {
        match block {
            Block::Top(name) => node_channels(doc, Scope::Top, &name),
            Block::Graph(g) => graph_channels(doc, g),
        }
    }
    let mut unused = Vec::new();
    for block in blocks(doc) {
        match block {
            Block::Top(name) => {
                if let Some(ni) = index(doc, Scope::Top, &name) {
                    upgrade_node(doc, Scope::Top, ni, &mut unused);
                }
            }
            Block::Graph(g) => {
                let mut ni = 0;
                while ni < doc.nodegraphs[g].nodes.len() {
                    ni += upgrade_node(doc, Scope::Graph(g), ni, &mut unused) + 1;
                }
            }
        }
    }
    for (scope, name) in unused {
        nodes_mut(doc, scope).retain(|n| n.name != name);
    }
}

/// Where nodes live: the document's top level or a nodegraph (by index).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Scope {
    Top,
    Graph(usize),
}

/// A top-level node (by name: indices shift as nodes are inserted) or a nodegraph, in
/// document order.
enum Block {
    Top(String),
    Graph(usize),
}

/// The document's top-level nodes and nodegraphs in document order (the nodes in their
/// order, each nodegraph before the first node authored after it).
fn blocks(doc: &Document) -> Vec<Block> {
    let mut graphs: Vec<usize> = (0..doc.nodegraphs.len()).collect();
    graphs.sort_by_key(|&g| doc.nodegraphs[g].line);
    let mut graphs = graphs.into_iter().peekable();
    let mut out = Vec::new();
    for n in &doc.nodes {
        while let Some(g) = graphs.next_if(|&g| doc.nodegraphs[g].line < n.line) {
            out.push(Block::Graph(g));
        }
        out.push(Block::Top(n.name.clone()));
    }
    out.extend(graphs.map(Block::Graph));
    out
}

fn nodes(doc: &Document, scope: Scope) -> &Vec<Node> {
    match scope {
        Scope::Top => &doc.nodes,
        Scope::Graph(g) => &doc.nodegraphs[g].nodes,
    }
}

fn nodes_mut(doc: &mut Document, scope: Scope) -> &mut Vec<Node> {
    match scope {
        Scope::Top => &mut doc.nodes,
        Scope::Graph(g) => &mut doc.nodegraphs[g].nodes,
    }
}

fn index(doc: &Document, scope: Scope, name: &str) -> Option<usize> {
    nodes(doc, scope).iter().position(|n| n.name == name)
}

/// A name for a new child of `scope`: `base`, else `base2`, `base3`, … (MaterialX's
/// `createValidChildName`).
fn unique_name(doc: &Document, scope: Scope, base: &str) -> String {
    let mut taken: HashSet<&str> = nodes(doc, scope).iter().map(|n| n.name.as_str()).collect();
    match scope {
        Scope::Top => {
            taken.extend(doc.nodegraphs.iter().map(|g| g.name.as_str()));
            taken.extend(doc.nodedefs.iter().map(|d| d.name.as_str()));
            taken.extend(doc.looks.iter().map(|l| l.name.as_str()));
            taken.extend(doc.collections.iter().map(|c| c.name.as_str()));
        }
        Scope::Graph(g) => {
            let graph = &doc.nodegraphs[g];
            taken.extend(graph.inputs.iter().map(|i| i.name.as_str()));
            taken.extend(graph.outputs.iter().map(|o| o.name.as_str()));
        }
    }
    let mut name = base.to_string();
    let mut k = 2;
    while taken.contains(name.as_str()) {
        name = format!("{base}{k}");
        k += 1;
    }
    name
}

/// The node an input authored in `scope` reads (MaterialX's `Input::getConnectedNode`): through
/// an interface input that is itself connected, through a nodegraph output, or by `nodename`.
fn connected(doc: &Document, scope: Scope, input: &Input) -> Option<(Scope, usize)> {
    if let (Some(iface), Scope::Graph(g)) = (&input.interfacename, scope)
        && let Some(outer) = doc.nodegraphs[g].inputs.iter().find(|i| &i.name == iface)
        && (outer.nodename.is_some() || outer.nodegraph.is_some())
    {
        return connected(doc, Scope::Top, outer);
    }
    if let Some(gname) = &input.nodegraph {
        let g = doc.nodegraphs.iter().position(|g| &g.name == gname)?;
        let out = doc.nodegraphs[g].output(input.output.as_deref())?;
        let inner = Scope::Graph(g);
        return Some((inner, index(doc, inner, out.nodename.as_deref()?)?));
    }
    Some((scope, index(doc, scope, input.nodename.as_deref()?)?))
}

/// The type of what a port with `channels` reads (see the module docs, step 1).
fn upstream_type(
    doc: &Document,
    upstream: Option<(Scope, usize)>,
    port: Option<ValueType>,
    channels: &str,
) -> String {
    let ty = upstream.map_or("", |(s, i)| nodes(doc, s)[i].type_name.as_str());
    if !ty.is_empty() && ty != "multioutput" {
        return ty.to_string();
    }
    match channels {
        "xx" | "xxx" | "xxxx" => "float",
        "xyz" | "x" | "y" | "z" => "vector3",
        "rgba" | "a" => "color4",
        _ if port == Some(ValueType::Color3) => "color4",
        _ => "color3",
    }
    .to_string()
}

/// A swizzle node reading `feed` (the port's binding, typed `upstream`) with `channels`.
fn swizzle_node(name: String, port: Option<ValueType>, mut feed: Input, upstream: &str) -> Node {
    let channels = feed.channels.take().unwrap_or_default();
    feed.name = "in".into();
    feed.ty = ValueType::parse(upstream);
    let line = feed.line;
    Node {
        name,
        category: "swizzle".into(),
        type_name: port.map_or("", ValueType::name).into(),
        ty: port,
        nodedef: None,
        version: None,
        inputs: vec![
            feed,
            Input::constant("channels", ValueType::String, Value::String(channels)),
        ],
        line,
    }
}

/// Step 1 for the inputs of node `name` of `scope`.
fn node_channels(doc: &mut Document, scope: Scope, name: &str) {
    let mut ii = 0;
    while let Some(ni) = index(doc, scope, name)
        && let Some(port) = nodes(doc, scope)[ni].inputs.get(ii)
    {
        ii += 1;
        let Some(channels) = &port.channels else {
            continue;
        };
        let upstream = upstream_type(doc, connected(doc, scope, port), port.ty, channels);
        if upstream == "float" && port.ty == Some(ValueType::Float) {
            nodes_mut(doc, scope)[ni].inputs[ii - 1].channels = None;
            continue;
        }
        let swizzle = swizzle_node(
            unique_name(doc, scope, "swizzle"),
            port.ty,
            port.clone(),
            &upstream,
        );
        let port = &mut nodes_mut(doc, scope)[ni].inputs[ii - 1];
        port.nodename = Some(swizzle.name.clone());
        port.value = None;
        port.nodegraph = None;
        port.output = None;
        port.interfacename = None;
        port.channels = None;
        nodes_mut(doc, scope).insert(ni, swizzle);
    }
}

/// Step 1 for the nodes and outputs of nodegraph `g`, in document order.
fn graph_channels(doc: &mut Document, g: usize) {
    let graph = &doc.nodegraphs[g];
    let mut items: Vec<(u32, Result<String, usize>)> = graph
        .nodes
        .iter()
        .map(|n| (n.line, Ok(n.name.clone())))
        .chain(
            graph
                .outputs
                .iter()
                .enumerate()
                .map(|(o, out)| (out.line, Err(o))),
        )
        .collect();
    items.sort_by_key(|(line, _)| *line);
    let scope = Scope::Graph(g);
    for (_, item) in items {
        let o = match item {
            Ok(name) => {
                node_channels(doc, scope, &name);
                continue;
            }
            Err(o) => o,
        };
        let out = &doc.nodegraphs[g].outputs[o];
        let Some(channels) = &out.channels else {
            continue;
        };
        let upstream_node = out
            .nodename
            .as_deref()
            .and_then(|n| index(doc, scope, n))
            .map(|i| (scope, i));
        let upstream = upstream_type(doc, upstream_node, out.ty, channels);
        if upstream == "float" && out.ty == Some(ValueType::Float) {
            doc.nodegraphs[g].outputs[o].channels = None;
            continue;
        }
        let feed = Input {
            name: "in".into(),
            ty: None,
            value: None,
            nodename: out.nodename.clone(),
            nodegraph: None,
            output: out.output.clone(),
            interfacename: out.interfacename.clone(),
            channels: out.channels.clone(),
            colorspace: String::new(),
            line: out.line,
        };
        let line = out.line;
        let swizzle = swizzle_node(unique_name(doc, scope, "swizzle"), out.ty, feed, &upstream);
        let graph = &mut doc.nodegraphs[g];
        let out = &mut graph.outputs[o];
        out.nodename = Some(swizzle.name.clone());
        out.output = None;
        out.interfacename = None;
        out.channels = None;
        let at = graph
            .nodes
            .iter()
            .position(|n| n.line > line)
            .unwrap_or(graph.nodes.len());
        graph.nodes.insert(at, swizzle);
    }
}

/// Step 2 for node `ni` of `scope`: the number of nodes inserted before it.
fn upgrade_node(
    doc: &mut Document,
    scope: Scope,
    ni: usize,
    unused: &mut Vec<(Scope, String)>,
) -> usize {
    match nodes(doc, scope)[ni].category.as_str() {
        "layer" => thin_film_layer(doc, scope, ni, unused),
        "subsurface_bsdf" => subsurface_radius(doc, scope, ni),
        "switch" => {
            if let Some(which) = nodes_mut(doc, scope)[ni]
                .inputs
                .iter_mut()
                .find(|i| i.name == "which")
                && matches!(which.ty, Some(ValueType::Integer | ValueType::Float))
                && let Some(Value::Numbers(v)) = &mut which.value
                && v.first().is_some_and(|&w| w >= 5.0)
            {
                *v = vec![0.0];
            }
        }
        "swizzle" => return usize::from(swizzle(doc, scope, ni)),
        "atan2" => {
            for i in &mut nodes_mut(doc, scope)[ni].inputs {
                match i.name.as_str() {
                    "in1" => i.name = "iny".into(),
                    "in2" => i.name = "inx".into(),
                    _ => {}
                }
            }
        }
        "normalmap" => normalmap(doc, scope, ni),
        _ => {}
    }
    0
}

/// A port reading a node: `(scope, node, input)` for a node input, `(graph, output)` for a
/// nodegraph output, `(graph, input)` for a nodegraph interface input.
enum Port {
    Input(Scope, usize, usize),
    Output(usize, usize),
    Interface(usize, usize),
}

fn thin_film_layer(doc: &mut Document, scope: Scope, ni: usize, unused: &mut Vec<(Scope, String)>) {
    let layer = &nodes(doc, scope)[ni];
    let (Some(top_in), Some(base_in)) = (layer.input("top"), layer.input("base")) else {
        return;
    };
    let (Some(top), Some(_)) = (
        connected(doc, scope, top_in),
        connected(doc, scope, base_in),
    ) else {
        return;
    };
    let film = &nodes(doc, top.0)[top.1];
    if film.category != "thin_film_bsdf" {
        return;
    }
    let copies: Vec<Input> = [("thickness", "thinfilm_thickness"), ("ior", "thinfilm_ior")]
        .into_iter()
        .filter_map(|(from, to)| {
            let mut i = film.input(from)?.clone();
            i.name = to.into();
            Some(i)
        })
        .collect();
    let base = base_in.clone();
    let dropped = [(scope, layer.name.clone()), (top.0, film.name.clone())];

    // The BSDFs upstream of the layer.
    let mut targets = Vec::new();
    let mut seen = HashSet::new();
    let mut stack = vec![(scope, ni)];
    while let Some((s, n)) = stack.pop() {
        for input in &nodes(doc, s)[n].inputs {
            let Some(up) = connected(doc, s, input) else {
                continue;
            };
            if !seen.insert(up) {
                continue;
            }
            let node = &nodes(doc, up.0)[up.1];
            let transmission = node
                .input("scatter_mode")
                .is_some_and(|m| m.value == Some(Value::String("T".into())));
            if matches!(
                node.category.as_str(),
                "dielectric_bsdf" | "conductor_bsdf" | "generalized_schlick_bsdf"
            ) && !(node.category == "dielectric_bsdf" && transmission)
            {
                targets.push(up);
            }
            stack.push(up);
        }
    }

    // The ports reading the layer (MaterialX's `Node::getDownstreamPorts`).
    let name = layer.name.as_str();
    let reads_layer = |s: Scope, i: &Input| {
        i.nodename.as_deref() == Some(name) && connected(doc, s, i) == Some((scope, ni))
    };
    let mut ports = Vec::new();
    let scopes = std::iter::once(Scope::Top).chain((0..doc.nodegraphs.len()).map(Scope::Graph));
    for s in scopes {
        for (k, node) in nodes(doc, s).iter().enumerate() {
            for (j, i) in node.inputs.iter().enumerate() {
                if reads_layer(s, i) {
                    ports.push(Port::Input(s, k, j));
                }
            }
        }
    }
    for (g, graph) in doc.nodegraphs.iter().enumerate() {
        if scope == Scope::Graph(g) {
            for (o, out) in graph.outputs.iter().enumerate() {
                if out.nodename.as_deref() == Some(name) {
                    ports.push(Port::Output(g, o));
                }
            }
        }
        for (j, i) in graph.inputs.iter().enumerate() {
            if reads_layer(Scope::Top, i) {
                ports.push(Port::Interface(g, j));
            }
        }
    }

    for (s, n) in targets {
        let inputs = &mut nodes_mut(doc, s)[n].inputs;
        for c in &copies {
            match inputs.iter_mut().find(|i| i.name == c.name) {
                Some(i) => *i = c.clone(),
                None => inputs.push(c.clone()),
            }
        }
    }
    // A base read by name: the ports take that name (as MaterialX); read through a nodegraph
    // output or an interface input: the ports take that binding.
    let by_name = base.nodegraph.is_none() && base.interfacename.is_none();
    for port in ports {
        match port {
            Port::Input(s, k, j) => rebind(&mut nodes_mut(doc, s)[k].inputs[j], &base, by_name),
            Port::Interface(g, j) => rebind(&mut doc.nodegraphs[g].inputs[j], &base, by_name),
            Port::Output(g, o) => {
                let out = &mut doc.nodegraphs[g].outputs[o];
                out.nodename = base.nodename.clone();
                if !by_name {
                    out.output = base.output.clone();
                    out.interfacename = base.interfacename.clone();
                }
            }
        }
    }
    unused.extend(dropped);
}

fn rebind(port: &mut Input, base: &Input, by_name: bool) {
    port.nodename = base.nodename.clone();
    if !by_name {
        port.nodegraph = base.nodegraph.clone();
        port.output = base.output.clone();
        port.interfacename = base.interfacename.clone();
    }
}

fn subsurface_radius(doc: &mut Document, scope: Scope, ni: usize) {
    let Some(radius) = nodes(doc, scope)[ni]
        .input("radius")
        .filter(|r| r.ty == Some(ValueType::Vector3))
    else {
        return;
    };
    let convert = Node {
        name: unique_name(doc, scope, "convert"),
        category: "convert".into(),
        type_name: "color3".into(),
        ty: Some(ValueType::Color3),
        nodedef: None,
        version: None,
        inputs: vec![Input {
            name: "in".into(),
            ..radius.clone()
        }],
        line: radius.line,
    };
    let nodes = nodes_mut(doc, scope);
    let radius = nodes[ni]
        .inputs
        .iter_mut()
        .find(|i| i.name == "radius")
        .expect("found above");
    // MaterialX's `Input::setConnectedNode`: the value, interface and nodegraph bindings go.
    radius.ty = Some(ValueType::Color3);
    radius.nodename = Some(convert.name.clone());
    radius.value = None;
    radius.interfacename = None;
    radius.nodegraph = None;
    nodes.push(convert);
}

/// The channels of a swizzle type (`float`, `colorN`, `vectorN`).
fn channel_count(ty: ValueType) -> Option<usize> {
    match ty {
        ValueType::Float => Some(1),
        ValueType::Vector2 => Some(2),
        ValueType::Color3 | ValueType::Vector3 => Some(3),
        ValueType::Color4 | ValueType::Vector4 => Some(4),
        _ => None,
    }
}

fn channel_index(c: u8) -> Option<usize> {
    match c {
        b'r' | b'x' => Some(0),
        b'g' | b'y' => Some(1),
        b'b' | b'z' => Some(2),
        b'a' | b'w' => Some(3),
        _ => None,
    }
}

fn channel_constant(c: u8) -> Option<f64> {
    match c {
        b'0' => Some(0.0),
        b'1' => Some(1.0),
        _ => None,
    }
}

/// What a swizzle becomes (module docs, step 2).
enum SwizzleTo {
    Constant,
    Extract,
    Convert,
    Combine,
    SeparateCombine,
}

/// Rewrites swizzle node `ni` of `scope`; whether a `separateN` node was inserted before it.
fn swizzle(doc: &mut Document, scope: Scope, ni: usize) -> bool {
    let node = &nodes(doc, scope)[ni];
    let src_ty = match node.input("in") {
        Some(i) => i.ty,
        None => Some(ValueType::Float),
    };
    let (Some(src_ty), Some(dst_ty)) = (src_ty, node.ty) else {
        return false;
    };
    let (Some(src_n), Some(dst_n)) = (channel_count(src_ty), channel_count(dst_ty)) else {
        return false;
    };
    let channels = match node.input("channels").and_then(|i| i.value.as_ref()) {
        Some(Value::String(s)) => s.clone().into_bytes(),
        _ => Vec::new(),
    };
    // An `in` both connected and valued: the value goes.
    let mut feed = node.input("in").cloned();
    if let Some(f) = &mut feed
        && (f.nodename.is_some() || f.nodegraph.is_some() || f.interfacename.is_some())
    {
        f.value = None;
    }
    let to = if feed.as_ref().is_none_or(|f| f.value.is_some())
        || (0..dst_n).all(|k| {
            channels
                .get(k)
                .copied()
                .and_then(channel_constant)
                .is_some()
        }) {
        SwizzleTo::Constant
    } else if dst_n == 1 {
        SwizzleTo::Extract
    } else if src_ty != dst_ty
        && matches!(
            (channels.as_slice(), src_n),
            (b"rgb" | b"xyz", 3 | 4)
                | (b"rgba" | b"xyzw", 4)
                | (b"rr" | b"rrr" | b"xx" | b"xxx", 1)
        )
    {
        SwizzleTo::Convert
    } else if src_n == 1 {
        SwizzleTo::Combine
    } else {
        SwizzleTo::SeparateCombine
    };
    let separate =
        matches!(to, SwizzleTo::SeparateCombine).then(|| unique_name(doc, scope, "separate"));

    let node = &mut nodes_mut(doc, scope)[ni];
    let had_nodedef = node.nodedef.is_some();
    node.inputs
        .retain(|i| i.name != "in" && i.name != "channels");
    let float =
        |name: String, v: f64| Input::constant(&name, ValueType::Float, Value::Numbers(vec![v]));
    let (category, nodedef) = match to {
        SwizzleTo::Constant => {
            let tokens = match &feed {
                None => vec![0.0],
                Some(f) => match &f.value {
                    Some(Value::Numbers(v)) => v.clone(),
                    _ => Vec::new(),
                },
            };
            let first = tokens.first().copied().unwrap_or(0.0);
            let value = (0..dst_n)
                .map(|k| match channels.get(k).copied() {
                    Some(c) => channel_index(c)
                        .and_then(|i| tokens.get(i).copied())
                        .or_else(|| channel_constant(c))
                        .unwrap_or(first),
                    None => first,
                })
                .collect();
            node.inputs
                .push(Input::constant("value", dst_ty, Value::Numbers(value)));
            (
                "constant".to_string(),
                format!("ND_constant_{}", dst_ty.name()),
            )
        }
        SwizzleTo::Extract => {
            node.inputs.extend(feed.clone());
            if let Some(i) = channels.first().copied().and_then(channel_index) {
                node.inputs.push(Input::constant(
                    "index",
                    ValueType::Integer,
                    Value::Numbers(vec![i as f64]),
                ));
            }
            (
                "extract".to_string(),
                format!("ND_extract_{}", src_ty.name()),
            )
        }
        SwizzleTo::Convert => {
            node.inputs.extend(feed.clone());
            (
                "convert".to_string(),
                format!("ND_convert_{}_{}", src_ty.name(), dst_ty.name()),
            )
        }
        SwizzleTo::Combine | SwizzleTo::SeparateCombine => {
            let feed = feed.clone().expect("a constant swizzle otherwise");
            let colour = matches!(feed.ty, Some(ValueType::Color3 | ValueType::Color4));
            for k in 0..dst_n {
                let name = format!("in{}", k + 1);
                let c = channels.get(k).copied();
                let input = match (c.and_then(channel_constant), &separate) {
                    (Some(v), _) => float(name, v),
                    (None, None) => Input {
                        name,
                        ..feed.clone()
                    },
                    (None, Some(sep)) => {
                        let out = match c.filter(|&c| channel_index(c).is_some()) {
                            Some(c) => format!("out{}", c as char),
                            None if colour => "outr".into(),
                            None => "outx".into(),
                        };
                        Input::connected(&name, Some(ValueType::Float), sep, Some(&out))
                    }
                };
                node.inputs.push(input);
            }
            (
                format!("combine{dst_n}"),
                format!("ND_combine{dst_n}_{}", dst_ty.name()),
            )
        }
    };
    node.category = category;
    if had_nodedef {
        node.nodedef = Some(nodedef);
    }
    let Some(name) = separate else {
        return false;
    };
    let line = node.line;
    let feed = feed.expect("a constant swizzle otherwise");
    nodes_mut(doc, scope).insert(
        ni,
        Node {
            name,
            category: format!("separate{src_n}"),
            type_name: "multioutput".into(),
            ty: None,
            nodedef: None,
            version: None,
            inputs: vec![feed],
            line,
        },
    );
    true
}

/// A `vector3` node appended to `scope`: its name.
fn push_vector3(
    doc: &mut Document,
    scope: Scope,
    base: &str,
    category: &str,
    inputs: Vec<Input>,
) -> String {
    let name = unique_name(doc, scope, base);
    let line = nodes(doc, scope).last().map_or(0, |n| n.line);
    nodes_mut(doc, scope).push(Node {
        name: name.clone(),
        category: category.into(),
        type_name: "vector3".into(),
        ty: Some(ValueType::Vector3),
        nodedef: None,
        version: None,
        inputs,
        line,
    });
    name
}

fn normalmap(doc: &mut Document, scope: Scope, ni: usize) {
    let node = &nodes(doc, scope)[ni];
    let renamed = |from: &str, to: &str| {
        node.input(from).map(|i| Input {
            name: to.into(),
            ..i.clone()
        })
    };
    let vector3 = Some(ValueType::Vector3);
    let object = node
        .input("space")
        .is_some_and(|s| s.value == Some(Value::String("object".into())));
    if object {
        let mut multiply: Vec<Input> = renamed("in", "in1").into_iter().collect();
        multiply.push(Input::constant(
            "in2",
            ValueType::Float,
            Value::Numbers(vec![2.0]),
        ));
        let multiply = push_vector3(doc, scope, "multiply", "multiply", multiply);
        let subtract = vec![
            Input::connected("in1", vector3, &multiply, None),
            Input::constant("in2", ValueType::Float, Value::Numbers(vec![1.0])),
        ];
        let subtract = push_vector3(doc, scope, "subtract", "subtract", subtract);
        let node = &mut nodes_mut(doc, scope)[ni];
        node.category = "normalize".into();
        node.inputs = vec![Input::connected("in", vector3, &subtract, None)];
        if node.nodedef.is_some() {
            node.nodedef = Some("ND_normalize_vector3".into());
        }
        return;
    }
    let frame = node.input("normal").is_some() || node.input("tangent").is_some();
    let bitangent = if frame && node.input("bitangent").is_none() {
        let cross: Vec<Input> = [renamed("normal", "in1"), renamed("tangent", "in2")]
            .into_iter()
            .flatten()
            .collect();
        let cross = push_vector3(doc, scope, "normalmap_cross", "crossproduct", cross);
        let input = Input::connected("in", vector3, &cross, None);
        let norm = push_vector3(doc, scope, "normalmap_cross_norm", "normalize", vec![input]);
        Some(Input::connected("bitangent", vector3, &norm, None))
    } else {
        None
    };
    let node = &mut nodes_mut(doc, scope)[ni];
    node.inputs.retain(|i| i.name != "space");
    node.inputs.extend(bitangent);
    if node.nodedef.as_deref() == Some("ND_normalmap") {
        node.nodedef = Some("ND_normalmap_float".into());
    }
}
