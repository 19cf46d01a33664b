//! Subdivision surfaces: a `Mesh` at the schema's default scheme (Catmull–Clark) is drawn as
//! its limit surface, with the tags as authored. Closed forms: the limit of a cube's face
//! centre, creases that keep a cube a cube, Loop's limit of a valence-n vertex.

use glam::DVec3;
use lux_usd::subdiv::LevelRule;
use lux_usd::{LoadOptions, Scene, Time, load_usda_str};

/// A 2 × 2 × 2 cube (points at ±1) as a `Mesh`, with `extra` authored on it.
fn cube(extra: &str) -> String {
    format!(
        r#"#usda 1.0
def Mesh "Cube" {{
    int[] faceVertexCounts = [4, 4, 4, 4, 4, 4]
    int[] faceVertexIndices = [0, 1, 3, 2, 2, 3, 5, 4, 4, 5, 7, 6, 6, 7, 1, 0, 1, 7, 5, 3, 6, 0, 2, 4]
    point3f[] points = [(-1, -1, 1), (1, -1, 1), (-1, 1, 1), (1, 1, 1), (-1, 1, -1), (1, 1, -1), (-1, -1, -1), (1, -1, -1)]
    {extra}
}}
"#
    )
}

/// The cube's twelve edges as a crease list (`creaseIndices` chains of two).
const CUBE_EDGES: &str = "int[] creaseIndices = [0, 1, 1, 3, 3, 2, 2, 0, 4, 5, 5, 7, 7, 6, 6, 4, 0, 6, 1, 7, 2, 4, 3, 5]\n    int[] creaseLengths = [2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2]";

fn load(text: &str) -> Scene {
    load_usda_str(text, Time::Start, &LoadOptions::default()).expect("loads")
}

fn refined(text: &str, level: u32) -> Scene {
    let mut s = load(text);
    s.refine_subdivision(&LevelRule::Fixed(level));
    s
}

/// The vertex nearest `p`, and its distance.
fn nearest(s: &Scene, p: DVec3) -> (usize, f64) {
    s.meshes[0]
        .positions
        .iter()
        .enumerate()
        .map(|(i, q)| (i, q.distance(p)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap()
}

/// The limit of the centre of a cube face (a valence-4 vertex after one step, among
/// valence-3 corners): `(16 · 1 + 4 · 4 · 3/4 + 4 · 5/9) / 36 = 68/81 = 0.839506…`, at every
/// level; its normal is the face's.
#[test]
fn default_scheme_cube_face_centres_are_the_limit_points() {
    let text = cube("");
    let s = load(&text);
    assert!(
        s.meshes[0].subdivision.is_some(),
        "unauthored scheme is catmullClark"
    );
    for level in 1..=4 {
        let s = refined(&text, level);
        let m = &s.meshes[0];
        assert!(m.subdivision.is_none());
        assert_eq!(m.triangles.len(), 6 * 2 * 4usize.pow(level));
        for axis in [
            DVec3::X,
            DVec3::NEG_X,
            DVec3::Y,
            DVec3::NEG_Y,
            DVec3::Z,
            DVec3::NEG_Z,
        ] {
            let (i, d) = nearest(&s, axis * 0.84);
            assert!(
                d < 1e-3,
                "level {level}: no vertex near {axis} (nearest at {d})"
            );
            let p = m.positions[i];
            assert!(
                (p.dot(axis) - 68.0 / 81.0).abs() < 1e-6,
                "level {level}: face centre {p} (expected {} along {axis})",
                68.0 / 81.0
            );
            assert!((p - axis * p.dot(axis)).length() < 1e-6);
            // The normal at every corner using that vertex is the face's.
            let normals = m.normals.as_ref().unwrap();
            for (t, tri) in m.triangles.iter().enumerate() {
                for k in 0..3 {
                    if tri[k] as usize == i {
                        assert!(normals[t][k].distance(axis) < 1e-6, "{}", normals[t][k]);
                    }
                }
            }
        }
        // Every vertex lies inside the cage and outside the inscribed limit body's face
        // centres' sphere, and every triangle faces outward.
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let g = (b - a).cross(c - a);
            assert!(
                g.dot(a + b + c) > 0.0,
                "triangle faces inward at level {level}"
            );
        }
        assert!(
            m.positions
                .iter()
                .all(|p| p.abs().max_element() <= 1.0 + 1e-9)
        );
    }
    // Level 0 keeps the cage's polygons.
    let s0 = refined(&text, 0);
    assert_eq!(s0.meshes[0].triangles.len(), 12);
    assert_eq!(s0.meshes[0].positions.len(), 8);
    assert_eq!(s0.drawn.refined_meshes, 0);
    assert_eq!(refined(&text, 2).drawn.refined_meshes, 1);
}

/// Infinitely sharp creases on all twelve edges keep the cube a cube (its limit surface is
/// the cage); a semi-sharp crease of sharpness 2 lies in between.
#[test]
fn creases_sharpen_the_cube() {
    let sharp = cube(&format!(
        "{CUBE_EDGES}\n    float[] creaseSharpnesses = [10]"
    ));
    // One sharpness for one chain is inconsistent with 12 chains: use one per chain.
    let per_chain = "float[] creaseSharpnesses = [10, 10, 10, 10, 10, 10, 10, 10, 10, 10, 10, 10]";
    let s = load(&sharp);
    assert!(
        s.warnings
            .iter()
            .any(|w| w.message.contains("creases ignored")),
        "{:?}",
        s.warnings
    );
    let s = refined(&cube(&format!("{CUBE_EDGES}\n    {per_chain}")), 3);
    let m = &s.meshes[0];
    for p in &m.positions {
        assert!(
            (p.abs().max_element() - 1.0).abs() < 1e-6,
            "{p} is off the cube"
        );
    }
    let (i, _) = nearest(&s, DVec3::Z);
    assert!((m.positions[i].z - 1.0).abs() < 1e-6);
    // Semi-sharp creases lie between smooth and sharp: sharpness 0.5 moves the face centre
    // part of the way; sharpness 2 keeps each face's first level planar (so its centre stays
    // at 1) but rounds the corners and edges part of the way.
    let semi = |s: f64| {
        cube(&format!(
            "{CUBE_EDGES}\n    float[] creaseSharpnesses = [{}]",
            vec![s.to_string(); 12].join(", ")
        ))
    };
    let half = refined(&semi(0.5), 3);
    let (i, _) = nearest(&half, DVec3::Z);
    let z = half.meshes[0].positions[i].z;
    assert!(
        z > 68.0 / 81.0 + 1e-3 && z < 1.0 - 1e-3,
        "sharpness 0.5: face centre at {z}"
    );
    let smooth = refined(&cube(""), 3);
    let two = refined(&semi(2.0), 3);
    for dir in [DVec3::ONE, DVec3::new(1.0, 0.0, 1.0)] {
        let reach = |s: &Scene| {
            let (i, _) = nearest(s, dir);
            s.meshes[0].positions[i].dot(dir) / dir.length_squared()
        };
        let (r0, r2) = (reach(&smooth), reach(&two));
        assert!(
            r0 < r2 - 1e-3 && r2 < 1.0 - 1e-3,
            "{dir}: smooth {r0}, sharpness 2 {r2}"
        );
    }
    // Bilinear refines linearly: the cube stays a cube.
    let s = refined(&cube("uniform token subdivisionScheme = \"bilinear\""), 2);
    assert_eq!(s.meshes[0].triangles.len(), 6 * 2 * 16);
    for p in &s.meshes[0].positions {
        assert!(
            (p.abs().max_element() - 1.0).abs() < 1e-6,
            "{p} is off the cube"
        );
    }
    // `none` is polygons: no cage.
    let s = load(&cube("uniform token subdivisionScheme = \"none\""));
    assert!(s.meshes[0].subdivision.is_none());
}

/// Loop's limit of a vertex of valence n with its ring at distance 1 in the plane below:
/// `ω / (ω + n)` of its height, `ω = 3 / (8β)`, `β = (5/8 − (3/8 + cos(2π/n)/4)²) / n`
/// (Loop 1987; the limit mask `(ω v + Σ vᵢ) / (ω + n)`): 48/110 = 0.436… for n = 4.
#[test]
fn loop_octahedron_apex_is_the_limit_point() {
    let text = r#"#usda 1.0
def Mesh "Octa" {
    uniform token subdivisionScheme = "loop"
    int[] faceVertexCounts = [3, 3, 3, 3, 3, 3, 3, 3]
    int[] faceVertexIndices = [0, 2, 4, 0, 4, 3, 0, 3, 5, 0, 5, 2, 1, 4, 2, 1, 3, 4, 1, 5, 3, 1, 2, 5]
    point3f[] points = [(0, 0, 1), (0, 0, -1), (1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0)]
}
"#;
    let n = 4.0f64;
    let beta = (5.0 / 8.0 - (3.0 / 8.0 + (2.0 * std::f64::consts::PI / n).cos() / 4.0).powi(2)) / n;
    let omega = 3.0 / (8.0 * beta);
    let apex = omega / (omega + n);
    for level in 1..=3 {
        let s = refined(text, level);
        let m = &s.meshes[0];
        assert_eq!(m.triangles.len(), 8 * 4usize.pow(level));
        let (i, _) = nearest(&s, DVec3::Z * apex);
        assert!(
            (m.positions[i].z - apex).abs() < 1e-6,
            "level {level}: apex at {} (expected {apex})",
            m.positions[i]
        );
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            assert!((b - a).cross(c - a).dot(a + b + c) > 0.0, "inward triangle");
        }
    }
}

/// Blender's subdivision surface modifier (OpenSubdiv in C++) at its limit surface is the
/// oracle: `tests/data/subdiv/blender_limit.py` (Blender 5.0.1 from PyPI's `bpy`) wrote the
/// cages and the limit vertices of Blender's evaluated mesh. lux's refined vertices are the
/// same points: every one of lux's is within 2e-6 of one of Blender's, and the counts agree
/// (cube, creased cube with a corner, a prism with n-gon caps and a semi-sharp rim, an open
/// sheet with a pentagon and triangles under both boundary rules).
#[test]
fn limit_points_equal_blenders() {
    let json: serde_json::Value =
        serde_json::from_str(include_str!("data/subdiv/blender_limit.json")).expect("oracle json");
    let cages = json["cages"].as_array().unwrap();
    assert_eq!(cages.len(), 5);
    for c in cages {
        let name = c["name"].as_str().unwrap();
        let list = |v: &serde_json::Value| -> Vec<String> {
            v.as_array()
                .unwrap()
                .iter()
                .map(|x| x.to_string())
                .collect()
        };
        let points: Vec<String> = c["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| format!("({})", list(p).join(", ")))
            .collect();
        let faces = c["faces"].as_array().unwrap();
        let counts: Vec<String> = faces
            .iter()
            .map(|f| f.as_array().unwrap().len().to_string())
            .collect();
        let indices: Vec<String> = faces.iter().flat_map(list).collect();
        let mut extra = String::new();
        let creases = c["creases"].as_array().unwrap();
        if !creases.is_empty() {
            let ix: Vec<String> = creases
                .iter()
                .flat_map(|e| [e[0].to_string(), e[1].to_string()])
                .collect();
            let s: Vec<String> = creases.iter().map(|e| e[2].to_string()).collect();
            extra += &format!(
                "int[] creaseIndices = [{}]\n int[] creaseLengths = [{}]\n float[] creaseSharpnesses = [{}]\n",
                ix.join(", "),
                vec!["2"; creases.len()].join(", "),
                s.join(", ")
            );
        }
        let corners = c["corners"].as_array().unwrap();
        if !corners.is_empty() {
            let ix: Vec<String> = corners.iter().map(|e| e[0].to_string()).collect();
            let s: Vec<String> = corners.iter().map(|e| e[1].to_string()).collect();
            extra += &format!(
                "int[] cornerIndices = [{}]\n float[] cornerSharpnesses = [{}]\n",
                ix.join(", "),
                s.join(", ")
            );
        }
        let text = format!(
            "#usda 1.0\ndef Mesh \"M\" {{\n uniform token subdivisionScheme = {}\n uniform token interpolateBoundary = {}\n int[] faceVertexCounts = [{}]\n int[] faceVertexIndices = [{}]\n point3f[] points = [{}]\n {extra}}}\n",
            c["scheme"],
            c["boundary"],
            counts.join(", "),
            indices.join(", "),
            points.join(", ")
        );
        let level = c["level"].as_u64().unwrap() as u32;
        let s = refined(&text, level);
        assert!(s.warnings.is_empty(), "{name}: {:?}", s.warnings);
        let ours = &s.meshes[0].positions;
        let theirs: Vec<DVec3> = c["blender"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| {
                DVec3::new(
                    p[0].as_f64().unwrap(),
                    p[1].as_f64().unwrap(),
                    p[2].as_f64().unwrap(),
                )
            })
            .collect();
        assert_eq!(ours.len(), theirs.len(), "{name}: vertex count");
        let mut worst = 0.0f64;
        for p in ours {
            let d = theirs
                .iter()
                .map(|q| q.distance(*p))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
        assert!(
            worst < 2e-6,
            "{name}: a vertex is {worst} from Blender's nearest"
        );
    }
}

/// A flat `k × k` grid of unit quads in z = 0 with `extra` authored.
fn grid(k: usize, extra: &str) -> String {
    let mut points = Vec::new();
    for j in 0..=k {
        for i in 0..=k {
            points.push(format!("({i}, {j}, 0)"));
        }
    }
    let mut indices = Vec::new();
    for j in 0..k {
        for i in 0..k {
            let a = j * (k + 1) + i;
            indices.extend([a, a + 1, a + k + 2, a + k + 1].map(|x| x.to_string()));
        }
    }
    format!(
        "#usda 1.0\ndef Mesh \"Grid\" {{\n int[] faceVertexCounts = [{}]\n int[] faceVertexIndices = [{}]\n point3f[] points = [{}]\n {extra}\n}}\n",
        vec!["4"; k * k].join(", "),
        indices.join(", "),
        points.join(", ")
    )
}

/// Primvars follow their interpolation: on a flat grid whose `displayColor` (vertex) and
/// `st` (faceVarying, no seams) equal the points' x and y, the refined values equal the
/// refined points' x and y at every corner (subdivision reproduces linear functions, and the
/// face-varying patches follow the same topology); `varying` data is bilinear over each face,
/// `uniform` constant per face.
#[test]
fn primvars_are_refined_by_their_interpolation() {
    let k = 3;
    let xy: Vec<String> = (0..=k)
        .flat_map(|j| (0..=k).map(move |i| format!("({i}, {j})")))
        .collect();
    let xy3: Vec<String> = (0..=k)
        .flat_map(|j| (0..=k).map(move |i| format!("({i}, {j}, 0)")))
        .collect();
    let mut fv_index = Vec::new();
    for j in 0..k {
        for i in 0..k {
            let a = j * (k + 1) + i;
            fv_index.extend([a, a + 1, a + k + 2, a + k + 1].map(|x| x.to_string()));
        }
    }
    let text = grid(
        k,
        &format!(
            "color3f[] primvars:displayColor = [{}] (interpolation = \"vertex\")\n \
             texCoord2f[] primvars:st = [{}] (interpolation = \"faceVarying\")\n \
             int[] primvars:st:indices = [{}]",
            xy3.join(", "),
            xy.join(", "),
            fv_index.join(", ")
        ),
    );
    // The loader reads texture coordinates for a material that reads them: bind one.
    let with_material = text.replace(
        "def Mesh \"Grid\" {",
        "def Material \"M\" {\n token outputs:surface.connect = </M/S.outputs:surface>\n def Shader \"S\" {\n uniform token info:id = \"UsdPreviewSurface\"\n color3f inputs:diffuseColor.connect = </M/T.outputs:rgb>\n token outputs:surface\n }\n def Shader \"T\" {\n uniform token info:id = \"UsdUVTexture\"\n asset inputs:file = @missing.png@\n float2 inputs:st.connect = </M/R.outputs:result>\n float3 outputs:rgb\n }\n def Shader \"R\" {\n uniform token info:id = \"UsdPrimvarReader_float2\"\n token inputs:varname = \"st\"\n float2 outputs:result\n }\n}\ndef Mesh \"Grid\" (prepend apiSchemas = [\"MaterialBindingAPI\"]) {\n rel material:binding = </M>",
    );
    for level in [1, 2] {
        let s = refined(&with_material, level);
        let m = s.meshes.iter().find(|m| m.path == "/Grid").unwrap();
        let colors = m.colors.as_ref().expect("colours");
        let uvs = m.uvs.as_ref().expect("uvs");
        for (t, tri) in m.triangles.iter().enumerate() {
            for c in 0..3 {
                let p = m.positions[tri[c] as usize];
                assert!(
                    colors[t][c].distance(p) < 1e-6,
                    "vertex colour {} at {p}",
                    colors[t][c]
                );
                assert!(
                    uvs[t][c].distance(p.truncate()) < 1e-6,
                    "st {} at {p}",
                    uvs[t][c]
                );
            }
        }
    }
    // Varying and uniform.
    let corners: Vec<String> = (0..(k + 1) * (k + 1))
        .map(|i| format!("({i}, 0, 0)"))
        .collect();
    let faces: Vec<String> = (0..k * k).map(|f| format!("(0, {f}, 0)")).collect();
    let varying = grid(
        k,
        &format!(
            "color3f[] primvars:displayColor = [{}] (interpolation = \"varying\")",
            corners.join(", ")
        ),
    );
    let s = refined(&varying, 2);
    let m = &s.meshes[0];
    for (tri, colors) in m.triangles.iter().zip(m.colors.as_ref().unwrap()) {
        for (&v, color) in tri.iter().zip(colors) {
            let p = m.positions[v as usize];
            // Index of a point: x + (k + 1) y, bilinear in the face as x and y are.
            let expected = p.x + (k + 1) as f64 * p.y;
            let got = color.x;
            assert!((got - expected).abs() < 1e-6, "varying {got} at {p}");
        }
    }
    let uniform = grid(
        k,
        &format!(
            "color3f[] primvars:displayColor = [{}] (interpolation = \"uniform\")",
            faces.join(", ")
        ),
    );
    let s = refined(&uniform, 2);
    let m = &s.meshes[0];
    for (t, tri) in m.triangles.iter().enumerate() {
        let centre = tri.iter().map(|&i| m.positions[i as usize]).sum::<DVec3>() / 3.0;
        let face = centre.x.floor() + k as f64 * centre.y.floor();
        for color in m.colors.as_ref().unwrap()[t] {
            assert_eq!(color.y, face);
        }
    }
}

/// A UV seam stays a seam: two quads sharing an edge whose corners have their own UVs on each
/// side keep each side's values along the shared edge (`faceVaryingLinearInterpolation` at
/// its default), and `all` interpolates UVs bilinearly over each face.
#[test]
fn face_varying_seams_and_linear_interpolation() {
    let two = |rule: &str| {
        format!(
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
        float2 inputs:st.connect = </M/R.outputs:result>
        float3 outputs:rgb
    }}
    def Shader "R" {{
        uniform token info:id = "UsdPrimvarReader_float2"
        token inputs:varname = "st"
        float2 outputs:result
    }}
}}
def Mesh "Two" (prepend apiSchemas = ["MaterialBindingAPI"]) {{
    rel material:binding = </M>
    {rule}
    int[] faceVertexCounts = [4, 4]
    int[] faceVertexIndices = [0, 1, 4, 3, 1, 2, 5, 4]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (2, 0, 0), (0, 1, 0), (1, 1, 0), (2, 1, 0)]
    texCoord2f[] primvars:st = [(0, 0), (0.45, 0), (0.45, 1), (0, 1), (0.55, 0), (1, 0), (1, 1), (0.55, 1)] (interpolation = "faceVarying")
    int[] primvars:st:indices = [0, 1, 2, 3, 4, 5, 6, 7]
}}
"#
        )
    };
    let s = refined(&two(""), 2);
    let m = s.meshes.iter().find(|m| m.path == "/Two").unwrap();
    let uvs = m.uvs.as_ref().unwrap();
    for (t, tri) in m.triangles.iter().enumerate() {
        let centre = tri.iter().map(|&i| m.positions[i as usize]).sum::<DVec3>() / 3.0;
        for c in 0..3 {
            let (p, uv) = (m.positions[tri[c] as usize], uvs[t][c]);
            if centre.x < 1.0 {
                assert!(uv.x <= 0.45 + 1e-6, "left face takes {uv} at {p}");
            } else {
                assert!(uv.x >= 0.55 - 1e-6, "right face takes {uv} at {p}");
            }
            if (p.x - 1.0).abs() < 1e-9 {
                let want = if centre.x < 1.0 { 0.45 } else { 0.55 };
                assert!((uv.x - want).abs() < 1e-6, "seam point {p}: {uv}");
            }
        }
    }
    // `all` interpolates bilinearly over each face, the default smoothly: on a flat unit
    // grid (whose limit map is the identity: x = i + u on face i) with st = (x², y²) at the
    // points, `all` gives the piecewise-bilinear values, the smooth rule the cubic spline's.
    let k = 3;
    let sq: Vec<String> = (0..=k)
        .flat_map(|j| (0..=k).map(move |i| format!("({}, {})", i * i, j * j)))
        .collect();
    let mut fv_index = Vec::new();
    for j in 0..k {
        for i in 0..k {
            let a = j * (k + 1) + i;
            fv_index.extend([a, a + 1, a + k + 2, a + k + 1].map(|x| x.to_string()));
        }
    }
    let material = two("").split("def Mesh").next().unwrap().to_owned();
    let sheet = |rule: &str| {
        let g = grid(
            k,
            &format!(
                "{rule}\n texCoord2f[] primvars:st = [{}] (interpolation = \"faceVarying\")\n int[] primvars:st:indices = [{}]",
                sq.join(", "),
                fv_index.join(", ")
            ),
        );
        g.replace("#usda 1.0\n", &material).replace(
            "def Mesh \"Grid\" {",
            "def Mesh \"Grid\" (prepend apiSchemas = [\"MaterialBindingAPI\"]) {\n rel material:binding = </M>",
        )
    };
    let piecewise = |x: f64, centre: f64| {
        let i = centre.floor();
        let t = x - i;
        (1.0 - t) * i * i + t * (i + 1.0) * (i + 1.0)
    };
    let mut smooth_differs = 0.0f64;
    for (rule, linear) in [
        (
            "uniform token faceVaryingLinearInterpolation = \"all\"",
            true,
        ),
        (
            "uniform token faceVaryingLinearInterpolation = \"none\"",
            false,
        ),
    ] {
        let s = refined(&sheet(rule), 2);
        let m = s.meshes.iter().find(|m| m.path == "/Grid").unwrap();
        let uvs = m.uvs.as_ref().unwrap();
        for (t, tri) in m.triangles.iter().enumerate() {
            let centre = tri.iter().map(|&i| m.positions[i as usize]).sum::<DVec3>() / 3.0;
            for c in 0..3 {
                let p = m.positions[tri[c] as usize];
                assert!(
                    (p.x * 4.0 - (p.x * 4.0).round()).abs() < 1e-6,
                    "limit map is not the identity at {p}"
                );
                let want = piecewise(p.x, centre.x);
                let d = (uvs[t][c].x - want).abs();
                if linear {
                    assert!(d < 1e-6, "all: {} at {p}, expected {want}", uvs[t][c]);
                } else {
                    smooth_differs = smooth_differs.max(d);
                }
            }
        }
    }
    assert!(
        smooth_differs > 1e-2,
        "the smooth rule gave the bilinear values ({smooth_differs})"
    );
}

/// Orientation, mirroring and holes: a `leftHanded` cube's front side is inside (its refined
/// triangles and normals face in), a cube mirrored by its transform still faces out, a hole
/// leaves its face out.
#[test]
fn orientation_mirroring_and_holes() {
    let outward = |s: &Scene| -> (usize, usize) {
        let m = &s.meshes[0];
        let normals = m.normals.as_ref().unwrap();
        let mut out = (0, 0);
        for (t, tri) in m.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| m.positions[i as usize]);
            let centre = (a + b + c) / 3.0;
            let g = (b - a).cross(c - a);
            assert_eq!(g.dot(centre) > 0.0, normals[t][0].dot(centre) > 0.0);
            if g.dot(centre) > 0.0 {
                out.0 += 1;
            } else {
                out.1 += 1;
            }
        }
        out
    };
    let n = 6 * 2 * 16;
    assert_eq!(outward(&refined(&cube(""), 2)), (n, 0));
    assert_eq!(
        outward(&refined(
            &cube("uniform token orientation = \"leftHanded\""),
            2
        )),
        (0, n)
    );
    let mirrored = cube(
        "double3 xformOp:scale = (-1, 1, 2)\n uniform token[] xformOpOrder = [\"xformOp:scale\"]",
    );
    let s = refined(&mirrored, 2);
    assert_eq!(outward(&s), (n, 0));
    assert!(
        s.meshes[0].positions.iter().any(|p| p.z > 1.5),
        "the scale applies"
    );
    // The +z face (face 0) is a hole: no triangle over its middle.
    let s = refined(&cube("int[] holeIndices = [0]"), 2);
    assert_eq!(s.meshes[0].triangles.len(), 5 * 2 * 16);
    let (_, d) = nearest(&s, DVec3::Z * 0.84);
    assert!(d > 0.1);
}

/// Bilinear refinement of an n-gon: its sub-quads' centres are the means of a corner, the
/// two edge middles beside it and the face's centroid.
#[test]
fn bilinear_ngon_is_refined_linearly() {
    let text = r#"#usda 1.0
def Mesh "Pentagon" {
    uniform token subdivisionScheme = "bilinear"
    int[] faceVertexCounts = [5]
    int[] faceVertexIndices = [0, 1, 2, 3, 4]
    point3f[] points = [(0, 0, 0), (2, 0, 0.5), (2.5, 1.5, 0), (1, 2.5, 0.3), (-0.5, 1.5, 0)]
}
"#;
    let s = refined(text, 2);
    let m = &s.meshes[0];
    assert_eq!(m.triangles.len(), 5 * 2 * 4);
    let p: Vec<DVec3> = [
        (0., 0., 0.),
        (2., 0., 0.5),
        (2.5, 1.5, 0.),
        (1., 2.5, 0.3),
        (-0.5, 1.5, 0.),
    ]
    .map(|(x, y, z)| DVec3::new(x, y, z))
    .to_vec();
    let centroid = p.iter().sum::<DVec3>() / 5.0;
    for k in 0..5 {
        let (prev, next) = (p[(k + 4) % 5], p[(k + 1) % 5]);
        let centre = (p[k] + (p[k] + next) / 2.0 + centroid + (prev + p[k]) / 2.0) / 4.0;
        let (_, d) = nearest(&s, centre);
        assert!(d < 1e-6, "sub-quad {k}: no vertex at {centre} ({d})");
    }
}

/// What cannot be refined as authored is said, naming the prim, and drawn as polygons.
#[test]
fn unrefinable_cages_are_warned_and_drawn_as_polygons() {
    let warned = |text: &str, what: &str| {
        let s = load(text);
        assert!(s.meshes[0].subdivision.is_none());
        assert!(
            s.warnings
                .iter()
                .any(|w| w.prim == "/Cube" && w.message.contains(what)),
            "{what}: {:?}",
            s.warnings
        );
        assert_eq!(s.meshes[0].triangles.len(), 12);
    };
    warned(
        &cube("uniform token subdivisionScheme = \"catmark\""),
        "not a UsdGeomMesh scheme",
    );
    warned(
        &cube("uniform token subdivisionScheme = \"loop\""),
        "needs triangles only",
    );
    let s = load(&cube("uniform token interpolateBoundary = \"sharp\""));
    assert!(
        s.warnings
            .iter()
            .any(|w| w.message.contains("interpolateBoundary \"sharp\""))
    );
    assert!(s.meshes[0].subdivision.is_some());
    let s = load(&cube(
        "int[] cornerIndices = [0, 1]\n float[] cornerSharpnesses = [1]",
    ));
    assert!(
        s.warnings
            .iter()
            .any(|w| w.message.contains("corners ignored"))
    );
    // A face repeating a vertex is left out of the surface, with a warning.
    let degenerate = cube("")
        .replace(
            "int[] faceVertexCounts = [4, 4, 4, 4, 4, 4]",
            "int[] faceVertexCounts = [4, 4, 4, 4, 4, 4, 3]",
        )
        .replace("6, 0, 2, 4]", "6, 0, 2, 4, 0, 0, 1]");
    let s = refined(&degenerate, 1);
    assert_eq!(s.meshes[0].triangles.len(), 6 * 2 * 4);
    assert!(
        s.warnings
            .iter()
            .any(|w| w.message.contains("repeat a vertex")),
        "{:?}",
        s.warnings
    );
}

/// A prototype's surface is refined once, for all its instances; the screen rule picks the
/// level its nearest instance needs.
#[test]
fn prototypes_are_refined_once_at_their_nearest_instances_level() {
    let text = r#"#usda 1.0
class Xform "Proto" {
    def Mesh "Cube" {
        int[] faceVertexCounts = [4, 4, 4, 4, 4, 4]
        int[] faceVertexIndices = [0, 1, 3, 2, 2, 3, 5, 4, 4, 5, 7, 6, 6, 7, 1, 0, 1, 7, 5, 3, 6, 0, 2, 4]
        point3f[] points = [(-1, -1, 1), (1, -1, 1), (-1, 1, 1), (1, 1, 1), (-1, 1, -1), (1, 1, -1), (-1, -1, -1), (1, -1, -1)]
    }
}
def Xform "Near" (instanceable = true prepend references = </Proto>) {
    double3 xformOp:translate = (0, 0, -10)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
def Xform "Far" (instanceable = true prepend references = </Proto>) {
    double3 xformOp:translate = (0, 0, -1000)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
def Camera "Cam" {
}
"#;
    let mut s = load(text);
    assert_eq!(s.meshes.len(), 1, "one prototype mesh");
    assert_eq!(s.instances.len(), 2);
    let camera = s.cameras[0].clone();
    // The screen rule's closed form: the near cube's +z face (edges 2 long, turning π/2 to
    // its neighbours) is 9 from the eye: 2 · (50 / 20.955 · 960) / 9 = 509 pixels, a
    // sagitta ratio 509 · (π/2) / (8 · 0.25) = 399.8: level ⌈log₄ 399.8⌉ = 5. The far one,
    // 999 away: ratio 3.6, level 1.
    let level = |path: &str| {
        lux_usd::subdiv::screen_level(
            s.meshes[0].subdivision.as_ref().unwrap(),
            &s.instances
                .iter()
                .find(|i| i.path == path)
                .unwrap()
                .to_world,
            &camera,
            960,
            10,
        )
    };
    let ratio = |d: f64| {
        2.0 * 50.0 / 20.955 * 960.0 / d * std::f64::consts::FRAC_PI_2
            / (8.0 * lux_usd::subdiv::TARGET_SAGITTA_PIXELS)
    };
    assert_eq!(level("/Near"), (ratio(9.0).log2() / 2.0).ceil() as u32);
    assert_eq!(level("/Near"), 5);
    assert_eq!(level("/Far"), 1);
    assert!(ratio(999.0) > 1.0 && ratio(999.0) < 4.0);
    let refined = s.refine_subdivision(&LevelRule::Screen {
        camera: &camera,
        width: 960,
        max_level: 4,
    });
    // The near instance's level 5, capped at 4; refined once for both.
    assert_eq!(refined, [lux_usd::subdiv::Refinement { mesh: 0, level: 4 }]);
    assert_eq!(s.meshes.len(), 1);
    assert_eq!(s.meshes[0].triangles.len(), 6 * 2 * 4usize.pow(4));
}

/// The screen rule refines where the surface bends: a flat sheet and a cube whose edges are
/// all infinitely sharp (its limit is the cage) stay at level 1 however close the camera is;
/// the smooth cube seen from its centre refines.
#[test]
fn screen_rule_follows_the_bend_not_the_size() {
    let camera = lux_usd::Camera::with_defaults("/Cam", glam::DMat4::IDENTITY);
    let level = |text: &str| {
        let s = load(text);
        lux_usd::subdiv::screen_level(
            s.meshes[0].subdivision.as_ref().unwrap(),
            &glam::DMat4::IDENTITY,
            &camera,
            1920,
            10,
        )
    };
    assert_eq!(level(&grid(3, "")), 1);
    let sharp = format!(
        "{CUBE_EDGES}\n float[] creaseSharpnesses = [{}]",
        ["10"; 12].join(", ")
    );
    assert_eq!(level(&cube(&sharp)), 1);
    // From the centre, every face is 1 away: 2 · (50 / 20.955 · 1920) / 1 · (π/2) / 2 =
    // 7197 → level ⌈log₄ 7197⌉ = 7.
    assert_eq!(level(&cube("")), 7);
}

/// `triangleSubdivisionRule = "smooth"` changes the limit surface of a mesh with triangles
/// (OpenSubdiv's smooth-triangle weights) and not of a quad mesh.
#[test]
fn smooth_triangle_rule_acts_on_triangles_only() {
    let pyramid = |rule: &str| {
        format!(
            r#"#usda 1.0
def Mesh "Pyramid" {{
    {rule}
    int[] faceVertexCounts = [4, 3, 3, 3, 3]
    int[] faceVertexIndices = [0, 3, 2, 1, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4]
    point3f[] points = [(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1), (0, 1.5, 0)]
}}
"#
        )
    };
    let smooth = "uniform token triangleSubdivisionRule = \"smooth\"";
    let a = refined(&pyramid(""), 2);
    let b = refined(&pyramid(smooth), 2);
    let moved = a.meshes[0]
        .positions
        .iter()
        .zip(&b.meshes[0].positions)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f64::max);
    assert!(moved > 1e-3, "the smooth rule moved no vertex ({moved})");
    let a = refined(&cube(""), 2);
    let b = refined(&cube(smooth), 2);
    assert_eq!(a.meshes[0].positions, b.meshes[0].positions);
}

/// A `MeshLightAPI` subdivision surface emits from its limit surface: the light's triangles
/// (light space) are the refined ones.
#[test]
fn mesh_lights_emit_from_the_refined_surface() {
    let text = cube("").replace(
        "def Mesh \"Cube\" {",
        "def Mesh \"Cube\" (prepend apiSchemas = [\"MeshLightAPI\"]) {\n    double3 xformOp:translate = (0, 5, 0)\n    uniform token[] xformOpOrder = [\"xformOp:translate\"]",
    );
    let s = refined(&text, 2);
    let m = &s.meshes[0];
    let light = &s.lights[m.light.expect("a mesh light")];
    let lux_math::LightShape::Mesh { triangles } = &light.shape else {
        panic!("not a mesh light")
    };
    assert_eq!(triangles.len(), m.triangles.len());
    for (t, tri) in triangles.iter().zip(&m.triangles) {
        for (p, &i) in t.iter().zip(tri) {
            let world = light.light_to_world.transform_point3(*p);
            assert!(world.distance(m.positions[i as usize]) < 1e-9);
        }
    }
}
