//! `xformOpOrder` evaluation against hand-computed matrices, in USD's row-vector convention
//! (`p' = p · M`, translation in the last row; spec README §2). Expected matrices are built
//! here independently of the loader: row-form rotation matrices multiplied in the order USD
//! documents (`xformOpOrder = [A, B, C]` → `M = C · B · A`, the last op applies first).

use glam::{DMat4, DVec3};
use lux_usd::{Scene, load_stage};
use std::path::PathBuf;

type Rows = [[f64; 4]; 4];

fn file() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes/xforms.usda")
}

const I: Rows = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

fn mul(a: &Rows, b: &Rows) -> Rows {
    let mut m = [[0.0; 4]; 4];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = (0..4).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    m
}

fn translate(x: f64, y: f64, z: f64) -> Rows {
    let mut m = I;
    m[3] = [x, y, z, 1.0];
    m
}

fn scale(x: f64, y: f64, z: f64) -> Rows {
    let mut m = I;
    m[0][0] = x;
    m[1][1] = y;
    m[2][2] = z;
    m
}

/// Row-form rotation about one axis (GfMatrix4d::SetRotate): counter-clockwise looking down
/// the axis, e.g. `(1, 0, 0) · rz(90) = (0, 1, 0)`.
fn rot(axis: char, deg: f64) -> Rows {
    let (s, c) = deg.to_radians().sin_cos();
    match axis {
        'X' => [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, c, s, 0.0],
            [0.0, -s, c, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ],
        'Y' => [
            [c, 0.0, -s, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [s, 0.0, c, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ],
        _ => [
            [c, s, 0.0, 0.0],
            [-s, c, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ],
    }
}

fn world(scene: &Scene, path: &str) -> DMat4 {
    scene
        .cameras
        .iter()
        .find(|c| c.path == path)
        .unwrap_or_else(|| panic!("camera {path}"))
        .camera_to_world
}

#[track_caller]
fn assert_rows(scene: &Scene, path: &str, want: Rows, tol: f64) {
    let got = world(scene, path);
    let want_m = lux_math::usd_matrix(want);
    let err = (got - want_m)
        .to_cols_array()
        .iter()
        .fold(0.0f64, |a, d| a.max(d.abs()));
    assert!(
        err <= tol,
        "{path}: max error {err}\n got  {got:?}\n want {want_m:?}"
    );
}

#[test]
fn single_ops() {
    let s = load_stage(file(), 1.0).unwrap();
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    assert_rows(&s, "/translate", translate(1.0, 2.0, 3.0), 0.0);
    assert_rows(&s, "/scale", scale(2.0, 3.0, 4.0), 0.0);
    // 90° about each axis, written out as literal signed permutations.
    assert_rows(
        &s,
        "/rotX",
        [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ],
        1e-15,
    );
    assert_rows(
        &s,
        "/rotY",
        [
            [0.0, 0.0, -1.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ],
        1e-15,
    );
    assert_rows(
        &s,
        "/rotZ",
        [
            [0.0, 1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ],
        1e-15,
    );
    // orient (0.7071, 0.7071, 0, 0) = 90° about X (float quaternion: float precision).
    assert_rows(&s, "/orient", rot('X', 90.0), 1e-6);
    assert_rows(
        &s,
        "/transform",
        [
            [0.0, 1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 2.0, 0.0],
            [5.0, 6.0, 7.0, 1.0],
        ],
        0.0,
    );
    // Point check of rotZ: +X goes to +Y.
    let p = world(&s, "/rotZ").transform_point3(DVec3::X);
    assert!((p - DVec3::Y).length() < 1e-15, "{p}");
}

#[test]
fn all_six_rotate_orders() {
    let s = load_stage(file(), 1.0).unwrap();
    let (x, y, z) = (30.0, 45.0, 60.0);
    let angle = |c: char| match c {
        'X' => x,
        'Y' => y,
        _ => z,
    };
    let mut seen: Vec<DMat4> = Vec::new();
    for order in ["XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"] {
        // rotateABC rotates about A first: p · R_A · R_B · R_C.
        let c: Vec<char> = order.chars().collect();
        let want = mul(
            &mul(&rot(c[0], angle(c[0])), &rot(c[1], angle(c[1]))),
            &rot(c[2], angle(c[2])),
        );
        // float3 angles: float-rounded degrees are exact here (30, 45, 60).
        assert_rows(&s, &format!("/rot{order}"), want, 1e-12);
        let m = world(&s, &format!("/rot{order}"));
        assert!(
            seen.iter().all(|o| !o.abs_diff_eq(m, 1e-3)),
            "rotate{order} equals another order"
        );
        seen.push(m);
    }
    // Spot check independent of the helper: under rotateXYZ (30, 45, 60) +X is untouched by
    // the X rotation, goes to (cos45, 0, −sin45) about Y, then about Z to
    // (cos45·cos60, cos45·sin60, −sin45).
    let v = world(&s, "/rotXYZ").transform_vector3(DVec3::X);
    let h = 0.5f64.sqrt();
    let want = DVec3::new(h * 0.5, h * 3f64.sqrt() / 2.0, -h);
    assert!((v - want).length() < 1e-12, "{v} vs {want}");
}

#[test]
fn op_order_invert_and_pivot() {
    let s = load_stage(file(), 1.0).unwrap();
    // [translate, rotateZ, scale] → M = S · Rz · T: (1,0,0) → (2,0,0) → (0,2,0) → (10,2,0).
    assert_rows(
        &s,
        "/trs",
        mul(
            &mul(&scale(2.0, 1.0, 1.0), &rot('Z', 90.0)),
            &translate(10.0, 0.0, 0.0),
        ),
        1e-15,
    );
    let p = world(&s, "/trs").transform_point3(DVec3::X);
    assert!((p - DVec3::new(10.0, 2.0, 0.0)).length() < 1e-12, "{p}");
    // Pivot: T(-p) · Rz · T(p), p = (1,0,0): the origin rotates about (1,0,0) to (1,-1,0).
    assert_rows(
        &s,
        "/pivot",
        mul(
            &mul(&translate(-1.0, 0.0, 0.0), &rot('Z', 90.0)),
            &translate(1.0, 0.0, 0.0),
        ),
        1e-15,
    );
    let o = world(&s, "/pivot").transform_point3(DVec3::ZERO);
    assert!((o - DVec3::new(1.0, -1.0, 0.0)).length() < 1e-12, "{o}");
    assert_rows(&s, "/invertScale", scale(0.5, 0.25, 0.125), 1e-15);
    assert_rows(&s, "/unlisted", translate(1.0, 1.0, 1.0), 0.0);
}

#[test]
fn ancestors_and_reset_xform_stack() {
    let s = load_stage(file(), 1.0).unwrap();
    // parent = Rz(90) · T(0,0,10) (row form); child = T(1,0,0) · parent.
    let parent = mul(&rot('Z', 90.0), &translate(0.0, 0.0, 10.0));
    assert_rows(
        &s,
        "/parent/child",
        mul(&translate(1.0, 0.0, 0.0), &parent),
        1e-15,
    );
    // Child origin: (1,0,0) rotated to (0,1,0), lifted to z = 10.
    let o = world(&s, "/parent/child").transform_point3(DVec3::ZERO);
    assert!((o - DVec3::new(0.0, 1.0, 10.0)).length() < 1e-12, "{o}");
    assert_rows(&s, "/parent/reset", translate(1.0, 0.0, 0.0), 0.0);
    let middle = mul(&scale(2.0, 2.0, 2.0), &parent);
    assert_rows(
        &s,
        "/parent/middle/grandchild",
        mul(&translate(1.0, 0.0, 0.0), &middle),
        1e-15,
    );
    let o = world(&s, "/parent/middle/grandchild").transform_point3(DVec3::ZERO);
    assert!((o - DVec3::new(0.0, 2.0, 10.0)).length() < 1e-12, "{o}");
    assert_rows(
        &s,
        "/parent/middle/deepReset",
        translate(0.0, 1.0, 0.0),
        0.0,
    );
}

#[test]
fn animated_parent_transform() {
    for (frame, t, deg) in [
        (0.0, 0.0, 0.0), // clamped to the first sample
        (1.0, 0.0, 0.0),
        (1.5, 1.0, 22.5),
        (2.0, 2.0, 45.0),
        (3.0, 4.0, 90.0),
        (7.0, 4.0, 90.0), // clamped to the last sample
    ] {
        let s = load_stage(file(), frame).unwrap();
        let parent = mul(&rot('Z', deg), &translate(t, 0.0, 0.0));
        // rotateZ is a float attribute: its interpolated angle is float-rounded.
        assert_rows(
            &s,
            "/animParent/child",
            mul(&translate(1.0, 0.0, 0.0), &parent),
            1e-7,
        );
        let (sn, cs) = deg.to_radians().sin_cos();
        let o = world(&s, "/animParent/child").transform_point3(DVec3::ZERO);
        assert!(
            (o - DVec3::new(t + cs, sn, 0.0)).length() < 1e-7,
            "frame {frame}: {o}"
        );
    }
}

#[test]
fn composition_is_double_precision() {
    let s = load_stage(file(), 1.0).unwrap();
    let o = world(&s, "/far/near").transform_point3(DVec3::ZERO);
    // 100000000.001 is not representable in f32 (spacing 8 there).
    assert!((o.x - 100_000_000.001).abs() < 1e-6, "{}", o.x);
}
