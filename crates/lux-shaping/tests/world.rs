//! `Shaping::factor_world`: the ShapingAPI factor of a world direction under the light's
//! light-to-world transform, `factor(normalize(L⁻¹ w))`, checked under non-uniform scale and
//! shear against the receiver's own light-space position and against closed-form cone edges.

use glam::{DMat4, DVec3};
use lux_math::LightTransform;
use lux_shaping::{Shaping, ShapingOptions, ShapingParams};

fn spot(cone_deg: f64) -> Shaping {
    let p = ShapingParams {
        cone_angle_deg: cone_deg,
        focus: 3.0,
        focus_tint: DVec3::new(0.1, 0.2, 0.3),
        ..ShapingParams::default()
    };
    Shaping::new(&p, None, ShapingOptions::default()).unwrap()
}

/// A 30° cone under `scale(3, 1, 1)`: in world space it reaches atan(3·tan 30°) = 60° off the
/// axis in the XZ plane and stays 30° in the YZ plane (the affine image of the local cone).
#[test]
fn cone_edges_under_a_non_uniform_scale() {
    let s = Shaping::new(
        &ShapingParams {
            cone_angle_deg: 30.0,
            ..ShapingParams::default()
        },
        None,
        ShapingOptions::default(),
    )
    .unwrap();
    let xf = LightTransform::new(DMat4::from_scale(DVec3::new(3.0, 1.0, 1.0))).unwrap();
    let edge_xz = (3.0 * 30f64.to_radians().tan()).atan();
    assert!((edge_xz.to_degrees() - 60.0).abs() < 1e-12);
    let at = |deg: f64, x: bool| {
        let (sn, c) = deg.to_radians().sin_cos();
        let w = if x {
            DVec3::new(sn, 0.0, -c)
        } else {
            DVec3::new(0.0, sn, -c)
        };
        s.factor_world(&xf, w)
    };
    assert_eq!(at(59.9, true), DVec3::ONE);
    assert_eq!(at(60.1, true), DVec3::ZERO);
    assert_eq!(at(29.9, false), DVec3::ONE);
    assert_eq!(at(30.1, false), DVec3::ZERO);
    // Mapping with the normal matrix Lᵀ would put the XZ edge at atan(tan 30° / 3) = 10.9°:
    // a direction at 40° in XZ is lit by factor_world and would be dark that way.
    let (sn, c) = 40f64.to_radians().sin_cos();
    let w = DVec3::new(sn, 0.0, -c);
    assert_eq!(s.factor_world(&xf, w), DVec3::ONE);
    assert_eq!(s.factor(xf.inv_normal(w)), DVec3::ZERO);
}

/// Under a shear with non-uniform scale and a translation, a receiver at the world image of a
/// light-space point gets the factor that point gets from the untransformed light, whatever
/// point of the light the direction starts from.
#[test]
fn a_receiver_is_lit_as_its_light_space_image() {
    let m = DMat4::from_cols_array(&[
        2.0, 0.3, 0.0, 0.0, //
        0.5, 0.7, 0.0, 0.0, //
        0.1, -0.4, 1.5, 0.0, //
        1.0, 2.0, 3.0, 1.0,
    ]);
    let xf = LightTransform::new(m).unwrap();
    assert!(!xf.is_similarity());
    let s = spot(50.0);
    let mut worst = 0.0f64;
    for i in 0..20 {
        for j in 0..20 {
            // a light-space receiver below the light and a point on a unit rect light
            let r_local = DVec3::new(
                -2.0 + 0.2 * i as f64,
                -2.0 + 0.2 * j as f64,
                -1.0 - 0.05 * (i + j) as f64,
            );
            let q_local = DVec3::new(0.5 - 0.05 * j as f64, -0.5 + 0.05 * i as f64, 0.0);
            let want = s.factor(r_local - q_local);
            let got = s.factor_world(&xf, xf.point(r_local) - xf.point(q_local));
            worst = worst.max((got - want).abs().max_element());
        }
    }
    assert!(worst < 1e-12, "{worst}");
}

/// Similarities change no angle: the factor of a rotated, uniformly scaled light towards the
/// rotated direction is the light-space factor; degenerate directions give zero.
#[test]
fn similarities_and_degenerate_directions() {
    let q = glam::DQuat::from_rotation_arc(DVec3::NEG_Z, DVec3::new(0.6, 0.0, -0.8));
    let xf = LightTransform::new(DMat4::from_scale_rotation_translation(
        DVec3::splat(2.5),
        q,
        DVec3::new(4.0, 5.0, 6.0),
    ))
    .unwrap();
    let s = spot(40.0);
    for deg in [0.0, 10.0, 25.0, 39.0, 41.0, 90.0] {
        let (sn, c) = f64::to_radians(deg).sin_cos();
        let local = DVec3::new(sn, 0.0, -c);
        let got = s.factor_world(&xf, q * local);
        assert!((got - s.factor(local)).abs().max_element() < 1e-14, "{deg}");
    }
    assert_eq!(s.factor_world(&xf, DVec3::ZERO), DVec3::ZERO);
    assert_eq!(s.factor_world(&xf, DVec3::splat(f64::NAN)), DVec3::ZERO);
}
