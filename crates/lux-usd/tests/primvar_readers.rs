//! UsdPrimvarReader_* feeding UsdPreviewSurface inputs: the reader (varname as token or string,
//! through an interface input, fallback) and the primvar it reads on the gprim, at every
//! interpolation, indexed or not, per triangle corner.

use glam::{DVec3, DVec4};
use lux_usd::{Input, LoadOptions, Time, load_usda_str};

/// A material whose `diffuseColor` reads `primvars:NAME` through a `UsdPrimvarReader_float3`
/// (`varname` authored as `varname_decl`), whose `roughness` reads `rough` through a
/// `UsdPrimvarReader_float`, bound to a two-triangle quad with `primvars` authored.
fn stage(varname_decl: &str, primvars: &str) -> String {
    format!(
        r#"#usda 1.0
def Material "M" {{
    token inputs:colorName = "tint"
    token outputs:surface.connect = </M/S.outputs:surface>
    def Shader "S" {{
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor.connect = </M/C.outputs:result>
        float inputs:roughness.connect = </M/R.outputs:result>
        token outputs:surface
    }}
    def Shader "C" {{
        uniform token info:id = "UsdPrimvarReader_float3"
        {varname_decl}
        float3 inputs:fallback = (0.1, 0.2, 0.3)
        float3 outputs:result
    }}
    def Shader "R" {{
        uniform token info:id = "UsdPrimvarReader_float"
        string inputs:varname = "rough"
        float outputs:result
    }}
}}
def Mesh "Quad" (prepend apiSchemas = ["MaterialBindingAPI"]) {{
    rel material:binding = </M>
    uniform token subdivisionScheme = "none"
    int[] faceVertexCounts = [4]
    int[] faceVertexIndices = [0, 1, 2, 3]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    {primvars}
}}
"#
    )
}

#[test]
fn readers_are_read_with_varname_and_fallback() {
    for decl in [
        "token inputs:varname = \"tint\"",
        "string inputs:varname = \"tint\"",
        "token inputs:varname.connect = </M.inputs:colorName>",
    ] {
        let s = load_usda_str(&stage(decl, ""), Time::Start, &LoadOptions::default()).unwrap();
        let m = &s.materials[0];
        let Input::Primvar(p) = &m.diffuse else {
            panic!("{decl}: diffuseColor is {:?}", m.diffuse)
        };
        assert_eq!(p.name, "tint", "{decl}");
        assert_eq!(p.components, 3);
        assert_eq!(p.id, "UsdPrimvarReader_float3");
        let f = |x: f32| x as f64;
        assert_eq!(p.fallback, DVec4::new(f(0.1), f(0.2), f(0.3), 0.0));
        let r = m.roughness.primvar().expect("roughness reader");
        assert_eq!((r.name.as_str(), r.components), ("rough", 1));
        assert_eq!(m.primvar_names(), ["tint", "rough"]);
        // Nothing authored on the mesh: no primvars (the renderer takes the fallback).
        assert!(s.meshes[0].primvars.is_empty());
        assert!(s.warnings.is_empty(), "{decl}: {:?}", s.warnings);
    }
}

/// The primvar per triangle corner at each interpolation (corners of triangles (0, 1, 2) and
/// (0, 2, 3) of the fan), indexed or not.
#[test]
fn primvars_are_expanded_by_interpolation() {
    let decl = "token inputs:varname = \"tint\"";
    let v = |i: u32| DVec3::new(i as f64, 10.0 * i as f64, 100.0 * i as f64).extend(0.0);
    let cases = [
        (
            "color3f[] primvars:tint = [(1, 10, 100)] (interpolation = \"constant\")",
            [[1, 1, 1], [1, 1, 1]],
        ),
        (
            "color3f primvars:tint = (1, 10, 100) (interpolation = \"constant\")",
            [[1, 1, 1], [1, 1, 1]],
        ),
        (
            "color3f[] primvars:tint = [(2, 20, 200)] (interpolation = \"uniform\")",
            [[2, 2, 2], [2, 2, 2]],
        ),
        (
            "color3f[] primvars:tint = [(0, 0, 0), (1, 10, 100), (2, 20, 200), (3, 30, 300)] (interpolation = \"vertex\")",
            [[0, 1, 2], [0, 2, 3]],
        ),
        (
            "color3f[] primvars:tint = [(0, 0, 0), (1, 10, 100), (2, 20, 200), (3, 30, 300)] (interpolation = \"varying\")",
            [[0, 1, 2], [0, 2, 3]],
        ),
        (
            "color3f[] primvars:tint = [(4, 40, 400), (5, 50, 500), (6, 60, 600), (7, 70, 700)] (interpolation = \"faceVarying\")",
            [[4, 5, 6], [4, 6, 7]],
        ),
        (
            "color3f[] primvars:tint = [(8, 80, 800), (9, 90, 900)] (interpolation = \"faceVarying\")\n int[] primvars:tint:indices = [1, 0, 1, 0]",
            [[9, 8, 9], [9, 9, 8]],
        ),
    ];
    for (primvar, want) in cases {
        let s = load_usda_str(&stage(decl, primvar), Time::Start, &LoadOptions::default())
            .unwrap_or_else(|e| panic!("{primvar}: {e}"));
        let m = &s.meshes[0];
        assert_eq!(m.primvars.len(), 1, "{primvar}");
        assert_eq!(m.primvars[0].name, "tint");
        let got = &m.primvars[0].values;
        for (t, tri) in want.iter().enumerate() {
            for (c, &k) in tri.iter().enumerate() {
                assert_eq!(got[t][c], v(k), "{primvar}: triangle {t} corner {c}");
            }
        }
    }
    // A float primvar for the float reader.
    let s = load_usda_str(
        &stage(
            decl,
            "float[] primvars:rough = [0.25] (interpolation = \"constant\")",
        ),
        Time::Start,
        &LoadOptions::default(),
    )
    .unwrap();
    let r = &s.meshes[0].primvars[0];
    assert_eq!(r.name, "rough");
    assert_eq!(r.values[1][2], DVec4::new(0.25, 0.0, 0.0, 0.0));
    // Too few values for the interpolation: a warning naming the primvar, not read.
    let s = load_usda_str(
        &stage(
            decl,
            "color3f[] primvars:tint = [(1, 1, 1)] (interpolation = \"vertex\")",
        ),
        Time::Start,
        &LoadOptions::default(),
    )
    .unwrap();
    assert!(s.meshes[0].primvars.is_empty());
    assert!(
        s.warnings
            .iter()
            .any(|w| w.prim == "/Quad" && w.message.contains("primvars:tint")),
        "{:?}",
        s.warnings
    );
}

/// A subdivision surface refines the primvars its material reads (vertex: smoothly, as its
/// points; the flat quad's refined tint equals the refined points where tint = the points).
#[test]
fn subdivided_primvars_are_refined() {
    let text = stage(
        "token inputs:varname = \"tint\"",
        "color3f[] primvars:tint = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)] (interpolation = \"vertex\")",
    )
    .replace("uniform token subdivisionScheme = \"none\"", "");
    let mut s = load_usda_str(&text, Time::Start, &LoadOptions::default()).unwrap();
    assert!(s.meshes[0].subdivision.is_some());
    s.refine_subdivision(&lux_usd::subdiv::LevelRule::Fixed(2));
    let m = &s.meshes[0];
    assert_eq!(m.primvars.len(), 1);
    assert_eq!(m.primvars[0].values.len(), m.triangles.len());
    for (tri, values) in m.triangles.iter().zip(&m.primvars[0].values) {
        for (&i, v) in tri.iter().zip(values) {
            assert!(v.truncate().distance(m.positions[i as usize]) < 1e-6);
        }
    }
}

/// A prototype's mesh without a binding of its own is drawn with its instance's material: it
/// carries the primvars that material reads.
#[test]
fn prototype_meshes_carry_what_instance_materials_read() {
    let text = stage("token inputs:varname = \"tint\"", "")
        .replace(
            "def Mesh \"Quad\" (prepend apiSchemas = [\"MaterialBindingAPI\"]) {\n    rel material:binding = </M>",
            "class Xform \"Proto\" {\ndef Mesh \"Quad\" {",
        )
        .replace(
            "    point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]\n    \n}\n",
            "    point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]\n    color3f[] primvars:tint = [(1, 2, 3)] (interpolation = \"constant\")\n}\n}\ndef Xform \"I\" (instanceable = true prepend references = </Proto> prepend apiSchemas = [\"MaterialBindingAPI\"]) {\n    rel material:binding = </M>\n}\n",
        );
    let s = load_usda_str(&text, Time::Start, &LoadOptions::default()).unwrap();
    assert_eq!(s.instances.len(), 1, "{text}");
    let m = &s.meshes[0];
    assert!(m.prototype.is_some() && m.material.is_none());
    assert_eq!(s.instances[0].material, Some(0));
    assert_eq!(m.primvars.len(), 1);
    assert_eq!(m.primvars[0].values[0][0], DVec4::new(1.0, 2.0, 3.0, 0.0));
}
