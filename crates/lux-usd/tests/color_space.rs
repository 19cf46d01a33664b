//! Colour values in a stated colour space reach the shading network in `lin_rec709`, lux's
//! working space: MaterialX `colorspace` (the input's, an enclosing element's or the
//! document's) and USD `colorSpace` metadata, converted by MaterialX cmlib's transforms; a
//! colour space lux does not know is a warning, never a silent substitute.

use lux_usd::mtlx::parse_document;
use lux_usd::shading::color_space::{ACESCG_TO_LIN_REC709, srgb_to_linear};
use lux_usd::shading::{NetSource, Value};
use lux_usd::{LoadOptions, WarningKind, load_usda_str};
use std::path::Path;

fn numbers(v: &Option<Value>) -> Vec<f64> {
    match v {
        Some(Value::Numbers(n)) => n.clone(),
        other => panic!("{other:?}"),
    }
}

const DOC: &str = r#"<?xml version="1.0"?>
<materialx version="1.39" colorspace="acescg">
  <standard_surface name="SR" type="surfaceshader">
    <input name="base_color" type="color3" value="1, 0, 0" />
    <input name="specular_color" type="color3" value="0.5, 0.5, 0.5" colorspace="srgb_texture" />
    <input name="coat_color" type="color3" value="0.5, 0.25, 0.125" colorspace="adobergb" />
    <input name="base" type="float" value="0.5" />
  </standard_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR" />
  </surfacematerial>
</materialx>
"#;

#[test]
fn document_colour_values_are_converted_from_their_active_colour_space() {
    let doc = parse_document(DOC, Path::new("mem.mtlx")).unwrap();
    let sr = doc.node("SR").unwrap();
    // The document's acescg: (1, 0, 0) in AP1 is the first row of cmlib's AP1 → Rec.709.
    let base = numbers(&sr.input("base_color").unwrap().value);
    assert_eq!(base, ACESCG_TO_LIN_REC709[0].to_vec());
    assert_eq!(sr.input("base_color").unwrap().colorspace, "");
    // The input's own srgb_texture beats the document's.
    let spec = numbers(&sr.input("specular_color").unwrap().value);
    assert_eq!(spec, vec![srgb_to_linear(0.5); 3]);
    // An unknown colour space keeps the value and says which space it is in.
    let coat = sr.input("coat_color").unwrap();
    assert_eq!(numbers(&coat.value), vec![0.5, 0.25, 0.125]);
    assert_eq!(coat.colorspace, "adobergb");
    // Not a colour: untouched.
    assert_eq!(numbers(&sr.input("base").unwrap().value), vec![0.5]);
}

#[test]
fn the_translated_layer_keeps_what_lux_could_not_convert() {
    let doc = parse_document(DOC, Path::new("mem.mtlx")).unwrap();
    let text = lux_usd::mtlx::usdmtlx::to_usda(&doc);
    assert!(
        text.contains("color3f inputs:coat_color = (0.5, 0.25, 0.125) (\n                colorSpace = \"adobergb\""),
        "{text}"
    );
    // Converted values carry no colour space.
    assert_eq!(text.matches("colorSpace").count(), 1, "{text}");
}

const STAGE: &str = r#"#usda 1.0
def Material "M"
{
    token outputs:mtlx:surface.connect = </M/SR.outputs:surface>

    def Shader "SR"
    {
        uniform token info:id = "ND_standard_surface_surfaceshader"
        color3f inputs:base_color = (0.5, 0.5, 0.5) (
            colorSpace = "srgb_texture"
        )
        color3f inputs:coat_color = (0.25, 0.5, 1) (
            colorSpace = "adobergb"
        )
        color3f inputs:specular_color = (0.25, 0.5, 1)
        token outputs:surface
    }
}

def Mesh "Tri" (
    prepend apiSchemas = ["MaterialBindingAPI"]
)
{
    rel material:binding = </M>
    int[] faceVertexCounts = [3]
    int[] faceVertexIndices = [0, 1, 2]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
}
"#;

#[test]
fn usd_colour_values_with_colour_space_metadata_are_converted() {
    let scene = load_usda_str(STAGE, 0.0, &LoadOptions::default()).unwrap();
    let net = scene.materials[0].network.as_ref().unwrap();
    let sr = &net.nodes[net.surface.as_ref().unwrap().node];
    let value = |name: &str| match &sr.inputs.iter().find(|i| i.name == name).unwrap().source {
        NetSource::Value(Value::Numbers(n)) => n.clone(),
        other => panic!("{other:?}"),
    };
    assert_eq!(value("base_color"), vec![srgb_to_linear(0.5); 3]);
    assert_eq!(value("specular_color"), vec![0.25, 0.5, 1.0]);
    assert_eq!(value("coat_color"), vec![0.25, 0.5, 1.0]);
    let w: Vec<_> = scene
        .warnings
        .iter()
        .filter(|w| w.kind == WarningKind::Unsupported && w.message.contains("adobergb"))
        .collect();
    assert_eq!(w.len(), 1, "{:#?}", scene.warnings);
    assert_eq!(w[0].prim, "/M/SR");
}
