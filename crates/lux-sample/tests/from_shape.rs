//! `Light::from_shape` (one UsdLux description, lux-math's `LightShape` and the light-to-world
//! transform, gives the sampler) and the one-sided `projected_solid_angle` of the area lights,
//! checked against closed forms and against the samplers' own irradiance estimates.

use glam::{DMat4, DQuat, DVec3};
use lux_math::{LightShape, LightTransform};
use lux_sample::*;
use std::f64::consts::PI;

fn xf(m: DMat4) -> LightTransform {
    LightTransform::new(m).unwrap()
}

/// A sheared, non-uniformly scaled, rotated and translated transform.
fn sheared() -> LightTransform {
    let shear = DMat4::from_cols_array(&[
        1.0, 0.0, 0.0, 0.0, //
        0.35, 1.0, 0.0, 0.0, //
        0.0, 0.2, 1.0, 0.0, //
        0.0, 0.0, 0.0, 1.0,
    ]);
    xf(DMat4::from_translation(DVec3::new(0.2, -0.1, 1.5))
        * DMat4::from_rotation_x(0.25)
        * shear
        * DMat4::from_scale(DVec3::new(1.6, 0.7, 1.0)))
}

#[test]
fn from_shape_is_the_default_technique_of_each_kind() {
    let t = sheared();
    let r = Reference::surface(DVec3::new(0.1, 0.2, 0.0), DVec3::Z);
    let pairs = [
        (
            LightShape::Rect {
                width: 1.0,
                height: 0.5,
            },
            Light::Rect(RectLight::new(1.0, 0.5, t, RectTechnique::SphericalRectangle).unwrap()),
        ),
        (
            LightShape::Disk { radius: 0.4 },
            Light::Disk(DiskLight::new(0.4, t, DiskTechnique::EllipticCone).unwrap()),
        ),
        (
            LightShape::Sphere { radius: 0.3 },
            Light::Sphere(SphereLight::new(0.3, t, SphereTechnique::Cone).unwrap()),
        ),
        (
            LightShape::Cylinder {
                radius: 0.2,
                length: 1.2,
            },
            Light::Cylinder(
                CylinderLight::new(0.2, 1.2, t, CylinderTechnique::SolidAngle).unwrap(),
            ),
        ),
        (
            LightShape::Distant { angle_deg: 5.0 },
            Light::Distant(DistantLight::new(5.0, &t).unwrap()),
        ),
        (LightShape::Dome, Light::Dome(DomeLight::uniform(t))),
    ];
    let mut rng = SplitMix64::new(5);
    for (shape, built) in pairs {
        let from = Light::from_shape(&shape, &t).unwrap();
        let mut hits = 0;
        for _ in 0..256 {
            let u = rng.next_2d();
            let (a, b) = (from.sample(&r, u), built.sample(&r, u));
            assert_eq!(a, b, "{shape:?}");
            hits += usize::from(a.is_some());
        }
        assert!(hits > 100, "{shape:?}: {hits}");
    }
    // a mesh's local triangles are placed by the transform, one-sided
    let tri = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
    ];
    let mesh = Light::from_shape(
        &LightShape::Mesh {
            triangles: vec![tri],
        },
        &t,
    )
    .unwrap();
    let Light::Mesh(m) = &mesh else {
        panic!("{mesh:?}")
    };
    let world: Vec<DVec3> = tri.iter().map(|&p| t.point(p)).collect();
    assert!(
        (m.area() - 0.5 * (world[1] - world[0]).cross(world[2] - world[0]).length()).abs() < 1e-12
    );
    assert!(!m.two_sided());
}

#[test]
fn from_shape_refuses_what_it_cannot_sample() {
    let t = LightTransform::IDENTITY;
    assert_eq!(
        Light::from_shape(
            &LightShape::Portal {
                width: 1.0,
                height: 1.0
            },
            &t
        )
        .unwrap_err(),
        SampleError::NotSampled {
            light: "PortalLight"
        }
    );
    assert!(matches!(
        Light::from_shape(&LightShape::Disk { radius: -1.0 }, &t),
        Err(SampleError::NonPositive {
            field: "radius",
            ..
        })
    ));
    assert!(matches!(
        Light::from_shape(&LightShape::Sphere { radius: f64::NAN }, &t),
        Err(SampleError::NonFinite { .. })
    ));
    assert!(
        Light::from_shape(
            &LightShape::Mesh {
                triangles: Vec::new()
            },
            &t
        )
        .is_err()
    );
    // a singular matrix never becomes a LightTransform
    let e: SampleError = LightTransform::new(DMat4::ZERO).unwrap_err().into();
    assert!(matches!(e, SampleError::BadTransform(_)));
}

/// Π of an `a × b` rectangle parallel to the receiver at height `h`, one corner above it:
/// `X/√(1+X²)·atan(Y/√(1+X²)) + Y/√(1+Y²)·atan(X/√(1+Y²))` over 2 (π times the form factor).
fn corner_rect(a: f64, b: f64, h: f64) -> f64 {
    let (x, y) = (a / h, b / h);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    0.5 * (x / sx * (y / sx).atan() + y / sy * (x / sy).atan())
}

#[test]
fn projected_solid_angles_in_closed_form() {
    // A 2 × 1 rect facing down from height 0.8 (the 1 × 1 rect scaled by 2 in x: non-uniform),
    // receiver below its centre: four corner rectangles of 1 × 0.5.
    let down = xf(DMat4::from_translation(DVec3::new(0.0, 0.0, 0.8))
        * DMat4::from_scale(DVec3::new(2.0, 1.0, 1.0)));
    let rect = Light::from_shape(
        &LightShape::Rect {
            width: 1.0,
            height: 1.0,
        },
        &down,
    )
    .unwrap();
    let r = Reference::surface(DVec3::ZERO, DVec3::Z);
    let want = 4.0 * corner_rect(1.0, 0.5, 0.8);
    let got = rect.projected_solid_angle(&r).unwrap();
    assert!((got - want).abs() < 1e-13, "{got} vs {want}");
    // one-sided: from above (behind its emitting −Z side) it gives nothing, though both faces
    // of the polygon would
    let above = Reference::surface(DVec3::new(0.0, 0.0, 1.6), DVec3::NEG_Z);
    assert_eq!(rect.projected_solid_angle(&above), Some(0.0));
    let Light::Rect(rl) = &rect else { panic!() };
    let both_faces = lux_irradiance::projected::polygon(above.p, above.n, &rl.corners());
    assert!((both_faces - want).abs() < 1e-13, "{both_faces}");
    // no normal, no projected solid angle
    assert_eq!(
        rect.projected_solid_angle(&Reference::point(DVec3::ZERO)),
        None
    );

    // A disk of radius R facing down at height h, coaxial: Π = π R²/(R² + h²).
    let (radius, h) = (0.6, 1.1);
    let disk = Light::from_shape(
        &LightShape::Disk { radius },
        &xf(DMat4::from_translation(DVec3::new(0.0, 0.0, h))),
    )
    .unwrap();
    let want = PI * radius * radius / (radius * radius + h * h);
    assert!((disk.projected_solid_angle(&r).unwrap() - want).abs() < 1e-13);
    assert_eq!(disk.projected_solid_angle(&above), Some(0.0));
    // an elliptic disk has no closed form here
    let squashed = Light::from_shape(&LightShape::Disk { radius }, &sheared()).unwrap();
    assert_eq!(squashed.projected_solid_angle(&r), None);

    // A sphere at distance D off the receiver's normal by ω: π sin²α cos ω when wholly above.
    let (radius, d, omega) = (0.3, 2.0, 0.4f64);
    let centre = DVec3::new(d * omega.sin(), 0.0, d * omega.cos());
    let q = DQuat::from_rotation_z(0.7);
    let sphere = Light::from_shape(
        &LightShape::Sphere { radius: 0.1 },
        &xf(DMat4::from_scale_rotation_translation(
            DVec3::splat(3.0),
            q,
            centre,
        )),
    )
    .unwrap();
    let sin_a = radius / d;
    let want = PI * sin_a * sin_a * omega.cos();
    assert!((sphere.projected_solid_angle(&r).unwrap() - want).abs() < 1e-13);
    let inside = Reference::surface(centre, DVec3::Z);
    assert_eq!(sphere.projected_solid_angle(&inside), Some(0.0));
}

/// Under shear and non-uniform scale the sampler's irradiance estimate `cos θ / pdf` averages to
/// the rect's one-sided Π (the mean of N samples within 4.5 standard errors); behind the rect
/// every sample is refused, as Π = 0 says.
#[test]
fn the_samplers_average_to_the_projected_solid_angle() {
    let t = sheared();
    let rect = Light::from_shape(
        &LightShape::Rect {
            width: 1.2,
            height: 0.8,
        },
        &t,
    )
    .unwrap();
    let disk = Light::from_shape(
        &LightShape::Disk { radius: 0.5 },
        &xf(DMat4::from_rotation_translation(
            DQuat::from_rotation_y(0.5),
            DVec3::new(0.3, 0.0, 1.2),
        )),
    )
    .unwrap();
    let sphere = Light::from_shape(
        &LightShape::Sphere { radius: 0.25 },
        &xf(DMat4::from_translation(DVec3::new(-0.4, 0.3, 0.9))),
    )
    .unwrap();
    let r = Reference::surface(
        DVec3::new(0.05, -0.1, 0.0),
        DVec3::new(0.1, 0.2, 1.0).normalize(),
    );
    for light in [&rect, &disk, &sphere] {
        let pi = light.projected_solid_angle(&r).unwrap();
        assert!(pi > 0.05, "{pi}");
        let mut rng = SplitMix64::new(11);
        let n = 200_000;
        let (mut s, mut s2) = (0.0, 0.0);
        for _ in 0..n {
            let v = light
                .sample(&r, rng.next_2d())
                .map_or(0.0, |x| r.n.dot(x.wi).max(0.0) / x.pdf);
            s += v;
            s2 += v * v;
        }
        let mean = s / n as f64;
        let se = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
        assert!(
            (mean - pi).abs() < 4.5 * se.max(1e-12 * pi),
            "{light:?}: {mean} ± {se} vs {pi}"
        );
    }
    // behind the rect (the other side of its plane from its −Z emission): nothing
    let behind = Reference::surface(t.point(DVec3::new(0.0, 0.0, 1.0)), -t.normal(DVec3::Z));
    assert_eq!(rect.projected_solid_angle(&behind), Some(0.0));
    let mut rng = SplitMix64::new(3);
    for _ in 0..100 {
        assert!(rect.sample(&behind, rng.next_2d()).is_none());
    }
}
