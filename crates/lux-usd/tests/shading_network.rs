//! UsdShade networks read as MaterialX-style [`Network`]s (`lux_usd::read_network`): a
//! UsdPreviewSurface network with a texture and a primvar reader, an inline MaterialX
//! `standard_surface` under `outputs:mtlx:surface` fed through a NodeGraph and the Material's
//! interface inputs, and a network with a cycle and dangling connections (warnings, no panic).

use lux_usd::reader::Reader;
use lux_usd::shading::{Connection, NetInput, NetNode, NetSource, Network, Value, ValueType};
use lux_usd::{LoadOptions, Warning, load_stage, read_network};
use openusd::usd::Stage;
use std::path::{Path, PathBuf};

fn data(file: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/shading")
        .join(file)
}

/// A reader of `stage`, opened from `file`, at time 1 with the default options.
fn reader<'s>(stage: &'s Stage, file: &Path) -> Reader<'s> {
    Reader {
        stage,
        file: file.to_path_buf(),
        time: 1.0,
        warnings: Vec::new(),
        type_warnings: Default::default(),
        limits: LoadOptions::default(),
    }
}

/// Writes `text` to a layer `name` in a new temporary directory `{prefix}{process id}`: the
/// directory and the layer's path.
fn temp_layer(prefix: &str, name: &str, text: &str) -> (PathBuf, PathBuf) {
    let dir = std::env::temp_dir().join(format!("{prefix}{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(name);
    std::fs::write(&file, text).unwrap();
    (dir, file)
}

/// The network of `material` in `file`, with the warnings reading it gave.
fn network(file: &str, material: &str) -> (Network, Vec<Warning>) {
    let path = data(file);
    let stage = Stage::open(path.to_str().unwrap()).unwrap();
    let mut r = reader(&stage, &path);
    let n = read_network(&mut r, material).unwrap();
    (n, r.warnings)
}

fn node<'a>(n: &'a Network, name: &str) -> (usize, &'a NetNode) {
    n.nodes
        .iter()
        .enumerate()
        .find(|(_, x)| x.name == name)
        .unwrap_or_else(|| panic!("no node {name} in {n:#?}"))
}

fn input<'a>(n: &'a NetNode, name: &str) -> &'a NetInput {
    n.inputs
        .iter()
        .find(|i| i.name == name)
        .unwrap_or_else(|| panic!("no input {name} on {n:#?}"))
}

fn numbers(i: &NetInput) -> Vec<f64> {
    match &i.source {
        NetSource::Value(Value::Numbers(v)) => v.clone(),
        other => panic!("{}: {other:?}", i.name),
    }
}

fn connection(i: &NetInput) -> &Connection {
    match &i.source {
        NetSource::Connection(c) => c,
        other => panic!("{}: {other:?}", i.name),
    }
}

fn f(x: f32) -> f64 {
    x.into()
}

#[test]
fn preview_surface_texture_and_primvar_reader() {
    let (n, warnings) = network("networks.usda", "/World/Looks/Preview");
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(n.material, "/World/Looks/Preview");
    assert_eq!(n.nodes.len(), 3, "{n:#?}");
    let (s, surface) = node(&n, "/World/Looks/Preview/Surface");
    let (t, texture) = node(&n, "/World/Looks/Preview/Albedo");
    let (p, reader) = node(&n, "/World/Looks/Preview/Reader");
    assert_eq!(
        n.surface,
        Some(Connection {
            node: s,
            output: "surface".into()
        })
    );
    assert_eq!(s, 0, "the surface shader is the first node");
    assert_eq!(surface.nodedef.as_deref(), Some("UsdPreviewSurface"));
    assert_eq!(texture.nodedef.as_deref(), Some("UsdUVTexture"));
    assert_eq!(reader.nodedef.as_deref(), Some("UsdPrimvarReader_float2"));
    assert!(surface.category.is_empty());
    // The texture's one output is float3: a vector3 node; the surface's is a token.
    assert_eq!(texture.ty, Some(ValueType::Vector3));
    assert_eq!(surface.ty, None);

    // Surface: a connection, an interface input's value, typed values.
    let diffuse = input(surface, "diffuseColor");
    assert_eq!(diffuse.ty, Some(ValueType::Color3));
    assert_eq!(
        connection(diffuse),
        &Connection {
            node: t,
            output: "rgb".into()
        }
    );
    let rough = input(surface, "roughness");
    assert_eq!(rough.ty, Some(ValueType::Float));
    assert_eq!(
        numbers(rough),
        [0.25],
        "through the Material's inputs:rough"
    );
    assert_eq!(numbers(input(surface, "metallic")), [0.5]);
    let spec = input(surface, "useSpecularWorkflow");
    assert_eq!(spec.ty, Some(ValueType::Integer));
    assert_eq!(numbers(spec), [1.0]);
    let normal = input(surface, "normal");
    assert_eq!(normal.ty, Some(ValueType::Vector3));
    assert_eq!(numbers(normal), [0.0, 0.0, 1.0]);
    // An array (LTESpectralAPI) is not a MaterialX input: left out, silently.
    assert_eq!(surface.inputs.len(), 5, "{surface:#?}");

    // Texture: the file resolved next to the layer, sRGB, tokens as strings, float4.
    let file = input(texture, "file");
    assert_eq!(file.ty, Some(ValueType::Filename));
    let NetSource::Value(Value::File(fv)) = &file.source else {
        panic!("{file:?}")
    };
    assert_eq!(fv.asset.authored, "leaf.png");
    assert_eq!(
        fv.asset
            .resolved
            .as_deref()
            .map(|p| p.canonicalize().unwrap()),
        Some(data("leaf.png").canonicalize().unwrap())
    );
    assert_eq!(fv.colorspace, "srgb_texture", "sourceColorSpace sRGB");
    assert!(
        texture.inputs.iter().all(|i| i.name != "sourceColorSpace"),
        "folded into the file: {texture:#?}"
    );
    // file, wrapS, scale, st.
    assert_eq!(texture.inputs.len(), 4, "{texture:#?}");
    let wrap = input(texture, "wrapS");
    assert_eq!(wrap.ty, Some(ValueType::String));
    assert_eq!(
        wrap.source,
        NetSource::Value(Value::String("mirror".into()))
    );
    let scale = input(texture, "scale");
    assert_eq!(scale.ty, Some(ValueType::Vector4));
    assert_eq!(numbers(scale), [2.0, 2.0, 2.0, 1.0]);
    let st = input(texture, "st");
    assert_eq!(st.ty, Some(ValueType::Vector2));
    assert_eq!(
        connection(st),
        &Connection {
            node: p,
            output: "result".into()
        }
    );

    // Primvar reader: varname through the Material's interface input, a float2 fallback.
    assert_eq!(
        input(reader, "varname").source,
        NetSource::Value(Value::String("st".into()))
    );
    let fallback = input(reader, "fallback");
    assert_eq!(fallback.ty, Some(ValueType::Vector2));
    assert_eq!(numbers(fallback), [0.5, 0.75]);
}

#[test]
fn inline_standard_surface_through_a_node_graph() {
    let (n, warnings) = network("networks.usda", "/World/Looks/Standard");
    assert!(warnings.is_empty(), "{warnings:?}");
    // The NodeGraph is resolved away: three Shader nodes.
    assert_eq!(n.nodes.len(), 3, "{n:#?}");
    let (s, sr) = node(&n, "/World/Looks/Standard/SR");
    let (m, mul) = node(&n, "/World/Looks/Standard/Tinted/Mul");
    let (i, image) = node(&n, "/World/Looks/Standard/Tinted/Image");
    assert_eq!(
        n.surface,
        Some(Connection {
            node: s,
            output: "out".into()
        }),
        "outputs:mtlx:surface"
    );
    assert_eq!(
        sr.nodedef.as_deref(),
        Some("ND_standard_surface_surfaceshader")
    );
    assert_eq!(mul.nodedef.as_deref(), Some("ND_multiply_color3"));
    assert_eq!(image.nodedef.as_deref(), Some("ND_image_color3"));
    assert_eq!(mul.ty, Some(ValueType::Color3));

    assert_eq!(numbers(input(sr, "base")), [f(0.9)]);
    assert_eq!(numbers(input(sr, "specular_roughness")), [f(0.3)]);
    let thin = input(sr, "thin_walled");
    assert_eq!(thin.ty, Some(ValueType::Boolean));
    assert_eq!(numbers(thin), [1.0]);
    // base_color ← the NodeGraph's outputs:out ← Mul.
    assert_eq!(
        connection(input(sr, "base_color")),
        &Connection {
            node: m,
            output: "out".into()
        }
    );
    assert_eq!(
        connection(input(mul, "in1")),
        &Connection {
            node: i,
            output: "out".into()
        }
    );
    // in2 ← the NodeGraph's interface input ← the Material's interface input.
    let in2 = input(mul, "in2");
    assert_eq!(in2.ty, Some(ValueType::Color3));
    assert_eq!(numbers(in2), [f(0.8), f(0.4), f(0.2)]);
    // The image's file carries its colorSpace metadata.
    let NetSource::Value(Value::File(fv)) = &input(image, "file").source else {
        panic!("{image:?}")
    };
    assert_eq!(fv.colorspace, "srgb_texture");
    assert!(fv.asset.resolved.is_some());
    assert_eq!(
        input(image, "uaddressmode").source,
        NetSource::Value(Value::String("periodic".into()))
    );
}

#[test]
fn cycles_and_dangling_connections_are_dropped_with_warnings() {
    let (n, warnings) = network("networks.usda", "/World/Looks/Broken");
    // outputs:mtlx:surface dangles: outputs:surface is read instead.
    let (a, shader) = node(&n, "/World/Looks/Broken/A");
    let (_, add) = node(&n, "/World/Looks/Broken/B");
    assert_eq!(n.nodes.len(), 2, "{n:#?}");
    assert_eq!(
        n.surface,
        Some(Connection {
            node: a,
            output: "out".into()
        })
    );
    let says = |prim: &str, what: &str| {
        warnings
            .iter()
            .any(|w| w.prim == prim && w.message.contains(what))
    };
    assert!(
        says("/World/Looks/Broken", "outputs:mtlx:surface"),
        "{warnings:#?}"
    );
    // The cycle A → B → A: the edge closing it (B's in1) is dropped.
    assert!(
        says("/World/Looks/Broken/B", "inputs:in1: connection cycle"),
        "{warnings:#?}"
    );
    assert!(add.inputs.iter().all(|i| i.name != "in1"), "{add:#?}");
    assert_eq!(numbers(input(add, "in2")), [f(0.1), f(0.2), f(0.3)]);
    assert!(matches!(
        input(shader, "base_color").source,
        NetSource::Connection(_)
    ));
    // A connection to a prim that does not exist.
    assert!(
        says("/World/Looks/Broken/A", "inputs:coat_color"),
        "{warnings:#?}"
    );
    assert!(shader.inputs.iter().all(|i| i.name != "coat_color"));
    // A NodeGraph whose output and interface input connect to each other.
    assert!(
        says("/World/Looks/Broken/A", "inputs:coat_roughness"),
        "{warnings:#?}"
    );
    assert!(shader.inputs.iter().all(|i| i.name != "coat_roughness"));
    assert_eq!(numbers(input(shader, "coat")), [0.5]);
    assert_eq!(warnings.len(), 4, "{warnings:#?}");
}

#[test]
fn materials_carry_their_graph() {
    let s = load_stage(data("networks.usda"), 1.0).unwrap();
    let material = |mesh: &str| {
        let m = s.meshes.iter().find(|m| m.path == mesh).unwrap();
        &s.materials[m.material.unwrap()]
    };
    for (mesh, path) in [
        ("/World/Preview", "/World/Looks/Preview"),
        ("/World/Standard", "/World/Looks/Standard"),
        ("/World/Broken", "/World/Looks/Broken"),
    ] {
        let m = material(mesh);
        let g = m
            .graph
            .as_ref()
            .unwrap_or_else(|| panic!("{path}: no graph"));
        assert_eq!(g.material, path);
    }
    // End to end (flatten, from wt-mtlx): the shading model, the surface, the texture the
    // NodeGraph reads with its colour space, the Material's tint reaching the multiply.
    let standard = material("/World/Standard").graph.as_ref().unwrap();
    assert_eq!(standard.model, "ND_standard_surface_surfaceshader");
    assert!(
        standard.surface.is_some() && standard.notes.is_empty(),
        "{standard:#?}"
    );
    let image = standard
        .nodes
        .iter()
        .find(|n| n.name == "/World/Looks/Standard/Tinted/Image")
        .unwrap();
    assert_eq!(image.nodedef, "ND_image_color3");
    let Some(lux_usd::shading::Source::Value(Value::File(fv))) =
        image.input("file").map(|i| &i.source)
    else {
        panic!("{image:#?}")
    };
    assert_eq!(fv.colorspace, "srgb_texture");
    let mul = standard
        .nodes
        .iter()
        .find(|n| n.name == "/World/Looks/Standard/Tinted/Mul")
        .unwrap();
    assert_eq!(
        mul.input("in2").unwrap().source,
        lux_usd::shading::Source::Value(Value::Numbers(vec![f(0.8), f(0.4), f(0.2)]))
    );
    assert_eq!(
        material("/World/Preview").graph.as_ref().unwrap().model,
        "ND_UsdPreviewSurface_surfaceshader"
    );
    // The UsdPreviewSurface fields are read as before.
    let preview = material("/World/Preview");
    assert!(preview.preview);
    assert_eq!(preview.roughness, lux_usd::Input::Value(0.25));
    assert_eq!(preview.diffuse.texture().unwrap().st_primvar, "st");
    // A MaterialX surface is drawn from its graph, from outputs:mtlx:surface or (here
    // /World/Looks/Broken, whose mtlx terminal dangles) outputs:surface: no "default grey"
    // warning for either.
    let grey = |p: &str| {
        s.warnings
            .iter()
            .any(|w| w.prim == p && w.message.contains("not UsdPreviewSurface"))
    };
    assert!(!material("/World/Standard").preview);
    assert!(!grey("/World/Looks/Standard"), "{:#?}", s.warnings);
    assert!(
        !s.warnings.iter().any(|w| w.prim == "/World/Looks/Standard"),
        "{:#?}",
        s.warnings
    );
    assert!(!grey("/World/Looks/Broken"), "{:#?}", s.warnings);
    assert!(material("/World/Broken").graph.is_some());
}

/// A material without a surface, a terminal connected to a value, a connection to a
/// property that is not an attribute path: no nodes, no panic.
#[test]
fn unreadable_terminals_give_empty_networks() {
    let (dir, file) = temp_layer(
        "lux-usdnet-",
        "empty.usda",
        r#"#usda 1.0
def Material "NoSurface"
{
}
def Material "ToInput"
{
    float inputs:x = 1
    token outputs:surface.connect = </ToInput.inputs:x>
}
def Material "ToXform"
{
    token outputs:mtlx:surface.connect = </X.outputs:out>
}
def Xform "X"
{
}
"#,
    );
    let stage = Stage::open(file.to_str().unwrap()).unwrap();
    let mut r = reader(&stage, &file);
    for m in [
        "/NoSurface",
        "/ToInput",
        "/ToXform",
        "/Missing",
        "not a path",
    ] {
        let n = read_network(&mut r, m).unwrap();
        assert!(n.nodes.is_empty() && n.surface.is_none(), "{m}: {n:#?}");
    }
    assert!(
        r.warnings
            .iter()
            .any(|w| w.prim == "/ToXform" && w.message.contains("not an output or input")),
        "{:#?}",
        r.warnings
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A MaterialX surface shader without `info:id` (a shader by source asset): the universal
/// `outputs:surface` is read instead; without one, the unidentified shader is the surface.
#[test]
fn mtlx_surface_without_an_id_falls_back_to_the_universal_surface() {
    let (dir, file) = temp_layer(
        "lux-usdnet-id-",
        "fallback.usda",
        r#"#usda 1.0
def Material "M"
{
    token outputs:mtlx:surface.connect = </M/Custom.outputs:out>
    token outputs:surface.connect = </M/Preview.outputs:surface>
    def Shader "Custom"
    {
        uniform token info:implementationSource = "sourceAsset"
        token outputs:out
    }
    def Shader "Preview"
    {
        uniform token info:id = "UsdPreviewSurface"
        float inputs:roughness = 0.5
        token outputs:surface
    }
}
def Material "Only"
{
    token outputs:mtlx:surface.connect = </M/Custom.outputs:out>
}
"#,
    );
    let stage = Stage::open(file.to_str().unwrap()).unwrap();
    let mut r = reader(&stage, &file);
    let n = read_network(&mut r, "/M").unwrap();
    assert_eq!(n.nodes.len(), 1, "{n:#?}");
    assert_eq!(n.nodes[0].name, "/M/Preview");
    assert_eq!(n.nodes[0].nodedef.as_deref(), Some("UsdPreviewSurface"));
    assert_eq!(numbers(input(&n.nodes[0], "roughness")), [0.5]);
    assert!(r.warnings.is_empty(), "{:#?}", r.warnings);
    let n = read_network(&mut r, "/Only").unwrap();
    assert_eq!(n.nodes.len(), 1, "{n:#?}");
    assert_eq!(n.nodes[0].nodedef, None);
    assert!(
        r.warnings
            .iter()
            .any(|w| w.prim == "/M/Custom" && w.message.contains("no info:id")),
        "{:#?}",
        r.warnings
    );
    let _ = std::fs::remove_dir_all(&dir);
}
