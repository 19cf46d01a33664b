//! Bad input never panics: constructors reject non-finite or non-positive parameters with typed
//! errors, and sampling from non-finite or degenerate reference points gives `None`/0.

use glam::{DMat4, DVec3};
use lux_sample::*;
use proptest::prelude::*;

fn lights() -> Vec<Light> {
    let xf = LightTransform::new(DMat4::from_translation(DVec3::new(0.0, 0.0, 1.0))).unwrap();
    vec![
        Light::Rect(RectLight::new(1.0, 2.0, xf, RectTechnique::SphericalRectangleCosine).unwrap()),
        Light::Disk(DiskLight::new(0.5, xf, DiskTechnique::PolarChord).unwrap()),
        Light::Disk(DiskLight::new(0.5, xf, DiskTechnique::EllipticCone).unwrap()),
        Light::Sphere(SphereLight::new(0.5, xf, SphereTechnique::Cone).unwrap()),
        Light::Cylinder(CylinderLight::new(0.5, 1.0, xf, CylinderTechnique::SolidAngle).unwrap()),
        Light::Distant(DistantLight::new(5.0, &xf).unwrap()),
        Light::Dome(DomeLight::uniform(xf)),
        Light::Mesh(
            MeshLight::new(
                &[DVec3::ZERO, DVec3::X, DVec3::Y],
                &[[0, 1, 2]],
                None,
                true,
                MeshTechnique::SphericalTriangle,
            )
            .unwrap(),
        ),
    ]
}

#[test]
fn constructors_reject_bad_parameters() {
    let id = LightTransform::IDENTITY;
    assert!(matches!(
        RectLight::new(f64::NAN, 1.0, id, RectTechnique::Area),
        Err(SampleError::NonFinite { field: "width", .. })
    ));
    assert!(matches!(
        RectLight::new(1.0, -1.0, id, RectTechnique::Area),
        Err(SampleError::NonPositive {
            field: "height",
            ..
        })
    ));
    assert!(DiskLight::new(0.0, id, DiskTechnique::Area).is_err());
    assert!(SphereLight::new(f64::INFINITY, id, SphereTechnique::Cone).is_err());
    assert!(CylinderLight::new(0.5, -2.0, id, CylinderTechnique::Area).is_err());
    assert!(DistantLight::new(f64::NAN, &id).is_err());
    assert!(matches!(
        MeshLight::new(
            &[DVec3::ZERO],
            &[[0, 1, 2]],
            None,
            false,
            MeshTechnique::Area
        ),
        Err(SampleError::BadIndex {
            triangle: 0,
            index: 1,
            ..
        })
    ));
    // Degenerate triangles only: nothing to sample.
    assert!(
        MeshLight::new(
            &[DVec3::ZERO, DVec3::X, DVec3::X * 2.0],
            &[[0, 1, 2]],
            None,
            false,
            MeshTechnique::Area
        )
        .is_err()
    );
    assert!(
        MeshLight::new(
            &[DVec3::ZERO, DVec3::X, DVec3::Y],
            &[[0, 1, 2]],
            Some(&[1.0, 2.0]),
            false,
            MeshTechnique::Area
        )
        .is_err()
    );
    assert!(LightTransform::new(DMat4::ZERO).is_err());
    assert!(LatLongMap::new(1 << 20, 1 << 20, vec![]).is_err());
    // A distant light with angle > 360 covers the sphere; a negative angle is a delta light.
    let all = DistantLight::new(1000.0, &id).unwrap();
    assert!((all.solid_angle() - 4.0 * std::f64::consts::PI).abs() < 1e-12);
    assert!(DistantLight::new(-3.0, &id).unwrap().is_delta());
}

#[test]
fn non_finite_references_do_not_panic() {
    for light in lights() {
        for p in [
            DVec3::NAN,
            DVec3::INFINITY,
            DVec3::new(0.0, f64::NEG_INFINITY, 0.0),
        ] {
            let r = Reference::surface(p, DVec3::Z);
            if let Some(s) = light.sample(&r, [0.5, 0.5]) {
                // Only lights at infinity ignore the position.
                assert!(s.distance.is_infinite(), "{light:?}");
            }
            let v = light.pdf(&r, DVec3::Z);
            match light {
                Light::Distant(_) | Light::Dome(_) => assert!(v.is_finite()),
                _ => assert_eq!(v, 0.0, "{light:?}"),
            }
        }
        assert_eq!(light.pdf(&Reference::point(DVec3::ZERO), DVec3::ZERO), 0.0);
    }
}

proptest! {
    /// Any finite reference and any u: samples are finite, unit, with positive finite pdf.
    #[test]
    fn samples_are_finite(x in -5.0..5.0f64, y in -5.0..5.0f64, z in -5.0..5.0f64,
                          u0 in 0.0..1.0f64, u1 in 0.0..1.0f64) {
        for light in lights() {
            if let Some(s) = light.sample(&Reference::surface(DVec3::new(x, y, z), DVec3::Z), [u0, u1]) {
                prop_assert!(s.pdf > 0.0 && s.pdf.is_finite(), "{:?} {:?}", light, s);
                prop_assert!((s.wi.length() - 1.0).abs() < 1e-9);
                prop_assert!(s.point.is_finite() && s.normal.is_finite());
            }
        }
    }
}
