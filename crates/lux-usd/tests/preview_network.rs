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
