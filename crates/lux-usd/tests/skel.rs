//! Skinned meshes (UsdSkel) posed at the frame, against usd-core.
//!
//! Every expected number here is usd-core 26.11's: `tests/data/skel/oracle.json` was written by
//! `tests/data/skel/bake.py`, which poses each stage with `UsdSkel.BakeSkinning` (into the session
//! layer) and records the world-space points (`ComputeLocalToWorldTransform(time)` × baked
//! points), the world-space normals where authored, the rigid world transform of posed implicit
//! surfaces and the drawn world box. The boxes in [`SOURCES_BOXES`] are the posed boxes listed
//! in `tests/data/skel/SOURCES.md` (usd-core's `UsdGeom.BBoxCache` of the posed stage).
//!
//! A point must match to 1e-5 of its mesh's world box size, a normal to 1e-4 rad.

use glam::{DMat4, DVec3};
use lux_usd::tessellate::{self, Axis};
use lux_usd::{LoadOptions, Scene, Time, load_stage_with};
use serde_json::Value;
use std::path::PathBuf;
use std::sync::OnceLock;

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/skel")
}

fn oracle() -> &'static Value {
    static ORACLE: OnceLock<Value> = OnceLock::new();
    ORACLE.get_or_init(|| {
        let text = std::fs::read_to_string(data().join("oracle.json")).unwrap();
        serde_json::from_str(&text).unwrap()
    })
}

/// The posed world boxes of `SOURCES.md` (usd-core 26.11), with the time they are at. lbs.usda's
/// box there includes its BasisCurves, which lux does not draw: its drawn box is checked
/// against the oracle's instead.
const SOURCES_BOXES: [(&str, f64, [f64; 3], [f64; 3]); 3] = [
    (
        "usdwg/test_assets/USDZ/RiggedSimple/RiggedSimple.usdz",
        1.0,
        [-1.0, -0.394747, -1.0],
        [1.0, 8.75541, 1.0],
    ),
    (
        "usdwg/test_assets/USDZ/RiggedFigure/RiggedFigure.usdz",
        0.0,
        [-0.277028, 2.06e-07, -0.112359],
        [0.274803, 1.47614, 0.239955],
    ),
    (
        "openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLUsdSkel/arm.usda",
        1.0,
        [-0.5, -0.5, 0.0],
        [0.5, 0.5, 4.0],
    ),
];

fn v3(v: &Value) -> DVec3 {
    let a = v.as_array().unwrap();
    DVec3::new(
        a[0].as_f64().unwrap(),
        a[1].as_f64().unwrap(),
        a[2].as_f64().unwrap(),
    )
}

fn ints(v: &Value) -> Vec<usize> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap() as usize)
        .collect()
}

fn bounds(points: impl IntoIterator<Item = DVec3>) -> (DVec3, DVec3) {
    points.into_iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    )
}

fn size(lo: DVec3, hi: DVec3) -> f64 {
    (hi - lo).max_element().max(1e-12)
}

fn load(file: &str, time: f64) -> Scene {
    load_stage_with(data().join(file), Time::Code(time), &LoadOptions::default())
        .unwrap_or_else(|e| panic!("{file} @ {time}: {e}"))
}

/// lux's fan triangulation of the oracle's faces (`mesh_topology`): per triangle its points and
/// face-vertex indices.
fn fan(counts: &[usize], indices: &[usize]) -> Vec<([usize; 3], [usize; 3])> {
    let mut out = Vec::new();
    let mut start = 0;
    for &n in counts {
        for k in 1..n.saturating_sub(1) {
            let fv = [start, start + k, start + k + 1];
            out.push((fv.map(|i| indices[i]), fv));
        }
        start += n;
    }
    out
}

/// The local points lux tessellates an implicit surface into, from the oracle's attributes.
fn tessellated(kind: &str, attrs: &Value) -> Vec<DVec3> {
    let f = |k: &str| attrs[k].as_f64().unwrap();
    let axis = || Axis::parse(attrs["axis"].as_str());
    match kind {
        "Sphere" => tessellate::sphere(f("radius")),
        "Cube" => tessellate::cube(f("size")),
        "Cylinder" => tessellate::cylinder(f("radius"), f("height"), axis()),
        "Cone" => tessellate::cone(f("radius"), f("height"), axis()),
        "Capsule" => tessellate::capsule(f("radius"), f("height"), axis()),
        _ => tessellate::plane(f("width"), f("length"), axis()),
    }
    .points
}

/// A skinned BasisCurves prim (cubic Bézier, 4 points a curve, unauthored widths: Hydra's 1):
/// lux draws a tube of radius ½ around the curve its posed control points make. Every tube
/// vertex lies within the box of usd-core's posed control points grown by ½ (a Bézier lies in
/// its control points' hull), and every curve's posed end points (which a Bézier passes
/// through) have a ring of (12) tube vertices ½ away. Unposed, neither holds.
fn check_tube(what: &str, path: &str, mesh: &lux_usd::Mesh, g: &Value) {
    let points: Vec<DVec3> = g["points"].as_array().unwrap().iter().map(v3).collect();
    let (lo, hi) = bounds(points.iter().copied());
    for p in &mesh.positions {
        assert!(
            p.cmpge(lo - 0.5 - 1e-6).all() && p.cmple(hi + 0.5 + 1e-6).all(),
            "{what}: {path} tube vertex {p} outside the posed control points' box {lo}..{hi} ± ½"
        );
    }
    let mut start = 0usize;
    for n in ints(&g["curve_vertex_counts"]) {
        assert_eq!(n, 4, "{what}: {path}: one Bézier segment a curve");
        for end in [points[start], points[start + 3]] {
            let ring = mesh
                .positions
                .iter()
                .filter(|p| (p.distance(end) - 0.5).abs() < 1e-6)
                .count();
            assert!(
                ring >= 12,
                "{what}: {path}: {ring} tube vertices ½ from the posed end point {end} (a \
                 12-sided ring expected)"
            );
        }
        start += n;
    }
}

/// The largest point error of `scene` against the oracle's case, relative to each mesh's box
/// size, and the largest normal angle (radians). Panics on anything missing.
fn compare(scene: &Scene, case: &Value) -> (f64, f64) {
    let what = format!("{} @ {}", case["file"], case["time"]);
    let (mut worst_point, mut worst_angle) = (0.0f64, 0.0f64);
    for g in case["gprims"].as_array().unwrap() {
        let path = g["path"].as_str().unwrap();
        let mesh = scene
            .meshes
            .iter()
            .find(|m| m.path == path)
            .unwrap_or_else(|| panic!("{what}: no mesh {path}"));
        if g["type"] == "BasisCurves" {
            check_tube(&what, path, mesh, g);
            continue;
        }
        let expected: Vec<DVec3> = match g.get("points") {
            Some(p) => p.as_array().unwrap().iter().map(v3).collect(),
            None => {
                let m: Vec<f64> = g["local_to_world"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_f64().unwrap())
                    .collect();
                // USD's row-vector matrix, rows as glam's columns.
                let l2w = DMat4::from_cols_slice(&m);
                tessellated(g["type"].as_str().unwrap(), &g["attributes"])
                    .into_iter()
                    .map(|p| l2w.transform_point3(p))
                    .collect()
            }
        };
        assert_eq!(
            mesh.positions.len(),
            expected.len(),
            "{what}: {path} point count"
        );
        let (lo, hi) = bounds(expected.iter().copied());
        let scale = size(lo, hi);
        for (i, (a, b)) in mesh.positions.iter().zip(&expected).enumerate() {
            let e = (*a - *b).length() / scale;
            assert!(
                e <= 1e-5,
                "{what}: {path} point {i} is {a}, usd-core's {b} ({e:.3e} of the box size {scale})"
            );
            worst_point = worst_point.max(e);
        }
        let Some(normals) = g.get("normals") else {
            continue;
        };
        let interp = normals["interpolation"].as_str().unwrap();
        let values: Vec<DVec3> = normals["values"]
            .as_array()
            .unwrap()
            .iter()
            .map(v3)
            .collect();
        let corners = mesh
            .normals
            .as_ref()
            .unwrap_or_else(|| panic!("{what}: {path} has no normals"));
        let tris = fan(
            &ints(&g["face_vertex_counts"]),
            &ints(&g["face_vertex_indices"]),
        );
        assert_eq!(corners.len(), tris.len(), "{what}: {path} triangle count");
        for (t, ((pts, fv), (lux_tri, lux_n))) in tris
            .iter()
            .zip(mesh.triangles.iter().zip(corners))
            .enumerate()
        {
            let lux_tri = lux_tri.map(|i| i as usize);
            // A mirroring transform reverses the winding (corners 1 and 2 swap).
            let order = if lux_tri == *pts {
                [0, 1, 2]
            } else if lux_tri == [pts[0], pts[2], pts[1]] {
                [0, 2, 1]
            } else {
                panic!("{what}: {path} triangle {t} is {lux_tri:?}, expected {pts:?}")
            };
            for k in 0..3 {
                let j = order[k];
                let want = match interp {
                    "faceVarying" => values[fv[j]],
                    "uniform" => values[0],
                    "constant" => values[0],
                    _ => values[pts[j]],
                };
                let got = lux_n[k];
                let angle = got.angle_between(want);
                assert!(
                    angle <= 1e-4,
                    "{what}: {path} triangle {t} corner {k} normal {got}, usd-core's {want} \
                     ({angle:.3e} rad)"
                );
                worst_angle = worst_angle.max(angle);
            }
        }
    }
    // Every skinned gprim usd-core bakes is posed, and counted.
    let posed = case["gprims"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|g| g["posed"].as_bool().unwrap())
        .count();
    assert_eq!(scene.drawn.posed_meshes, posed, "{what}: posed count");
    (worst_point, worst_angle)
}

/// Checks every oracle case of `file`; returns the worst point error and normal angle.
fn check(file: &str) -> (f64, f64) {
    let mut worst = (0.0f64, 0.0f64);
    let mut n = 0;
    for case in oracle()["cases"].as_array().unwrap() {
        if case["file"].as_str() != Some(file) {
            continue;
        }
        n += 1;
        let time = case["time"].as_f64().unwrap();
        let scene = load(file, time);
        let (p, a) = compare(&scene, case);
        worst = (worst.0.max(p), worst.1.max(a));
        // The drawn world box: the oracle's, or SOURCES.md's where it lists this time.
        // (Curves are left out of the box, as bake.py leaves them out: see there.)
        let (lo, hi) = bounds(
            scene
                .meshes
                .iter()
                .filter(|m| m.gprim != lux_usd::Gprim::BasisCurves)
                .flat_map(|m| m.positions.iter().copied()),
        );
        let (want_lo, want_hi) = match SOURCES_BOXES
            .iter()
            .find(|(f, t, _, _)| *f == file && *t == time)
        {
            Some((_, _, lo, hi)) => (DVec3::from(*lo), DVec3::from(*hi)),
            None if file.ends_with("lbs.usda") && time == 1.0 => {
                (v3(&case["drawn_box"][0]), v3(&case["drawn_box"][1]))
            }
            None => continue,
        };
        let tol = 1e-5 * size(want_lo, want_hi);
        assert!(
            (lo - want_lo).abs().max_element() <= tol && (hi - want_hi).abs().max_element() <= tol,
            "{file} @ {time}: lux's box {lo}..{hi}, usd-core's {want_lo}..{want_hi}"
        );
    }
    assert!(n > 0, "no oracle case for {file}");
    eprintln!(
        "{file}: {n} times, worst point error {:.2e} of the box size, worst normal {:.2e} rad",
        worst.0, worst.1
    );
    worst
}

#[test]
fn rigged_simple_matches_usd_core() {
    check("usdwg/test_assets/USDZ/RiggedSimple/RiggedSimple.usdz");
}

#[test]
fn rigged_figure_matches_usd_core() {
    check("usdwg/test_assets/USDZ/RiggedFigure/RiggedFigure.usdz");
}

#[test]
fn lbs_matches_usd_core() {
    check("openusd/pxr/usd/usdSkel/testenv/testUsdSkelBakeSkinning/lbs.usda");
}

/// Blend shapes with inbetweens (at, between, below and above their weights, negative
/// inbetween weights included), at every time the oracle lists.
#[test]
fn blend_shapes_match_usd_core() {
    check("openusd/pxr/usd/usdSkel/testenv/testUsdSkelBakeSkinning/blendshapes.usda");
}

#[test]
fn arm_matches_usd_core() {
    check("openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLUsdSkel/arm.usda");
}

#[test]
fn maya_skel_cube_matches_usd_core() {
    check("Autodesk-maya-usd/test/lib/usd/translators/UsdImportSkeleton/skelCube.usda");
}

/// lux's own cases: a transformed skeleton under a transformed SkelRoot (the gprim's own
/// transform ignored), geomBindTransform, a sparse animation over restTransforms, non-uniform
/// joint scales (normals by the inverse transpose), `normals` / vertex and faceVarying
/// `primvars:normals`, unnormalised weights, `skel:joints`, rigid (`constant`) influences on a
/// mesh and on implicit surfaces, a binding inherited from an ancestor, dual-quaternion
/// skinning.
#[test]
fn lux_cases_match_usd_core() {
    check("lux/skel_cases.usda");
}

/// The stages posed, without a warning about skinning: the old "bind pose" warning is gone.
#[test]
fn posed_stages_do_not_warn_about_the_bind_pose() {
    let scene = load("usdwg/test_assets/USDZ/RiggedFigure/RiggedFigure.usdz", 0.0);
    assert_eq!(scene.drawn.posed_meshes, 1);
    assert!(
        scene
            .warnings
            .iter()
            .all(|w| !w.message.contains("bind pose") && !w.message.contains("UsdSkel")),
        "{:#?}",
        scene.warnings
    );
}

/// A skeleton and animation for the inline stages below: joint `A/B` turned 90° about z at
/// (1, 0, 0).
const RIG: &str = r#"
    def Skeleton "Skel" (
        prepend apiSchemas = ["SkelBindingAPI"]
    )
    {
        uniform token[] joints = ["A", "A/B"]
        uniform matrix4d[] bindTransforms = [((1,0,0,0),(0,1,0,0),(0,0,1,0),(0,0,0,1)), ((1,0,0,0),(0,1,0,0),(0,0,1,0),(1,0,0,1))]
        uniform matrix4d[] restTransforms = [((1,0,0,0),(0,1,0,0),(0,0,1,0),(0,0,0,1)), ((1,0,0,0),(0,1,0,0),(0,0,1,0),(1,0,0,1))]
        rel skel:animationSource = </R/Skel/Anim>
        def SkelAnimation "Anim"
        {
            uniform token[] joints = ["A", "A/B"]
            float3[] translations = [(0,0,0), (1,0,0)]
            quatf[] rotations = [(1,0,0,0), (0.70710678,0,0,0.70710678)]
            half3[] scales = [(1,1,1), (1,1,1)]
        }
    }
"#;

fn skinned_mesh(name: &str, extra: &str) -> String {
    format!(
        r#"
    def Mesh "{name}" (
        prepend apiSchemas = ["SkelBindingAPI"]
    )
    {{
        int[] faceVertexCounts = [3]
        int[] faceVertexIndices = [0, 1, 2]
        point3f[] points = [(2, 0, 0), (2, 1, 0), (3, 0, 0)]
{extra}
    }}
"#
    )
}

fn influences(indices: &str, weights: &str) -> String {
    format!(
        r#"        int[] primvars:skel:jointIndices = {indices} (
            elementSize = 1
            interpolation = "vertex"
        )
        float[] primvars:skel:jointWeights = {weights} (
            elementSize = 1
            interpolation = "vertex"
        )"#
    )
}

fn stage(body: &str) -> String {
    format!(
        r#"#usda 1.0
def SkelRoot "R" (
    prepend apiSchemas = ["SkelBindingAPI"]
)
{{
    rel skel:skeleton = </R/Skel>
{RIG}
{body}
}}
"#
    )
}

/// What cannot be posed as authored is a warning naming the prim, and the mesh is drawn as
/// authored; nothing panics.
#[test]
fn malformed_skinning_is_a_warning_naming_the_prim() {
    let body = [
        skinned_mesh("Posed", &influences("[1, 1, 1]", "[1, 1, 1]")),
        skinned_mesh("Mismatched", &influences("[1, 1, 1]", "[1, 1]")),
        skinned_mesh(
            "NoSkeleton",
            &format!(
                "{}\n        rel skel:skeleton = </R/Nope>",
                influences("[1, 1, 1]", "[1, 1, 1]")
            ),
        ),
        skinned_mesh("NanWeights", &influences("[1, 1, 1]", "[nan, 1, 1]")),
        skinned_mesh("OutOfRange", &influences("[1, 5, 1]", "[1, 1, 1]")),
        skinned_mesh("TooFew", &influences("[1, 1]", "[1, 1]")),
    ]
    .concat();
    let scene = lux_usd::load_usda_str(&stage(&body), 1.0, &LoadOptions::default()).unwrap();
    let mesh = |name: &str| {
        scene
            .meshes
            .iter()
            .find(|m| m.path == format!("/R/{name}"))
            .unwrap()
    };
    let warned = |name: &str, what: &str| {
        scene
            .warnings
            .iter()
            .any(|w| w.prim == format!("/R/{name}") && w.message.contains(what))
    };
    let authored = [
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(2.0, 1.0, 0.0),
        DVec3::new(3.0, 0.0, 0.0),
    ];
    // Joint B turns 90° about z at (1, 0, 0): (2, 0, 0) → (1, 1, 0).
    let posed = [
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(1.0, 2.0, 0.0),
    ];
    let near = |a: &[DVec3], b: &[DVec3]| a.iter().zip(b).all(|(a, b)| (*a - *b).length() < 1e-6);
    assert!(near(&mesh("Posed").positions, &posed));
    for (name, what) in [
        ("Mismatched", "3 jointIndices and 2 jointWeights"),
        ("NoSkeleton", "is not a Skeleton"),
        ("OutOfRange", "joint index 5 is out of range"),
        ("TooFew", "2 joint influences for 3 points"),
    ] {
        assert!(warned(name, what), "{name}: {:#?}", scene.warnings);
        assert!(
            near(&mesh(name).positions, &authored),
            "{name} is drawn as authored"
        );
    }
    // A NaN weight counts as 0 (usd-core would put that point at NaN): the point collapses to
    // the skeleton's origin, as a zero weight does in UsdSkel; the others are posed.
    assert!(warned("NanWeights", "non-finite weights read as 0"));
    let nan = &mesh("NanWeights").positions;
    assert!(nan.iter().all(|p| p.is_finite()));
    assert!(
        near(&nan[1..], &posed[1..]) && nan[0] == DVec3::ZERO,
        "{nan:?}"
    );
    assert_eq!(scene.drawn.posed_meshes, 2);
}

/// A skinned mesh inside an instancing prototype, with its skeleton: posed once in the
/// prototype's space, placed by each instance, where the same mesh outside instancing is.
#[test]
fn a_skinned_prototype_is_posed_once_for_every_instance() {
    let rig = stage(&skinned_mesh("M", &influences("[1, 1, 1]", "[1, 1, 1]")))
        .replace("#usda 1.0\n", "")
        .replace("</R/", "</Src/R/");
    let text = format!(
        r#"#usda 1.0
class Xform "Src"
{{
{rig}
}}

def Xform "Plain" (
    references = </Src>
)
{{
    double3 xformOp:translate = (0, 0, 10)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}}

def Xform "I1" (
    instanceable = true
    references = </Src>
)
{{
    double3 xformOp:translate = (0, 0, 10)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}}

def Xform "I2" (
    instanceable = true
    references = </Src>
)
{{
    double3 xformOp:translate = (5, 0, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}}
"#
    );
    let scene = lux_usd::load_usda_str(&text, 1.0, &LoadOptions::default()).unwrap();
    let plain = scene
        .meshes
        .iter()
        .find(|m| m.path == "/Plain/R/M")
        .unwrap();
    // Joint B turns (2, 0, 0) to (1, 1, 0); the references are 10 along z.
    assert!((plain.positions[0] - DVec3::new(1.0, 1.0, 10.0)).length() < 1e-6);
    assert_eq!(scene.instances.len(), 2, "{:#?}", scene.warnings);
    let proto_mesh = scene
        .meshes
        .iter()
        .position(|m| m.prototype.is_some())
        .unwrap();
    for inst in &scene.instances {
        let placed = scene.meshes[proto_mesh].transformed(&inst.to_world);
        let offset = inst.to_world.transform_point3(DVec3::ZERO) - DVec3::new(0.0, 0.0, 10.0);
        for (a, b) in placed.positions.iter().zip(&plain.positions) {
            assert!(
                (*a - (*b + offset)).length() < 1e-6,
                "{}: {a} vs {b}",
                inst.path
            );
        }
    }
    // The plain mesh and the prototype's, each counted once.
    assert_eq!(scene.drawn.posed_meshes, 2);
}
