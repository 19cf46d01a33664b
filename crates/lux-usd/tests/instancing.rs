//! Instancing against usd-core: `tests/data/scenes/instancing/instancing.usda` (written for lux)
//! has a PointInstancer with positions, `quath` orientations, scales, a prototype whose root has
//! its own transform, a prototype holding two native instances (mirrored by its root's
//! scale), `inactiveIds` and time-sampled `invisibleIds`, and a native instance bound to a
//! material on the instance's side. The world points of every drawn instance are compared with
//! usd-core's (`ComputeInstanceTransformsAtTime` with the prototype transform included, masks
//! from `ComputeMaskAtTime`, instance proxies for the native instances), computed when the test
//! was written: count, sum and sum of squares of the points, and their bounds.

use glam::DVec3;
use lux_usd::{Input, LoadOptions, Scene, load_stage_with};
use std::path::PathBuf;

fn stage() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes/instancing/instancing.usda")
}

/// Every world point of every drawn mesh: world meshes as they are, prototype meshes through
/// each instance of their prototype.
fn world_points(s: &Scene) -> Vec<DVec3> {
    let mut out = Vec::new();
    for m in s.meshes.iter().filter(|m| m.prototype.is_none()) {
        out.extend(&m.positions);
    }
    for i in &s.instances {
        for &mi in &s.prototypes[i.prototype].meshes {
            out.extend(
                s.meshes[mi]
                    .positions
                    .iter()
                    .map(|p| i.to_world.transform_point3(*p)),
            );
        }
    }
    out
}

#[test]
fn instance_points_match_usd_core() {
    // (time, drawn PointInstancer instances, points, sum, sum of squares), from usd-core 26.11
    let want = [
        (
            1.0,
            4,
            23,
            DVec3::new(2022.6982886531755, 248.7320508075689, -25.50213623046875),
            207635.39723591207,
        ),
        (
            2.0,
            3,
            19,
            DVec3::new(1617.6982886531755, 207.0, -23.50213623046875),
            166190.7562197607,
        ),
    ];
    for (t, drawn, n, sum, sq) in want {
        let s = load_stage_with(stage(), t, &LoadOptions::default()).unwrap();
        assert!(s.warnings.is_empty(), "{:#?}", s.warnings);
        assert_eq!(s.gprims.point_instances, 5);
        assert_eq!(s.gprims.native_instances, 3);
        assert_eq!(s.gprims.meshes, 4);
        // geometry stored once: the quad and the triangle
        assert_eq!(s.meshes.len(), 2);
        // drawn entries: the quads are instances of their own; each Pair places two native
        // instances of the triangle (`/World/Scatter[i]/A`, `…/B`); plus /World/Row/C
        let quads = s.instances.iter().filter(|i| i.path.ends_with(']')).count();
        let pair_tris = s
            .instances
            .iter()
            .filter(|i| i.path.starts_with("/World/Scatter[") && !i.path.ends_with(']'))
            .count();
        assert_eq!(quads + pair_tris / 2, drawn, "{:#?}", s.instances);
        assert_eq!(s.instances.len(), quads + pair_tris + 1);
        let p = world_points(&s);
        assert_eq!(p.len(), n, "points at {t}");
        let got: DVec3 = p.iter().sum();
        let got_sq: f64 = p.iter().map(|q| q.length_squared()).sum();
        // quath orientations: both sides normalise the same half-precision values; the
        // tolerance covers f32 points and the order of the f64 sums.
        assert!(
            (got - sum).length() <= 1e-9 * sum.length(),
            "sum at {t}: {got} vs {sum}"
        );
        assert!(
            (got_sq - sq).abs() <= 1e-9 * sq,
            "squares at {t}: {got_sq} vs {sq}"
        );
        let lo = p.iter().fold(DVec3::INFINITY, |a, q| a.min(*q));
        let hi = p.iter().fold(DVec3::NEG_INFINITY, |a, q| a.max(*q));
        assert!((lo - DVec3::new(0.5, 5.0, -7.0)).length() < 1e-9, "{lo}");
        assert!(
            (hi - DVec3::new(107.59807621135332, 20.0, 5.75)).length() < 1e-9,
            "{hi}"
        );
    }
}

#[test]
fn instance_side_binding_and_mirroring() {
    let s = load_stage_with(stage(), 1.0, &LoadOptions::default()).unwrap();
    let c = s
        .instances
        .iter()
        .find(|i| i.path == "/World/Row/C")
        .expect("the native instance outside the instancer");
    let m = &s.materials[c.material.expect("the instance-side binding")];
    assert_eq!(m.path, "/World/Looks/Red");
    assert!(matches!(m.diffuse, Input::Value(c) if (c.x - 0.8).abs() < 1e-6));
    // the triangle itself has no binding: it takes the instance's
    let tri = &s.meshes[s.prototypes[c.prototype].meshes[0]];
    assert_eq!(tri.material, None);
    // the Pair's root scale (1, 1, −1) mirrors its instances of the triangle
    let mirrored = s
        .instances
        .iter()
        .filter(|i| i.path.contains("/A") || i.path.contains("/B"))
        .filter(|i| glam::DMat3::from_mat4(i.to_world).determinant() < 0.0)
        .count();
    assert_eq!(mirrored, 4, "{:#?}", s.instances);
}
