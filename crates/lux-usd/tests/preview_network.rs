//! A material's UsdPreviewSurface fields rebuilt as a network (`Material::preview_network`,
//! for materials built in code) flatten to the same MaterialX graph as the UsdShade network
//! the stage authors: checked on every UsdPreviewSurface material of the test stages.

use lux_usd::shading::{ShadingGraph, Source, Value, flatten};
use std::path::{Path, PathBuf};

/// The graph below output `output` of node `node`, names left out: category, nodedef and
/// every input's source, recursively.
fn describe(g: &ShadingGraph, node: usize, output: usize, out: &mut String, depth: usize) {
    let n = &g.nodes[node];
    out.push_str(&format!(
        "{}{} {} .{}\n",
        "  ".repeat(depth),
        n.category,
        n.nodedef,
        n.outputs[output].0
    ));
    for i in &n.inputs {
        out.push_str(&format!("{}  {}: ", "  ".repeat(depth), i.name));
        match &i.source {
            Source::Value(Value::File(f)) => out.push_str(&format!(
                "file {:?} {:?} {:?}\n",
                f.asset.authored, f.asset.resolved, f.colorspace
            )),
            Source::Value(v) => out.push_str(&format!("{v:?}\n")),
            Source::Geomprop(p) => out.push_str(&format!("geomprop {p}\n")),
            Source::Node { node, output } => {
                out.push('\n');
                describe(g, *node, *output, out, depth + 2);
            }
        }
    }
}

fn tree(g: &ShadingGraph) -> String {
    let (n, o) = g.surface.expect("a surface");
    let mut s = String::new();
    describe(g, n, o, &mut s, 0);
    s
}

fn stages() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let mut out = Vec::new();
    for dir in ["shading", "scenes"] {
        for e in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "usda") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

#[test]
fn rebuilt_preview_networks_flatten_as_the_authored_ones() {
    let mut compared = 0;
    let mut textured = 0;
    for stage in stages() {
        let Ok(scene) = lux_usd::load_stage(&stage, 1.0) else {
            continue;
        };
        for m in &scene.materials {
            let Some(g) = m.graph.as_deref() else {
                continue;
            };
            if !m.preview || g.model != "ND_UsdPreviewSurface_surfaceshader" {
                continue;
            }
            let (got, want) = (tree(&flatten(&m.preview_network())), tree(g));
            if let Some((k, (a, b))) = got
                .lines()
                .zip(want.lines())
                .enumerate()
                .find(|(_, (a, b))| a != b)
            {
                panic!(
                    "{}: {}: line {k}: rebuilt {a:?}, authored {b:?}",
                    stage.display(),
                    m.path
                );
            }
            assert_eq!(got, want, "{}: {}", stage.display(), m.path);
            compared += 1;
            textured += usize::from(!m.textures().is_empty());
        }
    }
    // The test stages hold plain, textured (with a transform) and primvar-driven surfaces.
    assert!(
        compared >= 5 && textured >= 2,
        "{compared} compared, {textured} textured"
    );
}

/// A `UsdUVTexture`'s `wrapS` / `wrapT` tokens reach its `image` node as the MaterialX address
/// modes they mean: `repeat` → `periodic`, `black` → `constant` (the texture's fallback
/// outside the image, as on the USD side), `clamp` and `mirror` as they are, `useMetadata`
/// (not written) the nodedef's `periodic`; none leaves a note. In code-built networks and in
/// a stage's own.
#[test]
fn wrap_tokens_become_image_address_modes() {
    use lux_usd::{AssetRef, Input, Material, TextureInput, Wrap};
    let texture = |wrap: Wrap| TextureInput {
        shader: "/M/Tex".to_owned(),
        file: Some(AssetRef {
            authored: "t.png".to_owned(),
            resolved: None,
        }),
        st_primvar: "st".to_owned(),
        st_fallback: glam::DVec2::ZERO,
        transform: None,
        scale: glam::DVec4::ONE,
        bias: glam::DVec4::ZERO,
        fallback: glam::DVec4::new(0.0, 0.0, 0.0, 1.0),
        fallback_authored: false,
        wrap_s: wrap,
        wrap_t: wrap,
        source_color_space: lux_usd::SourceColorSpace::Auto,
        output: "rgb".to_owned(),
    };
    let modes = |g: &ShadingGraph| {
        let image = g
            .nodes
            .iter()
            .find(|n| n.category == "image")
            .expect("an image node");
        ["uaddressmode", "vaddressmode"].map(|name| match &image.input(name).unwrap().source {
            Source::Value(Value::String(s)) => s.clone(),
            s => panic!("{name}: {s:?}"),
        })
    };
    for (wrap, want) in [
        (Wrap::Repeat, "periodic"),
        (Wrap::Black, "constant"),
        (Wrap::Clamp, "clamp"),
        (Wrap::Mirror, "mirror"),
        (Wrap::UseMetadata, "periodic"),
    ] {
        let m = Material {
            preview: true,
            diffuse: Input::Texture(Box::new(texture(wrap))),
            ..Material::new("/M")
        };
        let g = flatten(&m.preview_network());
        assert_eq!(modes(&g), [want, want], "{wrap:?}");
        assert!(
            g.notes.iter().all(|n| !n.contains("addressmode")),
            "{wrap:?}: {:?}",
            g.notes
        );
        // The same token authored on a stage's UsdUVTexture.
        let text = format!(
            r#"#usda 1.0
def Material "M" {{
    token outputs:surface.connect = </M/S.outputs:surface>
    def Shader "S" {{
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor.connect = </M/T.outputs:rgb>
        token outputs:surface
    }}
    def Shader "T" {{
        uniform token info:id = "UsdUVTexture"
        asset inputs:file = @t.png@
        token inputs:wrapS = "{0}"
        token inputs:wrapT = "{0}"
        float3 outputs:rgb
    }}
}}
def Mesh "Q" (prepend apiSchemas = ["MaterialBindingAPI"]) {{
    rel material:binding = </M>
    int[] faceVertexCounts = [3]
    int[] faceVertexIndices = [0, 1, 2]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
}}
"#,
            wrap.token()
        );
        let s = lux_usd::load_usda_str(&text, lux_usd::Time::Start, &Default::default()).unwrap();
        let g = s.materials[0].graph.as_deref().expect("the stage's graph");
        assert_eq!(modes(g), [want, want], "{wrap:?} on a stage");
    }
}
