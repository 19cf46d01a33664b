//! MaterialX documents, the embedded library and flattening, checked against MaterialX 1.39.5
//! itself (`tests/data/mtlx/oracle.py` → `oracle.json`).

use std::path::{Path, PathBuf};

use lux_usd::mtlx::{MtlxError, library, parse_document, read_document};
use lux_usd::reader::AssetRef;
use lux_usd::shading::{
    Connection, FileValue, GraphNode, NetInput, NetNode, NetSource, Network, ShadingGraph, Source,
    Value, ValueType, flatten,
};
use serde_json::Value as Json;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/mtlx")
        .join(name)
}

fn oracle() -> Json {
    let text = std::fs::read_to_string(data("oracle.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

fn numbers(j: &Json) -> Vec<f64> {
    j.as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect()
}

fn close(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| (x - y).abs() <= 1e-6 * (1.0 + y.abs()))
}

#[test]
fn every_nodedef_matches_materialx() {
    let oracle = oracle();
    let lib = library();
    let defs = oracle["nodedefs"].as_object().unwrap();
    let mut checked = 0;
    for (name, o) in defs {
        let outputs: Vec<(&str, &str)> = o["outputs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| (p[0].as_str().unwrap(), p[1].as_str().unwrap()))
            .collect();
        let def = lib
            .nodedef(name)
            .unwrap_or_else(|| panic!("{name} missing"));
        assert_eq!(def.category, o["node"].as_str().unwrap(), "{name}");
        // Ports of types lux does not model (`lightshader`) are left out.
        let want_out: Vec<(&str, &str)> = outputs
            .into_iter()
            .filter(|(_, t)| ValueType::parse(t).is_some())
            .collect();
        let got_out: Vec<(&str, &str)> = def
            .outputs
            .iter()
            .map(|(n, t)| (n.as_str(), t.name()))
            .collect();
        assert_eq!(got_out, want_out, "{name} outputs");
        // Each output's fallback where the node is not evaluated: `defaultinput`, `default`.
        for p in o["outputs"].as_array().unwrap() {
            let oname = p[0].as_str().unwrap();
            if ValueType::parse(p[1].as_str().unwrap()).is_none() {
                continue;
            }
            let got = def.output_fallback(oname);
            match (p[2].as_str(), p[3].as_str()) {
                (_, Some(input)) => assert_eq!(
                    got,
                    Some(&lux_usd::mtlx::OutputFallback::Input(input.to_string())),
                    "{name}.{oname} defaultinput"
                ),
                (Some(""), None) => assert!(
                    matches!(
                        got,
                        Some(lux_usd::mtlx::OutputFallback::Value(
                            Value::String(_) | Value::File(_)
                        ))
                    ),
                    "{name}.{oname} empty default: {got:?}"
                ),
                (Some(text), None) if text.starts_with(|c: char| c.is_ascii_uppercase()) => {
                    assert_eq!(
                        got,
                        Some(&lux_usd::mtlx::OutputFallback::Geomprop(text.to_string())),
                        "{name}.{oname} default"
                    )
                }
                (Some(text), None) => {
                    let want: Vec<f64> = text
                        .split(',')
                        .map(|x| match x.trim() {
                            "true" => 1.0,
                            "false" => 0.0,
                            x => x.parse::<f64>().unwrap(),
                        })
                        .collect();
                    match got {
                        Some(lux_usd::mtlx::OutputFallback::Value(Value::Numbers(v))) => {
                            assert!(close(v, &want), "{name}.{oname} default {v:?} vs {want:?}")
                        }
                        other => panic!("{name}.{oname} default {text}: {other:?}"),
                    }
                }
                (None, None) => assert_eq!(got, None, "{name}.{oname}"),
            }
        }
        let want_in: Vec<&Json> = o["inputs"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|i| ValueType::parse(i["type"].as_str().unwrap()).is_some())
            .collect();
        assert_eq!(def.inputs.len(), want_in.len(), "{name} inputs");
        for (got, want) in def.inputs.iter().zip(want_in) {
            let at = format!("{name}.{}", got.name);
            assert_eq!(got.name, want["name"].as_str().unwrap(), "{at}");
            assert_eq!(got.ty.name(), want["type"].as_str().unwrap(), "{at}");
            assert_eq!(got.uniform, want["uniform"].as_bool().unwrap(), "{at}");
            assert_eq!(
                got.defaultgeomprop.as_deref(),
                want["defaultgeomprop"].as_str(),
                "{at}"
            );
            match (&got.default, &want["value"]) {
                (None, Json::Null) => {}
                (Some(Value::Numbers(v)), w @ Json::Array(_)) => {
                    assert!(close(v, &numbers(w)), "{at}: {v:?} vs {w}")
                }
                (Some(Value::String(s)), Json::String(w)) => assert_eq!(s, w, "{at}"),
                (Some(Value::File(f)), Json::String(w)) => {
                    assert_eq!(&f.asset.authored, w, "{at}")
                }
                (g, w) => panic!("{at}: {g:?} vs {w}"),
            }
        }
        let implementation = lib.implementation(name).map(|g| g.name.as_str());
        assert_eq!(implementation, o["implementation"].as_str(), "{name}");
        checked += 1;
    }
    assert_eq!(checked, lib.nodedefs().len());
    assert!(checked > 700);
}

#[test]
fn resolve_agrees_with_materialx() {
    let oracle = oracle();
    let lib = library();
    let mut checked = 0;
    for r in oracle["resolve"].as_array().unwrap() {
        let inputs: Vec<(&str, ValueType)> = r["inputs"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|p| Some((p[0].as_str()?, ValueType::parse(p[1].as_str()?)?)))
            .collect();
        // Nodedefs declared in a test document itself are not the library's.
        if r["nodedef"]
            .as_str()
            .is_some_and(|n| lib.nodedef(n).is_none())
        {
            continue;
        }
        let ty = ValueType::parse(r["type"].as_str().unwrap());
        let got = lib
            .resolve_version(
                r["category"].as_str().unwrap(),
                ty,
                &inputs,
                r["version"].as_str(),
            )
            .map(|d| d.name.as_str());
        assert_eq!(got, r["nodedef"].as_str(), "{} {}", r["where"], r["name"]);
        checked += 1;
    }
    assert!(checked > 200);
}

#[test]
fn usd_ids_name_library_nodedefs() {
    let lib = library();
    for id in [
        "UsdPreviewSurface",
        "UsdUVTexture",
        "UsdTransform2d",
        "UsdPrimvarReader_float",
        "UsdPrimvarReader_float2",
        "UsdPrimvarReader_float3",
        "UsdPrimvarReader_float4",
        "UsdPrimvarReader_int",
        "UsdPrimvarReader_normal",
        "UsdPrimvarReader_point",
        "UsdPrimvarReader_vector",
        "UsdPrimvarReader_string",
    ] {
        let nd = lux_usd::mtlx::nodedef_for_usd_id(id).unwrap();
        assert!(lib.nodedef(nd).is_some(), "{id} → {nd}");
    }
    assert_eq!(
        lux_usd::mtlx::nodedef_for_usd_id("UsdPrimvarReader_float2"),
        Some("ND_UsdPrimvarReader_vector2")
    );
    assert_eq!(lux_usd::mtlx::nodedef_for_usd_id("ND_image_color3"), None);
}

fn flat(file: &str, material: &str) -> ShadingGraph {
    let doc = read_document(&data(file)).unwrap();
    let net = doc.network(material).unwrap();
    flatten(&net)
}

/// The names of a network's nodes, in order.
fn node_names(net: &Network) -> Vec<&str> {
    net.nodes.iter().map(|n| n.name.as_str()).collect()
}

/// The node feeding input `input` of `node`, and which of its outputs.
fn upstream<'g>(g: &'g ShadingGraph, node: &GraphNode, input: &str) -> (&'g GraphNode, usize) {
    match &node.input(input).unwrap().source {
        Source::Node { node, output } => (&g.nodes[*node], *output),
        s => panic!("{}.{input} is {s:?}", node.name),
    }
}

fn value(node: &GraphNode, input: &str) -> Vec<f64> {
    match &node.input(input).unwrap().source {
        Source::Value(Value::Numbers(v)) => v.clone(),
        s => panic!("{}.{input} is {s:?}", node.name),
    }
}

fn check_sorted(g: &ShadingGraph) {
    for (i, n) in g.nodes.iter().enumerate() {
        assert!(
            lux_usd::mtlx::library()
                .implementation(&n.nodedef)
                .is_none(),
            "{} still has a graph implementation",
            n.nodedef
        );
        for inp in &n.inputs {
            if let Source::Node { node, output } = inp.source {
                assert!(node < i, "{}.{} reads a later node", n.name, inp.name);
                assert!(output < g.nodes[node].outputs.len());
                assert_eq!(
                    g.nodes[node].outputs[output].1, inp.ty,
                    "{}.{}",
                    n.name, inp.name
                );
            }
        }
    }
}

#[test]
fn gold_conductor_reads_the_authored_base_color() {
    let g = flat("gold.mtlx", "gold");
    assert_eq!(g.notes, Vec::<String>::new());
    assert_eq!(g.model, "ND_standard_surface_surfaceshader");
    assert_eq!(g.material, "gold.mtlx:/gold");
    check_sorted(&g);
    let (s, o) = g.surface.unwrap();
    assert_eq!(g.nodes[s].category, "surface");
    assert_eq!(g.nodes[s].outputs[o].1, ValueType::SurfaceShader);
    let metal = g
        .nodes
        .iter()
        .find(|n| n.category == "conductor_bsdf")
        .unwrap();
    assert_eq!(
        metal.name,
        "gold.mtlx:/mtlxstandard_surface1/NG_standard_surface_surfaceshader_100/metal_bsdf"
    );
    let (ior, out) = upstream(&g, metal, "ior");
    assert_eq!(ior.category, "artistic_ior");
    assert_eq!(ior.outputs[out].0, "ior");
    let (refl, _) = upstream(&g, ior, "reflectivity");
    assert_eq!(refl.nodedef, "ND_multiply_color3FA");
    assert!(close(&value(refl, "in1"), &[0.910751, 0.793992, 0.405919]));
    assert!(close(&value(refl, "in2"), &[1.0]));
    let (edge, _) = upstream(&g, ior, "edge_color");
    assert!(close(&value(edge, "in1"), &[0.995348, 0.983757, 0.765725]));
    // The roughness helper reads the authored specular_roughness; the unconnected normal
    // reads the nodedef's defaultgeomprop.
    let (rough, _) = upstream(&g, metal, "roughness");
    assert_eq!(rough.category, "roughness_anisotropy");
    let (mix, _) = upstream(&g, rough, "roughness");
    assert_eq!(mix.nodedef, "ND_mix_float");
    assert!(close(&value(mix, "bg"), &[0.01]));
    assert!(close(&value(mix, "fg"), &[1.0]));
    assert_eq!(
        metal.input("normal").unwrap().source,
        Source::Geomprop("Nworld".into())
    );
}

#[test]
fn every_example_material_flattens() {
    for (file, material, model) in [
        (
            "bubblegum.mtlx",
            "bubblegum",
            "ND_standard_surface_surfaceshader",
        ),
        ("glass.mtlx", "glass", "ND_standard_surface_surfaceshader"),
        (
            "plastic.mtlx",
            "plastic",
            "ND_standard_surface_surfaceshader",
        ),
        (
            "bubblegum_openpbr.mtlx",
            "bubblegum",
            "ND_open_pbr_surface_surfaceshader",
        ),
        (
            "glass_openpbr.mtlx",
            "glass",
            "ND_open_pbr_surface_surfaceshader",
        ),
        (
            "gold_openpbr.mtlx",
            "gold",
            "ND_open_pbr_surface_surfaceshader",
        ),
        (
            "plastic_openpbr.mtlx",
            "plastic",
            "ND_open_pbr_surface_surfaceshader",
        ),
    ] {
        let g = flat(file, material);
        assert_eq!(g.model, model, "{file}");
        assert_eq!(g.notes, Vec::<String>::new(), "{file}");
        assert!(g.surface.is_some(), "{file}");
        check_sorted(&g);
        assert!(
            g.nodes.iter().any(|n| n.category == "dielectric_bsdf"),
            "{file}"
        );
    }
}

#[test]
fn nodegraphs_fileprefix_colorspace_and_looks() {
    let doc = read_document(&data("graph.mtlx")).unwrap();
    assert_eq!(doc.version, (1, 39));
    assert_eq!(doc.colorspace, "lin_rec709");
    assert_eq!(doc.materials(), vec!["M_wood", "M_preview"]);
    let look = &doc.looks[0];
    assert_eq!(look.name, "L_default");
    assert_eq!(look.assigns[0].material, "M_wood");
    assert_eq!(
        look.assigns[0].geom.as_deref(),
        Some("/World/Table,/World/Chair")
    );
    assert_eq!(look.assigns[1].collection.as_deref(), Some("C_props"));

    let net = doc.network("M_wood").unwrap();
    assert_eq!(
        node_names(&net),
        [
            "graph.mtlx:/SR_wood",
            "graph.mtlx:/NG_wood/tinted",
            "graph.mtlx:/NG_wood/grain",
            "graph.mtlx:/NG_wood/uv_scaled",
            "graph.mtlx:/NG_wood/uv",
            "graph.mtlx:/NG_wood/rough_map",
        ]
    );
    let g = flatten(&net);
    assert_eq!(g.notes, Vec::<String>::new());
    check_sorted(&g);
    let image = |name: &str| {
        g.nodes
            .iter()
            .find(|n| n.name == format!("graph.mtlx:/NG_wood/{name}"))
            .unwrap()
    };
    let grain = image("grain");
    assert_eq!(grain.nodedef, "ND_image_color3");
    let Source::Value(Value::File(f)) = &grain.input("file").unwrap().source else {
        panic!()
    };
    assert_eq!(f.asset.authored, "textures/wood.ppm");
    assert_eq!(f.asset.resolved, Some(data("textures/wood.ppm")));
    assert_eq!(f.colorspace, "srgb_texture");
    let rough = image("rough_map");
    let Source::Value(Value::File(f)) = &rough.input("file").unwrap().source else {
        panic!()
    };
    assert_eq!(f.asset.authored, "textures/wood_rough.png");
    assert_eq!(f.asset.resolved, None);
    assert_eq!(f.colorspace, "raw");
    // The interface input's value reaches the inner multiply; texcoord's default geomprop.
    let (scaled, _) = upstream(&g, grain, "texcoord");
    assert!(close(&value(scaled, "in2"), &[2.0, 2.0]));
    let (uv, _) = upstream(&g, scaled, "in1");
    assert_eq!(uv.category, "texcoord");
    // The tint is a colour inside NG_wood, whose colorspace is srgb_texture (MaterialX 1.39.5:
    // `getActiveColorSpace()` of NG_wood's `tint` is "srgb_texture"): converted to lin_rec709.
    let tinted = image("tinted");
    let srgb = lux_usd::shading::color_space::srgb_to_linear;
    assert!(close(
        &value(tinted, "in2"),
        &[srgb(0.9), srgb(0.6), srgb(0.3)]
    ));

    // UsdPreviewSurface through its library graph; the input's own empty fileprefix wins.
    let g = flatten(&doc.network("M_preview").unwrap());
    assert_eq!(g.model, "ND_UsdPreviewSurface_surfaceshader");
    assert_eq!(g.notes, Vec::<String>::new());
    check_sorted(&g);
    let img = g.nodes.iter().find(|n| n.category == "image").unwrap();
    assert_eq!(img.nodedef, "ND_image_color4");
    let Source::Value(Value::File(f)) = &img.input("file").unwrap().source else {
        panic!()
    };
    assert_eq!(f.asset.authored, "wood.ppm");
    assert_eq!(
        img.input("texcoord").unwrap().source,
        Source::Geomprop("UV0".into())
    );
}

/// An upgraded node's input (or a nodegraph output) against MaterialX's (`oracle.json`): type,
/// value and bindings.
fn check_port(
    at: &str,
    want: &Json,
    ty: Option<ValueType>,
    value: Option<&Value>,
    bindings: [Option<&str>; 4],
) {
    assert_eq!(ty.map(|t| t.name()), want["type"].as_str(), "{at}");
    let want_value = want["value"]
        .as_str()
        .map(|v| lux_usd::mtlx::parse_value(ty.unwrap(), v).unwrap());
    match (value, &want_value) {
        (Some(Value::Numbers(a)), Some(Value::Numbers(b))) => {
            assert!(close(a, b), "{at}: {a:?} {b:?}")
        }
        _ => assert_eq!(value, want_value.as_ref(), "{at}"),
    }
    for (k, key) in ["nodename", "nodegraph", "output", "interfacename"]
        .iter()
        .enumerate()
    {
        assert_eq!(bindings[k], want[key].as_str(), "{at}.{key}");
    }
}

/// Nodes of one scope of an upgraded document against MaterialX's (`oracle.json`): the same
/// names, categories, types, nodedef strings and inputs.
fn check_nodes(at: &str, nodes: &[lux_usd::mtlx::Node], want: &Json) {
    let want = want.as_array().unwrap();
    let names = |it: &mut dyn Iterator<Item = String>| {
        let mut v: Vec<String> = it.collect();
        v.sort();
        v
    };
    assert_eq!(
        names(&mut nodes.iter().map(|n| n.name.clone())),
        names(&mut want.iter().map(|w| w["name"].as_str().unwrap().to_string())),
        "{at}"
    );
    for w in want {
        let name = w["name"].as_str().unwrap();
        let node = nodes.iter().find(|n| n.name == name).unwrap();
        let at = format!("{at}/{name}");
        assert_eq!(node.category, w["category"].as_str().unwrap(), "{at}");
        assert_eq!(node.type_name, w["type"].as_str().unwrap(), "{at}");
        assert_eq!(node.nodedef.as_deref(), w["nodedef"].as_str(), "{at}");
        let wi = w["inputs"].as_array().unwrap();
        assert_eq!(node.inputs.len(), wi.len(), "{at}: {:?}", node.inputs);
        for i in wi {
            let iname = i["name"].as_str().unwrap();
            let got = node.input(iname).unwrap_or_else(|| panic!("{at}.{iname}"));
            check_port(
                &format!("{at}.{iname}"),
                i,
                got.ty,
                got.value.as_ref(),
                [
                    got.nodename.as_deref(),
                    got.nodegraph.as_deref(),
                    got.output.as_deref(),
                    got.interfacename.as_deref(),
                ],
            );
        }
    }
}

/// Input `input` of node `node` among the oracle's upgraded `nodes`.
fn oracle_input<'j>(nodes: &'j Json, node: &str, input: &str) -> &'j Json {
    let node = nodes.as_array().unwrap().iter().find(|n| n["name"] == node);
    let inputs = node.unwrap()["inputs"].as_array().unwrap();
    inputs.iter().find(|i| i["name"] == input).unwrap()
}

/// Where lux's upgrade knowingly differs from MaterialX's (`mtlx/upgrade.rs` docs): a port that
/// read a thin-film layer whose base is behind a nodegraph output. MaterialX gives it the name
/// of the node behind that output, which is not in the port's scope; lux gives it the base's
/// binding, which leads to that same node. (file, node, input).
const UPGRADE_DIFFERS: &[(&str, &str, &str)] = &[("upgrade_138_pbr.mtlx", "surf7", "bsdf")];

#[test]
fn a_138_document_is_upgraded_as_materialx_does() {
    let oracle = oracle();
    let upgraded = oracle["upgraded"].as_object().unwrap();
    assert_eq!(upgraded.len(), 3);
    for (file, want) in upgraded {
        let mut doc = read_document(&data(file)).unwrap();
        assert_eq!(doc.version, (1, 38));
        assert_eq!(want["version"], "1.39");
        for &(f, node, input) in UPGRADE_DIFFERS.iter().filter(|d| d.0 == file) {
            // The oracle's nodename is the node behind the nodegraph output lux's port reads.
            let want_node = oracle_input(&want["nodes"], node, input)["nodename"]
                .as_str()
                .unwrap();
            let port = doc
                .nodes
                .iter_mut()
                .find(|n| n.name == node)
                .unwrap()
                .inputs
                .iter_mut()
                .find(|i| i.name == input)
                .unwrap();
            let graph = want["nodegraphs"][port.nodegraph.as_deref().unwrap()]["outputs"]
                .as_array()
                .unwrap()
                .iter()
                .find(|o| o["name"].as_str() == port.output.as_deref())
                .unwrap();
            assert_eq!(
                graph["nodename"].as_str(),
                Some(want_node),
                "{f}: {node}.{input}"
            );
            assert_eq!(port.nodename, None, "{f}: {node}.{input}");
            // The rest of the comparison sees the port as MaterialX writes it.
            port.nodename = Some(want_node.to_string());
            port.nodegraph = None;
            port.output = None;
        }
        check_nodes(file, &doc.nodes, &want["nodes"]);
        let graphs = want["nodegraphs"].as_object().unwrap();
        assert_eq!(doc.nodegraphs.len(), graphs.len(), "{file}");
        for (gname, w) in graphs {
            let graph = doc.nodegraph(gname).unwrap();
            let at = format!("{file}:{gname}");
            check_nodes(&at, &graph.nodes, &w["nodes"]);
            let wo = w["outputs"].as_array().unwrap();
            assert_eq!(graph.outputs.len(), wo.len(), "{at}");
            for (o, want) in graph.outputs.iter().zip(wo) {
                assert_eq!(o.name, want["name"].as_str().unwrap(), "{at}");
                assert_eq!(o.channels, None, "{at}");
                check_port(
                    &format!("{at}.{}", o.name),
                    want,
                    o.ty,
                    None,
                    [
                        o.nodename.as_deref(),
                        None,
                        o.output.as_deref(),
                        o.interfacename.as_deref(),
                    ],
                );
            }
        }
    }
}

/// The upgraded PBR document's materials build networks: the thin-film layers are gone and the
/// BSDFs carry the film (values as MaterialX gives them: `oracle.json`).
#[test]
fn thin_film_layers_upgrade_into_networks() {
    let oracle = oracle();
    let want = &oracle["upgraded"]["upgrade_138_pbr.mtlx"];
    let doc = read_document(&data("upgrade_138_pbr.mtlx")).unwrap();
    let wanted_value = |scope: &Json, node: &str, input: &str| -> Vec<f64> {
        let v = oracle_input(scope, node, input)["value"].as_str().unwrap();
        vec![v.trim().parse().unwrap()]
    };
    for (material, bsdf, scope) in [
        ("M_gs", "gs", &want["nodes"]),
        ("M_c", "c1", &want["nodes"]),
        ("M_d", "d6", &want["nodes"]),
        ("M_ng", "d7", &want["nodegraphs"]["NG_base"]["nodes"]),
    ] {
        let net = doc.network(material).unwrap();
        assert!(
            net.nodes
                .iter()
                .all(|n| n.category != "layer" && n.category != "thin_film_bsdf"),
            "{material}: {:?}",
            node_names(&net)
        );
        let node = net
            .nodes
            .iter()
            .find(|n| n.name.ends_with(&format!("/{bsdf}")))
            .unwrap_or_else(|| panic!("{material}: {:?}", node_names(&net)));
        let thickness = node
            .inputs
            .iter()
            .find(|i| i.name == "thinfilm_thickness")
            .unwrap();
        assert_eq!(
            thickness.source,
            NetSource::Value(Value::Numbers(wanted_value(
                scope,
                bsdf,
                "thinfilm_thickness"
            ))),
            "{material}"
        );
    }
}

/// A document older than 1.38 (which lux does not upgrade) is a typed error naming the file and
/// the version, and inside a stage a composition warning: the stage loads without it.
#[test]
fn documents_older_than_138_are_refused_by_version() {
    let path = data("old_137.mtlx");
    let err = read_document(&path).unwrap_err();
    match &err {
        MtlxError::Version {
            file,
            line,
            major,
            minor,
        } => {
            assert_eq!(file, &path);
            assert_eq!((*line, *major, *minor), (2, 1, 37));
        }
        e => panic!("{e:?}"),
    }
    let message = err.to_string();
    assert!(message.contains("old_137.mtlx:2:"), "{message}");
    assert!(message.contains("MaterialX 1.37 document"), "{message}");
    let err = parse_document(
        "<materialx version=\"1.36\"><nodegraph name=\"NG\"/></materialx>",
        Path::new("v136.mtlx"),
    )
    .unwrap_err();
    assert!(matches!(
        err,
        MtlxError::Version {
            major: 1,
            minor: 36,
            ..
        }
    ));
    assert!(
        err.to_string().starts_with("v136.mtlx:1: a MaterialX 1.36"),
        "{err}"
    );
    // 1.38 and 1.39 (and no version: the current one) are read.
    for v in ["version=\"1.38\"", "version=\"1.39\"", ""] {
        parse_document(&format!("<materialx {v}/>"), Path::new("x.mtlx")).unwrap();
    }

    let dir = std::env::temp_dir().join(format!("lux-mtlx-137-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let stage = dir.join("stage.usda");
    std::fs::write(
        &stage,
        format!(
            "#usda 1.0\ndef Scope \"L\" (\n    prepend references = @{}@</MaterialX/Materials>\n)\n{{\n}}\n",
            path.display()
        ),
    )
    .unwrap();
    let scene = lux_usd::load_stage(&stage, 1.0).unwrap();
    let warning = scene
        .warnings
        .iter()
        .find(|w| w.kind == lux_usd::WarningKind::Composition)
        .expect("a composition warning");
    assert_eq!(warning.prim, "/L");
    assert!(
        warning
            .message
            .contains("old_137.mtlx:2: a MaterialX 1.37 document"),
        "{}",
        warning.message
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_documents_are_typed_errors() {
    let err = parse_document(
        "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\">\n  <image name=\"a\" type=\"color3\">\n</materialx>\n",
        Path::new("bad.mtlx"),
    )
    .unwrap_err();
    match err {
        MtlxError::Xml { line, ref file, .. } => {
            assert_eq!(line, 4);
            assert_eq!(file, Path::new("bad.mtlx"));
        }
        e => panic!("{e:?}"),
    }
    let err = parse_document(
        "<materialx version=\"1.39\">\n<image name=\"a\" type=\"color3\">\n<input name=\"default\" type=\"color3\" value=\"1, x\"/>\n</image>\n</materialx>",
        Path::new("bad.mtlx"),
    )
    .unwrap_err();
    match &err {
        MtlxError::Invalid { line, element, .. } => {
            assert_eq!(*line, 3);
            assert_eq!(element, "input \"default\"");
        }
        e => panic!("{e:?}"),
    }
    assert!(err.to_string().contains("color3"));
    assert!(matches!(
        parse_document("<mtlx/>", Path::new("x.mtlx")),
        Err(MtlxError::Invalid { .. })
    ));
    assert!(matches!(
        parse_document(
            "<materialx><image type=\"float\"/></materialx>",
            Path::new("x.mtlx")
        ),
        Err(MtlxError::Invalid { line: 1, .. })
    ));
    let doc = parse_document("<materialx/>", Path::new("x.mtlx")).unwrap();
    assert!(matches!(
        doc.network("nope"),
        Err(MtlxError::Network { .. })
    ));
}

#[test]
fn custom_nodes_of_the_document_and_versions() {
    let doc = read_document(&data("custom_node.mtlx")).unwrap();
    let net = doc.network("M").unwrap();
    assert_eq!(
        node_names(&net),
        [
            "custom_node.mtlx:/SR",
            "custom_node.mtlx:/t1/m",
            "custom_node.mtlx:/red"
        ]
    );
    // version="1.0.0" selects the older standard_surface nodedef (MaterialX agrees: oracle).
    assert_eq!(
        net.nodes[0].nodedef.as_deref(),
        Some("ND_standard_surface_surfaceshader_100")
    );
    let g = flatten(&net);
    assert_eq!(g.notes, Vec::<String>::new());
    assert_eq!(g.model, "ND_standard_surface_surfaceshader_100");
    check_sorted(&g);
    let tint = g
        .nodes
        .iter()
        .find(|n| n.name == "custom_node.mtlx:/t1/m")
        .unwrap();
    assert_eq!(tint.nodedef, "ND_multiply_color3FA");
    // `amount` unauthored on t1: the document nodedef's default.
    assert!(close(&value(tint, "in2"), &[0.5]));
    let (red, _) = upstream(&g, tint, "in1");
    assert!(close(&value(red, "value"), &[1.0, 0.0, 0.0]));
    // 1.0.0's default base is 0.8 (1.0.1's is 1).
    let metal = g
        .nodes
        .iter()
        .find(|n| n.category == "conductor_bsdf")
        .unwrap();
    let (ior, _) = upstream(&g, metal, "ior");
    let (refl, _) = upstream(&g, ior, "reflectivity");
    assert!(close(&value(refl, "in2"), &[0.8]));
    assert_eq!(upstream(&g, refl, "in1").0.name, tint.name);
}

fn usd_node(name: &str, id: &str, inputs: Vec<(&str, Option<ValueType>, NetSource)>) -> NetNode {
    NetNode {
        name: name.into(),
        nodedef: Some(id.into()),
        category: String::new(),
        ty: None,
        inputs: inputs
            .into_iter()
            .map(|(n, ty, source)| NetInput {
                name: n.into(),
                ty,
                source,
            })
            .collect(),
    }
}

fn conn(node: usize, output: &str) -> NetSource {
    NetSource::Connection(Connection {
        node,
        output: output.into(),
    })
}

#[test]
fn a_usd_preview_surface_network_flattens() {
    let file = FileValue {
        asset: AssetRef {
            authored: "./albedo.png".into(),
            resolved: None,
        },
        colorspace: String::new(),
    };
    let net = Network {
        material: "/World/Mat".into(),
        nodes: vec![
            usd_node(
                "/World/Mat/Surface",
                "UsdPreviewSurface",
                vec![
                    ("diffuseColor", Some(ValueType::Color3), conn(1, "rgb")),
                    // authored as a float where the nodedef says integer: converted, noted
                    (
                        "useSpecularWorkflow",
                        Some(ValueType::Float),
                        NetSource::Value(Value::Numbers(vec![0.0])),
                    ),
                ],
            ),
            usd_node(
                "/World/Mat/Tex",
                "UsdUVTexture",
                vec![
                    (
                        "file",
                        Some(ValueType::Filename),
                        NetSource::Value(Value::File(file)),
                    ),
                    ("st", Some(ValueType::Vector2), conn(2, "result")),
                    (
                        "sourceColorSpace",
                        Some(ValueType::String),
                        NetSource::Value(Value::String("sRGB".into())),
                    ),
                ],
            ),
            usd_node(
                "/World/Mat/St",
                "UsdPrimvarReader_float2",
                vec![(
                    "varname",
                    Some(ValueType::String),
                    NetSource::Value(Value::String("st".into())),
                )],
            ),
        ],
        surface: Some(Connection {
            node: 0,
            output: "surface".into(),
        }),
    };
    let g = flatten(&net);
    assert_eq!(g.model, "ND_UsdPreviewSurface_surfaceshader");
    assert_eq!(g.notes.len(), 1, "{:?}", g.notes);
    assert!(g.notes[0].contains("useSpecularWorkflow"), "{:?}", g.notes);
    check_sorted(&g);
    let image = g.nodes.iter().find(|n| n.category == "image").unwrap();
    assert_eq!(image.nodedef, "ND_image_color4");
    assert_eq!(
        image.name,
        "/World/Mat/Tex/IMP_UsdUVTexture_22/image_reader"
    );
    let Source::Value(Value::File(f)) = &image.input("file").unwrap().source else {
        panic!()
    };
    assert_eq!(f.colorspace, "srgb_texture");
    // st ← the primvar reader's implementation: a geompropvalue reading `st`.
    let (reader, _) = upstream(&g, image, "texcoord");
    assert_eq!(reader.category, "geompropvalue");
    assert_eq!(
        reader.input("geomprop").unwrap().source,
        Source::Value(Value::String("st".into()))
    );
}

#[test]
fn unknown_nodes_and_cycles_are_notes() {
    let net = Network {
        material: "/M".into(),
        nodes: vec![
            NetNode {
                name: "/M/S".into(),
                nodedef: None,
                category: "standard_surface".into(),
                ty: Some(ValueType::SurfaceShader),
                inputs: vec![
                    NetInput {
                        name: "base_color".into(),
                        ty: Some(ValueType::Color3),
                        source: conn(1, "out"),
                    },
                    NetInput {
                        name: "base".into(),
                        ty: Some(ValueType::Float),
                        source: conn(2, "out"),
                    },
                ],
            },
            NetNode {
                name: "/M/Mystery".into(),
                nodedef: None,
                category: "no_such_node".into(),
                ty: Some(ValueType::Color3),
                inputs: vec![],
            },
            NetNode {
                name: "/M/A".into(),
                nodedef: None,
                category: "add".into(),
                ty: Some(ValueType::Float),
                inputs: vec![NetInput {
                    name: "in1".into(),
                    ty: Some(ValueType::Float),
                    source: conn(3, "out"),
                }],
            },
            NetNode {
                name: "/M/B".into(),
                nodedef: None,
                category: "add".into(),
                ty: Some(ValueType::Float),
                inputs: vec![NetInput {
                    name: "in1".into(),
                    ty: Some(ValueType::Float),
                    source: conn(2, "out"),
                }],
            },
        ],
        surface: Some(Connection {
            node: 0,
            output: "out".into(),
        }),
    };
    let g = flatten(&net);
    assert_eq!(g.model, "ND_standard_surface_surfaceshader");
    check_sorted(&g);
    assert_eq!(g.notes.len(), 2, "{:?}", g.notes);
    assert!(
        g.notes
            .iter()
            .any(|n| n.contains("/M/Mystery") && n.contains("/M"))
    );
    assert!(g.notes.iter().any(|n| n.contains("cycle")));
    // The unknown node's consumer takes the nodedef default (base_color 0.8 grey).
    let mult = g
        .nodes
        .iter()
        .find(|n| n.name.ends_with("/metal_reflectivity"))
        .unwrap();
    assert!(close(&value(mult, "in1"), &[0.8, 0.8, 0.8]));
    // The cycle A → B → A is cut at the input closing it (B.in1 takes its default, 0).
    let b = g.nodes.iter().find(|n| n.name == "/M/B").unwrap();
    assert!(close(&value(b, "in1"), &[0.0]));
    let (a, _) = upstream(&g, mult, "in2");
    assert_eq!(a.name, "/M/A");
}
