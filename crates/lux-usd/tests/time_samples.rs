//! timeSamples evaluated at a frame: linear interpolation for numbers (half, float, double),
//! vectors, matrices and arrays of equal length, slerp for quaternions, held values for
//! everything else (bool, token, int vectors, asset paths), clamped before the first and after
//! the last sample. Samples are authored at frames 1 and 3 in `time_samples.usda`.

use glam::{DVec2, DVec3};
use lux_usd::{Projection, Scene, load_stage};
use std::path::PathBuf;

fn file() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes/time_samples.usda")
}

fn at(frame: f64) -> Scene {
    load_stage(file(), frame).unwrap_or_else(|e| panic!("frame {frame}: {e}"))
}

#[test]
fn scalars_interpolate_in_their_declared_precision() {
    for (frame, intensity, exposure) in [
        (-5.0, 10.0, 0.5),
        (1.0, 10.0, 0.5),
        (1.5, 12.5, 0.625),
        (2.0, 15.0, 0.75),
        (2.5, 17.5, 0.875),
        (3.0, 20.0, 1.0),
        (100.0, 20.0, 1.0),
    ] {
        let s = at(frame);
        let l = s.light("/Lamp").unwrap();
        assert_eq!(l.params.intensity, intensity, "intensity at {frame}");
        assert_eq!(l.params.exposure, exposure, "exposure at {frame}");
    }
    // A non-dyadic fraction: float arithmetic, float result (as a .usdc float sample gives).
    let s = at(1.0 + 2.0 / 3.0);
    let want = f64::from(10.0f32 + (20.0f32 - 10.0) * (1.0f32 / 3.0));
    assert_eq!(s.light("/Lamp").unwrap().params.intensity, want);
    // double rotateX 0 → 90: 30° at 5/3, exactly in double.
    let cam = s.cameras.iter().find(|c| c.path == "/Cam").unwrap();
    let y = cam.camera_to_world.transform_vector3(DVec3::Y);
    let a = 30f64.to_radians();
    assert!(
        (y - DVec3::new(0.0, a.cos(), a.sin())).length() < 1e-12,
        "{y}"
    );
    // half rotateY 0 → 90 at frame 2: 45°.
    let s = at(2.0);
    let cam = s.cameras.iter().find(|c| c.path == "/HalfCam").unwrap();
    let z = cam.camera_to_world.transform_vector3(DVec3::Z);
    let h = 0.5f64.sqrt();
    assert!((z - DVec3::new(h, 0.0, h)).length() < 1e-12, "{z}");
}

#[test]
fn vectors_matrices_quaternions_and_arrays_interpolate() {
    let s = at(2.0);
    let l = s.light("/Lamp").unwrap();
    assert_eq!(l.params.color, DVec3::new(0.5, 0.0, 0.5));
    let cam = s.cameras.iter().find(|c| c.path == "/Cam").unwrap();
    assert_eq!(cam.clipping_range, DVec2::new(2.0, 200.0));
    // matrix: identity → (diag(3,1,1), translation (2,4,6)) at 2: diag(2,1,1), (1,2,3).
    let m = s
        .cameras
        .iter()
        .find(|c| c.path == "/MatrixCam")
        .unwrap()
        .camera_to_world;
    let want = lux_math::usd_matrix([
        [2.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [1.0, 2.0, 3.0, 1.0],
    ]);
    assert_eq!(m, want);
    // quaternion slerp: identity → 90° about Z gives 45° (a lerp of the matrices would not be
    // a rotation: its image of +X would have length 1/√2·… ≠ 1).
    let q = s
        .cameras
        .iter()
        .find(|c| c.path == "/QuatCam")
        .unwrap()
        .camera_to_world;
    let x = q.transform_vector3(DVec3::X);
    let h = 0.5f64.sqrt();
    assert!((x - DVec3::new(h, h, 0.0)).length() < 1e-12, "{x}");
    // points (float3[]): the first triangle's corners move from z = 0 to z = 2.
    let tri = s.meshes.iter().find(|m| m.path == "/Tri").unwrap();
    assert_eq!(
        tri.positions,
        vec![
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(2.0, 0.0, 1.0),
            DVec3::new(0.0, 2.0, 1.0)
        ]
    );
    // float pixelAspectRatio 1 → 2
    assert_eq!(s.render_settings[0].pixel_aspect_ratio(), 1.5);
}

#[test]
fn non_interpolable_values_are_held() {
    for (frame, later) in [
        (0.0, false),
        (1.0, false),
        (2.9, false),
        (3.0, true),
        (9.0, true),
    ] {
        let s = at(frame);
        let l = s.light("/Lamp").unwrap();
        assert_eq!(l.treat_as_point, later, "bool at {frame}");
        let dome = s.light("/Dome").unwrap();
        let tex = dome.texture.as_ref().unwrap();
        let want_tex = if later {
            "../luxtest/04f377f94ce81cd7b5101fffdf571454.jpg"
        } else {
            "textures/latlong_4x2.png"
        };
        assert_eq!(tex.authored, want_tex, "asset at {frame}");
        assert!(tex.resolved.as_ref().unwrap().is_file());
        assert_eq!(
            dome.texture_format.token(),
            if later { "mirroredBall" } else { "latlong" },
            "token at {frame}"
        );
        let cam = s.cameras.iter().find(|c| c.path == "/Cam").unwrap();
        let proj = if later {
            Projection::Orthographic
        } else {
            Projection::Perspective
        };
        assert_eq!(cam.projection, proj, "projection at {frame}");
        // int2: held
        let res = s.render_settings[0].resolution();
        assert_eq!(
            res,
            if later { [300, 150] } else { [100, 50] },
            "int2 at {frame}"
        );
        // visibility token: the mesh under /Vis disappears from frame 3 on
        assert_eq!(
            s.meshes.iter().any(|m| m.path == "/Vis/Tri"),
            !later,
            "visibility at {frame}"
        );
    }
}

#[test]
fn blocked_samples_fall_back_to_the_schema_default() {
    let radius = |frame: f64| match at(frame).light("/Lamp").unwrap().shape {
        lux_math::LightShape::Sphere { radius } => radius,
        ref other => panic!("{other:?}"),
    };
    assert_eq!(radius(1.0), 0.25);
    assert_eq!(radius(2.0), 0.5); // the `None` sample: SphereLight default radius
    assert_eq!(radius(2.5), 0.5); // lower sample blocked
    assert_eq!(radius(3.0), 0.75);
}
