//! Flattening a [`Network`] against the MaterialX library (see the module docs).
//!
//! MaterialX Specification, "Nodes" (a node's nodedef from its category and types), "Inputs"
//! (unconnected inputs take the nodedef's `value`, else its `defaultgeomprop`), "Custom Node
//! Definition Using Node Graphs" (a node whose nodedef has a nodegraph implementation is that
//! graph, its `interfacename` inputs reading the node's inputs).

use std::collections::HashMap;

use super::{GraphInput, GraphNode, NetSource, Network, ShadingGraph, Source, Value, ValueType};
use crate::mtlx::{Library, NodeDef, NodeGraphDef, library, nodedef_for_usd_id, zero_value};

/// Flattens `network` against the embedded MaterialX library: nodedefs resolved, defaults
/// filled, implementation graphs expanded, nodes topologically sorted (see [`super`]).
///
/// Only what the material's surface reads is kept. An input of closure type (`BSDF`, `EDF`,
/// …) that nothing feeds holds the empty value `Value::Numbers(vec![])` ("no closure"). A node
/// whose nodedef cannot be found, a connection into a cycle, a value of another type than the
/// nodedef's (converted: a single number spread over every channel, else components dropped
/// or zero-filled) and an input the nodedef does not declare each leave a note. A
/// `UsdUVTexture`'s `sourceColorSpace` (`sRGB`, `raw`; `auto` leaves it unstated) becomes its
/// file's colour space (`srgb_texture`, `raw`) when the file states none, and its `wrapS` /
/// `wrapT` tokens the `image` address modes they mean (`repeat` is `periodic`, `black`
/// `constant`, `useMetadata` `periodic`).
pub fn flatten(network: &Network) -> ShadingGraph {
    let mut f = Flattener {
        lib: library(),
        net: network,
        nodes: Vec::new(),
        notes: Vec::new(),
        state: vec![State::Todo; network.nodes.len()],
    };
    let mut graph = ShadingGraph {
        material: network.material.clone(),
        ..ShadingGraph::default()
    };
    let mut surface = None;
    if let Some(c) = &network.surface
        && c.node < network.nodes.len()
    {
        let outs = f.net_outputs(c.node);
        if let Some(def) = f.resolve_net(c.node) {
            graph.model = def.name.clone();
        }
        let pick = outs
            .iter()
            .position(|(n, _)| n == &c.output)
            .or_else(|| (outs.len() == 1).then_some(0));
        if let Some(k) = pick
            && let Src::Node(node, output) = outs[k].1
        {
            surface = Some((node, output));
        }
    }
    // Keep what the surface reads, in creation order (inputs are created before their
    // readers, so every connection already points to an earlier node).
    let mut keep = vec![false; f.nodes.len()];
    if let Some((s, _)) = surface {
        keep[s] = true;
        for i in (0..f.nodes.len()).rev() {
            if keep[i] {
                for inp in &f.nodes[i].inputs {
                    if let Src::Node(n, _) = inp.2 {
                        keep[n] = true;
                    }
                }
            }
        }
    }
    let mut remap = vec![usize::MAX; f.nodes.len()];
    for (i, pn) in f.nodes.into_iter().enumerate() {
        if !keep[i] {
            continue;
        }
        remap[i] = graph.nodes.len();
        graph.nodes.push(GraphNode {
            name: pn.name,
            category: pn.category,
            nodedef: pn.nodedef,
            outputs: pn.outputs,
            inputs: pn
                .inputs
                .into_iter()
                .map(|(name, ty, src)| GraphInput {
                    name,
                    ty,
                    source: match src {
                        Src::Value(v) => Source::Value(v),
                        Src::Geomprop(g) => Source::Geomprop(g),
                        Src::Node(n, o) => Source::Node {
                            node: remap[n],
                            output: o,
                        },
                    },
                })
                .collect(),
        });
    }
    graph.surface = surface.map(|(n, o)| (remap[n], o));
    graph.notes = f.notes;
    graph
}

/// A source while flattening: indices are into [`Flattener::nodes`].
#[derive(Clone, Debug)]
enum Src {
    Value(Value),
    Geomprop(String),
    Node(usize, usize),
}

#[derive(Clone)]
enum State {
    Todo,
    Busy,
    Done(Vec<(String, Src)>),
}

struct PNode {
    name: String,
    category: String,
    nodedef: String,
    outputs: Vec<(String, ValueType)>,
    inputs: Vec<(String, ValueType, Src)>,
}

struct Flattener<'a> {
    lib: &'a Library,
    net: &'a Network,
    nodes: Vec<PNode>,
    notes: Vec<String>,
    state: Vec<State>,
}

/// The default of a nodedef input: its `value`, else its `defaultgeomprop`, else MaterialX's
/// zero value (empty for closures).
fn default_src(lib_input: &crate::mtlx::DefInput) -> Src {
    if let Some(v) = &lib_input.default {
        return Src::Value(v.clone());
    }
    if let Some(g) = &lib_input.defaultgeomprop {
        return Src::Geomprop(g.clone());
    }
    Src::Value(zero_value(lib_input.ty).unwrap_or(Value::Numbers(Vec::new())))
}

/// `value` (authored as `from`) as a value of type `to`.
fn convert(value: &Value, to: ValueType) -> Value {
    match (value, to) {
        (Value::String(s), ValueType::Filename) => zero_file(s),
        (Value::File(f), ValueType::String) => Value::String(f.asset.authored.clone()),
        (Value::Numbers(v), _) if to.components() > 0 => {
            let n = to.components();
            if v.len() == 1 {
                Value::Numbers(vec![v[0]; n])
            } else {
                let mut out: Vec<f64> = v.iter().copied().take(n).collect();
                while out.len() < n {
                    // Alpha of a colour4 (and w) made from three channels is opaque.
                    out.push(if out.len() == 3 { 1.0 } else { 0.0 });
                }
                Value::Numbers(out)
            }
        }
        _ => value.clone(),
    }
}

fn zero_file(s: &str) -> Value {
    Value::File(super::FileValue {
        asset: crate::reader::AssetRef {
            authored: s.to_string(),
            resolved: None,
        },
        colorspace: String::new(),
    })
}

fn value_fits(value: &Value, ty: ValueType) -> bool {
    match value {
        Value::Numbers(v) => v.len() == ty.components() && ty.components() > 0,
        Value::String(_) => ty == ValueType::String,
        Value::File(_) => ty == ValueType::Filename,
    }
}

impl<'a> Flattener<'a> {
    fn resolve_net(&self, i: usize) -> Option<&'a NodeDef> {
        let node = &self.net.nodes[i];
        if let Some(nd) = &node.nodedef {
            return self
                .lib
                .nodedef(nd)
                .or_else(|| nodedef_for_usd_id(nd).and_then(|n| self.lib.nodedef(n)));
        }
        if node.category.is_empty() {
            return None;
        }
        self.lib
            .resolve(&node.category, node.ty, &node.input_types())
    }

    /// The outputs (name, source) of network node `i`, flattening it on first use.
    fn net_outputs(&mut self, i: usize) -> Vec<(String, Src)> {
        match &self.state[i] {
            State::Done(o) => return o.clone(),
            State::Busy => {
                self.notes.push(format!(
                    "{}: part of a connection cycle in {}; the input closing it takes its default",
                    self.net.nodes[i].name, self.net.material
                ));
                return Vec::new();
            }
            State::Todo => {}
        }
        self.state[i] = State::Busy;
        let net = self.net;
        let node = &net.nodes[i];
        let Some(def) = self.resolve_net(i) else {
            let what = node.nodedef.clone().unwrap_or_else(|| {
                format!(
                    "category \"{}\" of type {}",
                    node.category,
                    node.ty.map_or("multioutput", |t| t.name())
                )
            });
            self.notes.push(format!(
                "{}: no MaterialX nodedef for {what} in {}; what it feeds takes its defaults",
                node.name, net.material
            ));
            self.state[i] = State::Done(Vec::new());
            return Vec::new();
        };
        // UsdUVTexture's `sourceColorSpace` (no MaterialX input) is its file's colour space.
        let source_colorspace = node
            .inputs
            .iter()
            .find(|a| a.name == "sourceColorSpace")
            .and_then(|a| match &a.source {
                NetSource::Value(Value::String(s)) => match s.as_str() {
                    "sRGB" => Some("srgb_texture"),
                    "raw" => Some("raw"),
                    _ => None,
                },
                _ => None,
            });
        for a in &node.inputs {
            if a.name == "sourceColorSpace" && def.category == "UsdUVTexture" {
                continue;
            }
            if def.input(&a.name).is_none() {
                self.notes.push(format!(
                    "{}: input \"{}\" is not an input of {} (ignored)",
                    node.name, a.name, def.name
                ));
            }
        }
        let mut inputs = Vec::with_capacity(def.inputs.len());
        for d in &def.inputs {
            let src = match node.inputs.iter().find(|a| a.name == d.name) {
                None => default_src(d),
                Some(a) => match &a.source {
                    NetSource::Value(v) => {
                        // A colour authored as a vector of as many components (USD's
                        // float4 for UsdUVTexture's color4 `scale`) is the same value.
                        let same = |t: ValueType| {
                            t == d.ty
                                || (t.components() == d.ty.components()
                                    && matches!(
                                        (t, d.ty),
                                        (ValueType::Vector3, ValueType::Color3)
                                            | (ValueType::Color3, ValueType::Vector3)
                                            | (ValueType::Vector4, ValueType::Color4)
                                            | (ValueType::Color4, ValueType::Vector4)
                                    ))
                        };
                        if !value_fits(v, d.ty) || a.ty.is_some_and(|t| !same(t)) {
                            self.notes.push(format!(
                                "{}: input \"{}\" authored as {} but {} declares {}; converted",
                                node.name,
                                d.name,
                                a.ty.map_or("another type", |t| t.name()),
                                def.name,
                                d.ty.name()
                            ));
                            Src::Value(convert(v, d.ty))
                        } else if def.category == "UsdUVTexture"
                            && (d.name == "wrapS" || d.name == "wrapT")
                            && let Value::String(token) = v
                        {
                            Src::Value(Value::String(wrap_address_mode(token).into()))
                        } else {
                            Src::Value(v.clone())
                        }
                    }
                    NetSource::Connection(c) if c.node < net.nodes.len() => {
                        let outs = self.net_outputs(c.node);
                        let k = outs
                            .iter()
                            .position(|(n, _)| n == &c.output)
                            .or_else(|| (outs.len() == 1).then_some(0));
                        match k {
                            Some(k) => outs[k].1.clone(),
                            None => {
                                if !outs.is_empty() {
                                    self.notes.push(format!(
                                        "{}: input \"{}\" connects to missing output \"{}\" of {}; default used",
                                        node.name, d.name, c.output, net.nodes[c.node].name
                                    ));
                                }
                                default_src(d)
                            }
                        }
                    }
                    NetSource::Connection(_) => default_src(d),
                },
            };
            inputs.push(src);
        }
        if let Some(cs) = source_colorspace {
            for src in &mut inputs {
                if let Src::Value(Value::File(f)) = src
                    && f.colorspace.is_empty()
                {
                    f.colorspace = cs.to_string();
                }
            }
        }
        let outs = self.instantiate(def, inputs, &node.name, 0);
        self.state[i] = State::Done(outs.clone());
        outs
    }

    /// Creates a node of nodedef `def` reading `inputs` (one per nodedef input): itself when
    /// it has no implementation graph, else that graph's nodes, recursively.
    fn instantiate(
        &mut self,
        def: &'a NodeDef,
        inputs: Vec<Src>,
        name: &str,
        depth: usize,
    ) -> Vec<(String, Src)> {
        let graph = if depth < 32 {
            self.lib.implementation(&def.name)
        } else {
            None
        };
        let Some(graph) = graph else {
            let idx = self.nodes.len();
            self.nodes.push(PNode {
                name: name.to_string(),
                category: def.category.clone(),
                nodedef: def.name.clone(),
                outputs: def.outputs.clone(),
                inputs: def
                    .inputs
                    .iter()
                    .zip(inputs)
                    .map(|(d, s)| (d.name.clone(), d.ty, s))
                    .collect(),
            });
            return def
                .outputs
                .iter()
                .enumerate()
                .map(|(k, (n, _))| (n.clone(), Src::Node(idx, k)))
                .collect();
        };
        let mut scope = GraphScope {
            graph,
            def,
            inputs,
            prefix: format!("{name}/{}", graph.name),
            memo: HashMap::new(),
            depth,
        };
        let mut outs = Vec::new();
        for (k, (oname, _)) in def.outputs.iter().enumerate() {
            let gout = graph.output(Some(oname)).or_else(|| {
                (def.outputs.len() == 1)
                    .then(|| graph.output(None))
                    .flatten()
            });
            let src = match gout {
                Some(o) => {
                    if let Some(iface) = &o.interfacename {
                        scope.interface(iface)
                    } else if let Some(n) = &o.nodename {
                        self.inner_output(&mut scope, n, o.output.as_deref())
                    } else {
                        None
                    }
                }
                None => None,
            };
            let src = src.unwrap_or_else(|| {
                Src::Value(zero_value(def.outputs[k].1).unwrap_or(Value::Numbers(Vec::new())))
            });
            outs.push((oname.clone(), src));
        }
        outs
    }

    fn inner_output(
        &mut self,
        scope: &mut GraphScope<'a>,
        node: &str,
        output: Option<&str>,
    ) -> Option<Src> {
        let outs = self.inner_node(scope, node);
        let k = match output {
            Some(o) => outs.iter().position(|(n, _)| n == o),
            None => None,
        }
        .or_else(|| (!outs.is_empty()).then_some(0))?;
        Some(outs[k].1.clone())
    }

    fn inner_node(&mut self, scope: &mut GraphScope<'a>, name: &str) -> Vec<(String, Src)> {
        match scope.memo.get(name) {
            Some(Some(o)) => return o.clone(),
            Some(None) => {
                self.notes.push(format!(
                    "{}/{name}: part of a connection cycle in {}",
                    scope.prefix, self.net.material
                ));
                return Vec::new();
            }
            None => {}
        }
        scope.memo.insert(name.to_string(), None);
        let graph = scope.graph;
        let Some(node) = graph.node(name) else {
            self.notes.push(format!(
                "{}: no node \"{name}\" in {}",
                scope.prefix, graph.name
            ));
            scope.memo.insert(name.to_string(), Some(Vec::new()));
            return Vec::new();
        };
        let def = match &node.nodedef {
            Some(nd) => self.lib.nodedef(nd),
            None => self
                .lib
                .resolve(&node.category, node.ty, &node.input_types()),
        };
        let Some(def) = def else {
            self.notes.push(format!(
                "{}/{name}: no MaterialX nodedef for category \"{}\" in {}",
                scope.prefix, node.category, self.net.material
            ));
            scope.memo.insert(name.to_string(), Some(Vec::new()));
            return Vec::new();
        };
        let mut inputs = Vec::with_capacity(def.inputs.len());
        for d in &def.inputs {
            let src = match node.input(&d.name) {
                None => None,
                Some(a) => {
                    if let Some(iface) = &a.interfacename {
                        scope.interface(iface)
                    } else if let Some(n) = &a.nodename {
                        self.inner_output(scope, n, a.output.as_deref())
                    } else {
                        a.value.clone().map(|v| {
                            if value_fits(&v, d.ty) {
                                Src::Value(v)
                            } else {
                                Src::Value(convert(&v, d.ty))
                            }
                        })
                    }
                }
            };
            inputs.push(src.unwrap_or_else(|| default_src(d)));
        }
        let path = format!("{}/{}", scope.prefix, name);
        let outs = self.instantiate(def, inputs, &path, scope.depth + 1);
        scope.memo.insert(name.to_string(), Some(outs.clone()));
        outs
    }
}

/// One expansion of an implementation graph.
struct GraphScope<'a> {
    graph: &'a NodeGraphDef,
    def: &'a NodeDef,
    inputs: Vec<Src>,
    prefix: String,
    /// Inner node name → its outputs (`None` while being flattened: a cycle).
    memo: HashMap<String, Option<Vec<(String, Src)>>>,
    depth: usize,
}

impl GraphScope<'_> {
    fn interface(&self, name: &str) -> Option<Src> {
        let k = self.def.inputs.iter().position(|i| i.name == name)?;
        Some(self.inputs[k].clone())
    }
}

/// The MaterialX `image` address mode (`uaddressmode`, `vaddressmode`: `constant`, `clamp`,
/// `periodic`, `mirror`) that a `UsdUVTexture` `wrapS` / `wrapT` token means, as the
/// `IMP_UsdUVTexture` nodegraph passes it on: UsdPreviewSurface's `repeat` is `periodic`,
/// `black` (the nodedef's first enum value) `constant` (the texture's `fallback` outside the
/// image), `useMetadata` `periodic` (lux's readers carry no wrap metadata: `repeat`, as the
/// USD-side inputs read it); `clamp`, `mirror` and the MaterialX names themselves stay. An
/// unknown token stays too (the graph's compiler names it).
fn wrap_address_mode(token: &str) -> &str {
    match token {
        "repeat" | "useMetadata" => "periodic",
        "black" => "constant",
        other => other,
    }
}
