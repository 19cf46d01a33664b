//! χ² goodness-of-fit of every sampler's directions against its own `pdf` (Mitsuba approach),
//! for several placements including near-field and grazing ones; plus the checks that the
//! machinery rejects a wrong density.

mod common;

use common::*;
use glam::{DMat4, DVec3};
use lux_sample::*;

const N: usize = 200_000;
/// Quadrature points per light (or triangle).
const G: usize = 600_000;

fn up(h: f64) -> LightTransform {
    xf(DMat4::from_translation(DVec3::new(0.0, 0.0, h)))
}

#[test]
fn incomplete_gamma_matches_closed_forms() {
    // Q(1, x) = e^{−x}; χ² with 2 dof has p = e^{−χ²/2}; Q(1/2, x) = erfc(√x).
    for &x in &[0.1, 1.0, 3.0, 20.0] {
        assert!((gamma_q(1.0, x) - (-x).exp()).abs() < 1e-13, "{x}");
    }
    assert!((chi2_p_value(4.0, 2) - (-2.0f64).exp()).abs() < 1e-13);
    // erfc(1) = 0.157299207050285130658...
    assert!((gamma_q(0.5, 1.0) - 0.157_299_207_050_285_13).abs() < 1e-12);
    // Median of χ²(100) ≈ 99.334: p ≈ 0.5.
    assert!((chi2_p_value(99.334, 100) - 0.5).abs() < 1e-3);
}

/// The test must be able to fail: the right samples against pdf·(1 + 0.2·tilt) renormalised
/// are rejected, for a wide (near rect) and a narrow (sphere cone) light.
#[test]
fn wrong_pdf_is_rejected() {
    let cases: Vec<(Light, Reference)> = vec![
        (
            Light::Rect(
                RectLight::new(1.0, 1.0, up(0.25), RectTechnique::SphericalRectangle).unwrap(),
            ),
            Reference::surface(DVec3::ZERO, DVec3::Z),
        ),
        (
            Light::Sphere(SphereLight::new(0.5, up(1.5), SphereTechnique::Cone).unwrap()),
            Reference::point(DVec3::ZERO),
        ),
    ];
    for (light, r) in cases {
        let cap = Cap::around(r.p, DVec3::new(0.0, 0.0, 1.5), 0.75, 30, 60);
        let cap = if light.pdf(&r, DVec3::Z) > 1.0 {
            cap
        } else {
            Cap::whole_sphere(DVec3::Z, 30, 60)
        };
        let t = lux_math::Frame::from_normal(cap.axis).t;
        let sin_cap = (1.0 - cap.cos_min * cap.cos_min).max(0.0).sqrt().max(0.05);
        let tilt = |w: DVec3| 1.0 + 0.2 * w.dot(t) / sin_cap;
        let z: f64 = cap
            .integrate(&|w| light.pdf(&r, w) * tilt(w), 6)
            .iter()
            .sum();
        let wrong = |w: DVec3| light.pdf(&r, w) * tilt(w) / z;
        let res = chi2_test(
            cap,
            N,
            1,
            &|u| light.sample(&r, u).map(|s| s.wi),
            &expected_directions(&cap, &wrong, 4 * G),
        );
        assert!(
            res.p_value < 1e-6,
            "wrong pdf accepted: p = {}",
            res.p_value
        );
        // …while the right pdf passes with the same samples.
        let right = expected_directions(&cap, &|w| light.pdf(&r, w), 4 * G);
        let ok = chi2_test(cap, N, 1, &|u| light.sample(&r, u).map(|s| s.wi), &right);
        assert!(ok.p_value > ALPHA, "right pdf rejected: {ok:?}");
    }
}

/// A sampler whose samples do not follow its pdf (directions squeezed towards the axis) fails.
#[test]
fn wrong_samples_are_rejected() {
    let light = SphereLight::new(0.5, up(1.5), SphereTechnique::Cone).unwrap();
    let r = Reference::point(DVec3::ZERO);
    let cap = Cap::around(r.p, DVec3::new(0.0, 0.0, 1.5), 0.5, 30, 60);
    let res = chi2_test(
        cap,
        N,
        2,
        &|u| {
            light
                .sample(&r, [u[0] * (0.9 + 0.1 * u[0]), u[1]])
                .map(|s| s.wi)
        },
        &expected_directions(&cap, &|w| light.pdf(&r, w), 4 * G),
    );
    assert!(
        res.p_value < 1e-6,
        "biased sampler accepted: p = {}",
        res.p_value
    );
}

fn rect_refs() -> Vec<(&'static str, Reference)> {
    vec![
        (
            "near",
            Reference::surface(DVec3::new(0.0, 0.0, -0.25), DVec3::Z),
        ),
        (
            "offset",
            Reference::surface(
                DVec3::new(0.7, 0.4, -1.0),
                DVec3::new(0.3, 0.0, 1.0).normalize(),
            ),
        ),
        (
            "far",
            Reference::surface(DVec3::new(3.0, -2.0, -5.0), DVec3::Z),
        ),
        (
            "grazing",
            Reference::surface(
                DVec3::new(1.5, 0.2, -0.03),
                DVec3::new(-1.0, 0.0, 0.2).normalize(),
            ),
        ),
        (
            "tilted receiver",
            Reference::surface(
                DVec3::new(0.2, 0.1, -0.3),
                DVec3::new(1.0, 0.2, 0.3).normalize(),
            ),
        ),
    ]
}

#[test]
fn rect_all_techniques() {
    for t in [
        RectTechnique::Area,
        RectTechnique::SphericalRectangle,
        RectTechnique::SphericalRectangleCosine,
    ] {
        for (w, h, m) in [
            (1.0, 1.0, DMat4::IDENTITY),
            (2.0, 0.5, DMat4::from_rotation_z(0.4)),
            (1.0, 1.0, DMat4::from_scale(DVec3::new(0.5, 2.0, 1.0))),
            (1.0, 0.7, skewed(DVec3::ZERO)),
        ] {
            let light = Light::Rect(RectLight::new(w, h, xf(m), t).unwrap());
            let centre = xf(m).point(DVec3::ZERO);
            let rad = 0.5 * (w * w + h * h).sqrt() * 2.5;
            for (name, r0) in rect_refs() {
                // Place the reference in the light's local frame so it is on the emitting side.
                let r = Reference::surface(xf(m).point(r0.p), xf(m).vector(r0.n).normalize());
                let cap = Cap::around(r.p, centre, rad, 40, 80);
                let e = pick(
                    t != RectTechnique::Area
                        && (r.p - centre).length() < 0.5 * (w * w + h * h).sqrt(),
                    &cap,
                    &r,
                    &light,
                    &rect_surface(w, h, xf(m)),
                );
                check_light(
                    &format!("rect {t:?} {w}x{h} {name}"),
                    &light,
                    &r,
                    cap,
                    N / 4,
                    &e,
                );
            }
        }
    }
}

#[test]
fn disk_all_techniques() {
    for t in [
        DiskTechnique::Area,
        DiskTechnique::PolarChord,
        DiskTechnique::EllipticCone,
    ] {
        for m in [
            DMat4::IDENTITY,
            DMat4::from_scale(DVec3::new(2.0, 0.5, 1.0)),
            skewed(DVec3::new(0.1, 0.0, 0.0)),
        ] {
            let light = Light::Disk(DiskLight::new(0.5, xf(m), t).unwrap());
            for (name, pl) in [
                ("on axis", DVec3::new(0.0, 0.0, -0.5)),
                ("inside offset", DVec3::new(0.2, 0.1, -0.1)),
                ("outside", DVec3::new(1.5, 0.3, -0.4)),
                ("far", DVec3::new(-4.0, 3.0, -6.0)),
                ("grazing", DVec3::new(2.0, 0.0, -0.02)),
            ] {
                let r = Reference::point(xf(m).point(pl));
                let cap = Cap::around(r.p, xf(m).point(DVec3::ZERO), 1.6, 40, 80);
                let e = expected_surface(&cap, r.p, G, &disk_surface(0.5, xf(m)), &|d| {
                    light.pdf(&r, d)
                });
                check_light(
                    &format!("disk {t:?} {name} {m:?}"),
                    &light,
                    &r,
                    cap,
                    N / 4,
                    &e,
                );
            }
        }
    }
}

#[test]
fn sphere_all_techniques() {
    for t in [SphereTechnique::Area, SphereTechnique::Cone] {
        for (rad, m) in [
            (0.5, DMat4::IDENTITY),
            (0.5, DMat4::from_scale(DVec3::new(1.0, 2.0, 0.5))),
            (0.3, skewed(DVec3::ZERO)),
            // rotation + uniform scale + translation: sampled directly in world space
            (
                0.4,
                DMat4::from_scale_rotation_translation(
                    DVec3::splat(1.7),
                    glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.4, -1.1, 2.3),
                    DVec3::new(0.3, -0.2, 0.5),
                ),
            ),
        ] {
            let light = Light::Sphere(SphereLight::new(rad, xf(m), t).unwrap());
            for (name, pl, nt) in [
                ("d=1.5", DVec3::new(0.0, 0.0, -3.0 * rad), 40),
                ("near", DVec3::new(0.0, 1.02 * rad, 0.0), 40),
                ("inside", DVec3::new(0.1 * rad, 0.2 * rad, -0.3 * rad), 40),
                ("far", DVec3::new(30.0, 20.0, -40.0) * rad, 20),
            ] {
                let r = Reference::point(xf(m).point(pl));
                let bound = rad * 2.5;
                let cap = Cap::around(r.p, xf(m).point(DVec3::ZERO), bound, nt, 2 * nt);
                let inside = xf(m).inv_point(r.p).length() <= rad;
                let e = pick(
                    t == SphereTechnique::Cone && !inside && pl.length() < 2.0 * rad,
                    &cap,
                    &r,
                    &light,
                    &sphere_surface(rad, xf(m), r.p),
                );
                check_light(
                    &format!("sphere {t:?} {name} {m:?}"),
                    &light,
                    &r,
                    cap,
                    N / 4,
                    &e,
                );
            }
        }
    }
}

/// The cosine-weighted projected-cap technique from receivers with a normal: wholly above the
/// horizon (the ellipse), cut by it and without a normal (the cone fallback), near and far,
/// for a sphere in world space and under a uniform scale and rotation.
#[test]
fn sphere_projected_cap() {
    for (rad, m) in [
        (0.5, DMat4::IDENTITY),
        (
            0.4,
            DMat4::from_scale_rotation_translation(
                DVec3::splat(1.7),
                glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.4, -1.1, 2.3),
                DVec3::new(0.3, -0.2, 0.5),
            ),
        ),
    ] {
        let light =
            Light::Sphere(SphereLight::new(rad, xf(m), SphereTechnique::ProjectedCap).unwrap());
        let s = 1.7f64.max(1.0) * rad;
        for (name, pl, n) in [
            ("above, facing", DVec3::new(0.0, 0.0, -3.0 * rad), DVec3::Z),
            (
                "above, tilted",
                DVec3::new(0.5, 0.2, -2.5) * rad,
                DVec3::new(0.4, -0.2, 1.0),
            ),
            (
                "near",
                DVec3::new(0.0, 0.0, -1.1 * rad),
                DVec3::new(0.1, 0.0, 1.0),
            ),
            (
                "cut by the horizon",
                DVec3::new(2.0, 0.0, -0.3) * rad,
                DVec3::Z,
            ),
            ("no normal", DVec3::new(0.3, 0.1, -2.0) * rad, DVec3::ZERO),
        ] {
            let p = xf(m).point(pl);
            let nw = if n == DVec3::ZERO {
                n
            } else {
                xf(m).vector(n).normalize()
            };
            let r = if n == DVec3::ZERO {
                Reference::point(p)
            } else {
                Reference::surface(p, nw)
            };
            let cap = Cap::around(r.p, xf(m).point(DVec3::ZERO), 2.5 * s, 40, 80);
            let e = pick(true, &cap, &r, &light, &sphere_surface(rad, xf(m), r.p));
            check_light(
                &format!("sphere projected cap {name} {m:?}"),
                &light,
                &r,
                cap,
                N / 4,
                &e,
            );
        }
    }
}

/// A tiny, very distant sphere (small-angle regime, α ≈ 1e-4 rad) is still sampled correctly.
#[test]
fn sphere_small_angle() {
    let light = Light::Sphere(SphereLight::new(1e-3, up(10.0), SphereTechnique::Cone).unwrap());
    let r = Reference::point(DVec3::ZERO);
    let cap = Cap {
        axis: DVec3::Z,
        cos_min: 1.0 - 2e-8,
        nt: 20,
        np: 40,
    };
    let e = expected_surface(&cap, r.p, G, &sphere_surface(1e-3, up(10.0), r.p), &|d| {
        light.pdf(&r, d)
    });
    check_light("sphere small angle", &light, &r, cap, N / 4, &e);
}

#[test]
fn cylinder_all_techniques() {
    for t in [
        CylinderTechnique::Area,
        CylinderTechnique::VisibleArea,
        CylinderTechnique::SolidAngle,
    ] {
        for m in [
            DMat4::IDENTITY,
            DMat4::from_scale(DVec3::new(1.0, 2.0, 0.5)),
            skewed(DVec3::ZERO),
        ] {
            let light = Light::Cylinder(CylinderLight::new(0.5, 1.0, xf(m), t).unwrap());
            for (name, pl) in [
                ("below", DVec3::new(0.0, 0.0, -1.0)),
                ("oblique", DVec3::new(0.8, 0.6, -0.7)),
                ("past the end", DVec3::new(1.2, 0.0, -0.8)),
                ("near", DVec3::new(0.1, 0.0, -0.55)),
                // Past the end, barely outside the radius: the lateral surface is seen edge-on.
                ("grazing", DVec3::new(1.5, 0.0, -0.52)),
                ("far", DVec3::new(5.0, -4.0, 6.0)),
            ] {
                let r = Reference::point(xf(m).point(pl));
                let cap = Cap::around(r.p, xf(m).point(DVec3::ZERO), 2.5, 40, 80);
                let e = pick(
                    t == CylinderTechnique::SolidAngle && pl.length() < 0.75,
                    &cap,
                    &r,
                    &light,
                    &cylinder_surface(0.5, 1.0, xf(m), r.p),
                );
                check_light(
                    &format!("cylinder {t:?} {name} {m:?}"),
                    &light,
                    &r,
                    cap,
                    N / 4,
                    &e,
                );
            }
        }
    }
}

fn tetra() -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let p = vec![
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(0.9, 0.0, -0.3),
        DVec3::new(-0.45, 0.8, -0.3),
        DVec3::new(-0.45, -0.8, -0.3),
    ];
    // Outward orientation (right-handed).
    let i = vec![[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]];
    (p, i)
}

#[test]
fn mesh_all_techniques() {
    let (p, i) = tetra();
    for t in [MeshTechnique::Area, MeshTechnique::SphericalTriangle] {
        for two_sided in [false, true] {
            let power = [1.0, 2.0, 0.5, 3.0];
            let mesh = MeshLight::new(&p, &i, Some(&power), two_sided, t).unwrap();
            let light = Light::Mesh(mesh.clone());
            for (name, r) in [
                ("near", DVec3::new(0.1, 0.2, 1.3)),
                ("side", DVec3::new(2.0, 1.0, 0.2)),
                // Just below the plane of the bottom face (z = −0.3): that face is seen edge-on.
                ("grazing", DVec3::new(2.0, 0.3, -0.32)),
                ("far", DVec3::new(-8.0, 5.0, 3.0)),
            ] {
                let r = Reference::point(r);
                let cap = Cap::around(r.p, DVec3::ZERO, 1.2, 40, 80);
                let e = {
                    let mut e = vec![0.0; cap.nt * cap.np];
                    for (k, tri) in i.iter().enumerate() {
                        let v = [p[tri[0] as usize], p[tri[1] as usize], p[tri[2] as usize]];
                        let ek = expected_surface(&cap, r.p, G, &triangle_surface(v), &|d| {
                            mesh.pdf_triangle(&r, k, d)
                        });
                        e.iter_mut().zip(ek).for_each(|(a, b)| *a += b);
                    }
                    e
                };
                check_light(
                    &format!("mesh {t:?} two_sided={two_sided} {name}"),
                    &light,
                    &r,
                    cap,
                    N / 4,
                    &e,
                );
            }
        }
    }
}

#[test]
fn distant_cones() {
    for angle in [0.53, 10.0, 120.0, 300.0] {
        let m = DMat4::from_rotation_x(0.7) * DMat4::from_rotation_z(0.2);
        let light = DistantLight::new(angle, &xf(m)).unwrap();
        let axis = light.direction();
        let half = (angle * 0.5f64).to_radians();
        let cap = if half * 1.2 < std::f64::consts::PI {
            Cap {
                axis,
                cos_min: (half * 1.2).cos(),
                nt: 30,
                np: 60,
            }
        } else {
            Cap::whole_sphere(axis, 30, 60)
        };
        let e = expected_directions(
            &cap,
            &|d| light.pdf(&Reference::point(DVec3::ZERO), d),
            4 * G,
        );
        check_light(
            &format!("distant {angle}°"),
            &Light::Distant(light),
            &Reference::point(DVec3::ZERO),
            cap,
            N / 4,
            &e,
        );
    }
}

fn test_map() -> LatLongMap {
    let (w, h) = (64, 32);
    let mut t = vec![0.0f32; w * h];
    for y in 0..h {
        for x in 0..w {
            // A smooth sky gradient, a bright "sun" and a black patch.
            let mut v = 0.2 + (y as f32 / h as f32);
            if (x as i32 - 40).abs() < 3 && (y as i32 - 9).abs() < 2 {
                v = 5.0;
            }
            if (10..20).contains(&x) && (20..26).contains(&y) {
                v = 0.0;
            }
            t[y * w + x] = v;
        }
    }
    LatLongMap::new(w, h, t).unwrap()
}

#[test]
fn dome_all_techniques() {
    let r = Reference::point(DVec3::new(3.0, 1.0, 2.0));
    let m = DMat4::from_rotation_x(std::f64::consts::FRAC_PI_2) * DMat4::from_rotation_y(0.3);
    let uniform = Light::Dome(DomeLight::uniform(xf(m)));
    let e = expected_directions(
        &Cap::whole_sphere(DVec3::Y, 30, 60),
        &|d| uniform.pdf(&r, d),
        4 * G,
    );
    check_light(
        "dome uniform",
        &uniform,
        &r,
        Cap::whole_sphere(DVec3::Y, 30, 60),
        N / 4,
        &e,
    );
    for t in [DomeTechnique::Texture, DomeTechnique::MisCompensated] {
        for m in [
            DMat4::IDENTITY,
            m,
            DMat4::from_scale(DVec3::new(1.0, 3.0, 1.0)),
        ] {
            let light = Light::Dome(DomeLight::new(&test_map(), xf(m), t).unwrap());
            let e = expected_directions(
                &Cap::whole_sphere(DVec3::Y, 40, 80),
                &|d| light.pdf(&r, d),
                4 * G,
            );
            check_light(
                &format!("dome {t:?} {m:?}"),
                &light,
                &r,
                Cap::whole_sphere(DVec3::Y, 40, 80),
                N,
                &e,
            );
        }
    }
}

/// ∫ pdf dω = 1 over the sphere for every light that always succeeds (quadrature on a fine
/// cap grid; the tolerance is the quadrature error of the silhouette bins, 2e-3).
#[test]
fn pdfs_integrate_to_one() {
    let r = Reference::surface(DVec3::new(0.2, -0.1, -0.6), DVec3::Z);
    let lights: Vec<(&str, Light, DVec3, f64)> = vec![
        (
            "rect",
            Light::Rect(
                RectLight::new(
                    1.0,
                    1.0,
                    xf(skewed(DVec3::ZERO)),
                    RectTechnique::SphericalRectangleCosine,
                )
                .unwrap(),
            ),
            DVec3::ZERO,
            1.5,
        ),
        (
            "disk",
            Light::Disk(
                DiskLight::new(0.5, LightTransform::IDENTITY, DiskTechnique::PolarChord).unwrap(),
            ),
            DVec3::ZERO,
            0.6,
        ),
        (
            "sphere",
            Light::Sphere(
                SphereLight::new(0.3, xf(skewed(DVec3::ZERO)), SphereTechnique::Cone).unwrap(),
            ),
            DVec3::ZERO,
            0.8,
        ),
        (
            "cylinder",
            Light::Cylinder(
                CylinderLight::new(
                    0.2,
                    1.0,
                    LightTransform::IDENTITY,
                    CylinderTechnique::SolidAngle,
                )
                .unwrap(),
            ),
            DVec3::ZERO,
            0.6,
        ),
    ];
    for (name, light, c, rad) in lights {
        let cap = Cap::around(r.p, c, rad, 200, 400);
        let m: f64 = cap.integrate(&|w| light.pdf(&r, w), 4).iter().sum();
        assert!((m - 1.0).abs() < 2e-3, "{name}: ∫pdf = {m}");
    }
}

/// ∫ pdf dω over the sphere equals the probability that `sample` succeeds, for every light and
/// every technique: 1 for the techniques that always return a sample, the visible fraction for
/// the area techniques of spheres and cylinders (back-facing samples return `None`) and for
/// one-sided meshes. Finite lights are integrated over their surface (pdf·cos θₗ/d² dA, the
/// same integral without the grazing singularities of the direction pdf), lights at infinity
/// over directions; the success probability is estimated from 200 000 samples.
#[test]
fn pdf_integral_equals_success_probability() {
    let n = 200_000;
    let success = |light: &Light, r: &Reference| {
        let mut rng = SplitMix64::new(5);
        (0..n)
            .filter(|_| light.sample(r, rng.next_2d()).is_some())
            .count() as f64
            / n as f64
    };
    let check = |name: &str, light: &Light, r: &Reference, integral: f64| {
        let p = success(light, r);
        let sigma = (p * (1.0 - p) / n as f64).sqrt();
        assert!(
            (integral - p).abs() <= 4.0 * sigma + 3e-3,
            "{name}: ∫pdf dω = {integral}, P(sample) = {p}"
        );
        if p == 1.0 {
            assert!(
                (integral - 1.0).abs() < 3e-3,
                "{name}: ∫pdf dω = {integral}"
            );
        }
    };
    let whole = |r: &Reference| Cap::whole_sphere((DVec3::ZERO - r.p).normalize(), 20, 40);
    let m = skewed(DVec3::new(0.1, -0.2, 0.3));
    let r = Reference::surface(xf(m).point(DVec3::new(0.3, -0.2, -0.7)), DVec3::Z);
    for t in [
        RectTechnique::Area,
        RectTechnique::SphericalRectangle,
        RectTechnique::SphericalRectangleCosine,
    ] {
        let light = Light::Rect(RectLight::new(1.0, 0.7, xf(m), t).unwrap());
        let e: f64 = expected_surface(&whole(&r), r.p, G, &rect_surface(1.0, 0.7, xf(m)), &|d| {
            light.pdf(&r, d)
        })
        .iter()
        .sum();
        check(&format!("rect {t:?}"), &light, &r, e);
    }
    for t in [
        DiskTechnique::Area,
        DiskTechnique::PolarChord,
        DiskTechnique::EllipticCone,
    ] {
        let light = Light::Disk(DiskLight::new(0.5, xf(m), t).unwrap());
        let e: f64 = expected_surface(&whole(&r), r.p, G, &disk_surface(0.5, xf(m)), &|d| {
            light.pdf(&r, d)
        })
        .iter()
        .sum();
        check(&format!("disk {t:?}"), &light, &r, e);
    }
    for t in [SphereTechnique::Area, SphereTechnique::Cone] {
        for pl in [DVec3::new(0.3, -0.2, -0.7), DVec3::new(0.1, 0.05, -0.1)] {
            let light = Light::Sphere(SphereLight::new(0.4, xf(m), t).unwrap());
            let r = Reference::point(xf(m).point(pl));
            let e: f64 =
                expected_surface(&whole(&r), r.p, G, &sphere_surface(0.4, xf(m), r.p), &|d| {
                    light.pdf(&r, d)
                })
                .iter()
                .sum();
            check(&format!("sphere {t:?} {pl}"), &light, &r, e);
        }
    }
    for t in [
        CylinderTechnique::Area,
        CylinderTechnique::VisibleArea,
        CylinderTechnique::SolidAngle,
    ] {
        let light = Light::Cylinder(CylinderLight::new(0.3, 1.0, xf(m), t).unwrap());
        let r = Reference::point(xf(m).point(DVec3::new(0.3, -0.2, -0.7)));
        let e: f64 = expected_surface(
            &whole(&r),
            r.p,
            G,
            &cylinder_surface(0.3, 1.0, xf(m), r.p),
            &|d| light.pdf(&r, d),
        )
        .iter()
        .sum();
        check(&format!("cylinder {t:?}"), &light, &r, e);
    }
    let (p, i) = tetra();
    for t in [MeshTechnique::Area, MeshTechnique::SphericalTriangle] {
        for two_sided in [false, true] {
            let mesh = MeshLight::new(&p, &i, Some(&[1.0, 2.0, 0.5, 3.0]), two_sided, t).unwrap();
            let r = Reference::point(DVec3::new(0.4, 0.3, 1.1));
            let mut e = 0.0;
            for (k, tri) in i.iter().enumerate() {
                let v = [p[tri[0] as usize], p[tri[1] as usize], p[tri[2] as usize]];
                e += expected_surface(&whole(&r), r.p, G, &triangle_surface(v), &|d| {
                    mesh.pdf_triangle(&r, k, d)
                })
                .iter()
                .sum::<f64>();
            }
            check(
                &format!("mesh {t:?} two_sided={two_sided}"),
                &Light::Mesh(mesh),
                &r,
                e,
            );
        }
    }
    let r = Reference::point(DVec3::ZERO);
    for angle in [10.0, 300.0] {
        let d = DistantLight::new(angle, &xf(m)).unwrap();
        let half = (0.5 * angle).to_radians() * 1.2;
        let cap = Cap {
            axis: d.direction(),
            cos_min: if half < std::f64::consts::PI {
                half.cos()
            } else {
                -1.0
            },
            nt: 200,
            np: 400,
        };
        let light = Light::Distant(d);
        let e: f64 = cap.integrate(&|d| light.pdf(&r, d), 4).iter().sum();
        check(&format!("distant {angle}"), &light, &r, e);
    }
    let mut domes = vec![(
        "dome uniform".to_string(),
        Light::Dome(DomeLight::uniform(xf(m))),
    )];
    for t in [DomeTechnique::Texture, DomeTechnique::MisCompensated] {
        domes.push((
            format!("dome {t:?}"),
            Light::Dome(DomeLight::new(&test_map(), xf(m), t).unwrap()),
        ));
    }
    for (name, light) in domes {
        let e: f64 = Cap::whole_sphere(DVec3::Y, 200, 400)
            .integrate(&|d| light.pdf(&r, d), 4)
            .iter()
            .sum();
        check(&name, &light, &r, e);
    }
}

/// Expected bin probabilities: direction-space quadrature for solid-angle techniques (their pdf
/// is bounded and piecewise constant/smooth in direction), surface quadrature for area
/// techniques (their direction pdf is singular at grazing angles but constant per area).
/// Far from the light, slivers seen edge-on defeat direction quadrature, so callers pass
/// `solid_angle = true` only for solid-angle techniques seen from the near field.
fn pick(
    solid_angle: bool,
    cap: &Cap,
    r: &Reference,
    light: &Light,
    surface: &dyn Fn(f64, f64) -> Option<(DVec3, DVec3, f64)>,
) -> Vec<f64> {
    if solid_angle {
        expected_directions(cap, &|d| light.pdf(r, d), 4 * G)
    } else {
        expected_surface(cap, r.p, G, surface, &|d| light.pdf(r, d))
    }
}
