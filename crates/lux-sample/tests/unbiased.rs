//! Unbiasedness: Monte-Carlo unshadowed irradiance from each light (radiance 1) against closed
//! forms, within 4σ (σ the standard error of the estimate, itself required to be < 1 % so the
//! comparison is decisive).

mod common;

use common::*;
use glam::{DMat4, DVec3};
use lux_sample::*;
use std::f64::consts::{PI, TAU};

const N: usize = 200_000;

fn assert_mc(name: &str, light: &Light, r: &Reference, exact: f64) {
    let (mean, se) = mc_irradiance(light, r, N, 0xE1 ^ name.len() as u64);
    assert!(
        se < 0.01 * exact,
        "{name}: estimate not decisive: {mean} ± {se} (exact {exact})"
    );
    assert!(
        (mean - exact).abs() < 4.0 * se,
        "{name}: E = {mean} ± {se}, closed form {exact} ({:.1}σ)",
        (mean - exact) / se
    );
}

#[test]
fn rect_matches_polygon_form_factor() {
    for t in [
        RectTechnique::Area,
        RectTechnique::SphericalRectangle,
        RectTechnique::SphericalRectangleCosine,
    ] {
        for (m, p, n) in [
            (
                DMat4::from_translation(DVec3::new(0.0, 0.0, 0.25)),
                DVec3::ZERO,
                DVec3::Z,
            ),
            (
                DMat4::from_translation(DVec3::new(0.0, 0.0, 1.0)),
                DVec3::new(0.4, 0.1, 0.0),
                DVec3::Z,
            ),
            (
                DMat4::from_translation(DVec3::new(0.2, 0.0, 0.6)) * DMat4::from_rotation_y(0.3),
                DVec3::ZERO,
                DVec3::new(0.2, 0.1, 1.0).normalize(),
            ),
            // Sheared, non-uniformly scaled: a parallelogram.
            (
                skewed(DVec3::new(0.0, 0.0, 0.8)),
                DVec3::new(0.1, 0.3, 0.0),
                DVec3::Z,
            ),
        ] {
            let light = RectLight::new(1.0, 0.8, xf(m), t).unwrap();
            let exact = polygon_irradiance(p, n, &light.corners());
            assert_mc(
                &format!("rect {t:?} {m:?}"),
                &Light::Rect(light),
                &Reference::surface(p, n),
                exact,
            );
        }
    }
}

fn ellipse_polygon(m: DMat4, r: f64, k: usize) -> Vec<DVec3> {
    (0..k)
        .map(|i| {
            let a = TAU * i as f64 / k as f64;
            m.transform_point3(DVec3::new(r * a.cos(), r * a.sin(), 0.0))
        })
        .collect()
}

#[test]
fn disk_matches_on_axis_closed_form_and_polygon() {
    for t in [
        DiskTechnique::Area,
        DiskTechnique::PolarChord,
        DiskTechnique::EllipticCone,
    ] {
        // On axis: E = π r²/(r² + h²).
        let (r, h) = (0.5, 0.5);
        let light =
            DiskLight::new(r, xf(DMat4::from_translation(DVec3::new(0.0, 0.0, h))), t).unwrap();
        let exact = PI * r * r / (r * r + h * h);
        assert_mc(
            &format!("disk {t:?} on axis"),
            &Light::Disk(light),
            &Reference::surface(DVec3::ZERO, DVec3::Z),
            exact,
        );
        // Off axis and under shear/non-uniform scale: the ellipse as a 4096-gon (relative
        // error ~ (2π/4096)²/6 ≈ 4e-7).
        for (m, p) in [
            (
                DMat4::from_translation(DVec3::new(0.7, 0.2, 0.4)),
                DVec3::ZERO,
            ),
            (
                skewed(DVec3::new(0.0, 0.0, 0.7)),
                DVec3::new(0.3, -0.2, 0.0),
            ),
        ] {
            let light = DiskLight::new(0.5, xf(m), t).unwrap();
            let exact = polygon_irradiance(p, DVec3::Z, &ellipse_polygon(m, 0.5, 4096));
            assert_mc(
                &format!("disk {t:?} {m:?}"),
                &Light::Disk(light),
                &Reference::surface(p, DVec3::Z),
                exact,
            );
        }
    }
}

#[test]
fn sphere_matches_closed_form() {
    for t in [SphereTechnique::Area, SphereTechnique::Cone] {
        // E = π sin²α cos θ for a sphere fully above the horizon.
        for (c, rad) in [
            (DVec3::new(0.0, 0.0, 1.5), 0.5),
            (DVec3::new(0.5, 0.3, 1.2), 0.3),
            (DVec3::new(30.0, 0.0, 40.0), 0.2),
        ] {
            let light = SphereLight::new(rad, LightTransform::from_translation(c), t).unwrap();
            let d = c.length();
            let exact = PI * rad * rad / (d * d) * c.z / d;
            assert_mc(
                &format!("sphere {t:?} {c}"),
                &Light::Sphere(light),
                &Reference::surface(DVec3::ZERO, DVec3::Z),
                exact,
            );
        }
        // Ellipsoid: Lambert's formula on the silhouette curve (the image of the local tangent
        // circle), as a 4096-gon.
        let m = skewed(DVec3::new(0.2, 0.1, 1.6));
        let rad = 0.4;
        let light = SphereLight::new(rad, xf(m), t).unwrap();
        let pl = xf(m).inv_point(DVec3::ZERO);
        let d2 = pl.length_squared();
        let centre = pl * (rad * rad / d2);
        let radius = rad * (1.0 - rad * rad / d2).sqrt();
        let f = lux_math::Frame::from_normal(pl.normalize());
        let poly: Vec<DVec3> = (0..4096)
            .map(|i| {
                let a = TAU * i as f64 / 4096.0;
                m.transform_point3(centre + radius * (a.cos() * f.t + a.sin() * f.b))
            })
            .collect();
        let exact = polygon_irradiance(DVec3::ZERO, DVec3::Z, &poly);
        assert_mc(
            &format!("ellipsoid {t:?}"),
            &Light::Sphere(light),
            &Reference::surface(DVec3::ZERO, DVec3::Z),
            exact,
        );
    }
}

#[test]
fn cylinder_matches_quadrature() {
    for (m, p) in [
        (
            DMat4::from_translation(DVec3::new(0.0, 0.0, 1.0)),
            DVec3::ZERO,
        ),
        (
            DMat4::from_translation(DVec3::new(0.6, 0.2, 0.9)) * DMat4::from_rotation_z(0.5),
            DVec3::ZERO,
        ),
        (skewed(DVec3::new(0.0, 0.3, 1.2)), DVec3::new(0.1, 0.0, 0.0)),
    ] {
        // Reference: E = ∫ cos θᵣ cos θₗ / d² dA over the front-facing lateral surface, midpoint
        // rule on 2000×2000 cells (smooth integrand, error < 1e-5 relative).
        let surf = cylinder_surface(0.5, 1.0, xf(m), p);
        let g = 2000;
        let mut exact = 0.0;
        for i in 0..g {
            for j in 0..g {
                let (s, t) = ((i as f64 + 0.5) / g as f64, (j as f64 + 0.5) / g as f64);
                if let Some((q, nrm, jac)) = surf(s, t) {
                    let v = q - p;
                    let d2 = v.length_squared();
                    let w = v / d2.sqrt();
                    exact += w.z.max(0.0) * nrm.dot(-w) / d2 * jac;
                }
            }
        }
        exact /= (g * g) as f64;
        for t in [
            CylinderTechnique::Area,
            CylinderTechnique::VisibleArea,
            CylinderTechnique::SolidAngle,
        ] {
            let light = CylinderLight::new(0.5, 1.0, xf(m), t).unwrap();
            assert_mc(
                &format!("cylinder {t:?} {m:?}"),
                &Light::Cylinder(light),
                &Reference::surface(p, DVec3::Z),
                exact,
            );
        }
    }
}

#[test]
fn mesh_matches_polygon_form_factor() {
    // A unit square split into two triangles, facing down (−Z) at height 0.5.
    let pts = [
        DVec3::new(-0.5, -0.5, 0.5),
        DVec3::new(0.5, -0.5, 0.5),
        DVec3::new(0.5, 0.5, 0.5),
        DVec3::new(-0.5, 0.5, 0.5),
    ];
    let idx = [[0, 2, 1], [0, 3, 2]];
    let p = DVec3::new(0.2, 0.1, 0.0);
    let exact = polygon_irradiance(p, DVec3::Z, &pts);
    for t in [MeshTechnique::Area, MeshTechnique::SphericalTriangle] {
        for power in [None, Some([1.0, 3.0])] {
            let light =
                MeshLight::new(&pts, &idx, power.as_ref().map(|p| &p[..]), false, t).unwrap();
            assert_mc(
                &format!("mesh {t:?} {power:?}"),
                &Light::Mesh(light),
                &Reference::surface(p, DVec3::Z),
                exact,
            );
        }
    }
    // Seen from behind, a one-sided mesh gives nothing.
    let light = MeshLight::new(&pts, &idx, None, false, MeshTechnique::SphericalTriangle).unwrap();
    let r = Reference::surface(DVec3::new(0.0, 0.0, 1.0), -DVec3::Z);
    assert!(light.sample(&r, [0.3, 0.6]).is_none());
    assert_eq!(light.pdf(&r, -DVec3::Z), 0.0);
    assert!((light.area() - 1.0).abs() < 1e-15);
}

#[test]
fn distant_matches_closed_form() {
    // E = π sin²θmax cos θ for a cone fully above the horizon (normalize off, radiance 1).
    for angle in [0.53, 10.0, 60.0] {
        let m = DMat4::from_rotation_x(0.4);
        let light = DistantLight::new(angle, &xf(m)).unwrap();
        let half = (0.5 * angle).to_radians();
        let exact = PI * half.sin().powi(2) * light.direction().z;
        assert_mc(
            &format!("distant {angle}"),
            &Light::Distant(light),
            &Reference::surface(DVec3::ZERO, DVec3::Z),
            exact,
        );
        // The sampling measure is the cone's solid angle 2π(1 − cos θmax).
        assert!(
            (light.solid_angle() - TAU * (1.0 - half.cos())).abs()
                < 1e-12 * light.solid_angle().max(1e-3)
        );
    }
    // angle = 0: a delta light; E = cos θ from one sample with pdf 1.
    let light = DistantLight::new(0.0, &xf(DMat4::from_rotation_x(0.4))).unwrap();
    let s = light
        .sample(&Reference::point(DVec3::ZERO), [0.3, 0.7])
        .unwrap();
    assert!(s.delta && s.pdf == 1.0 && s.distance.is_infinite());
    assert!((s.wi.z - 0.4f64.cos()).abs() < 1e-15);
    assert_eq!(light.pdf(&Reference::point(DVec3::ZERO), s.wi), 0.0);
    assert!(DistantLight::new(f64::NAN, &LightTransform::IDENTITY).is_err());
}

#[test]
fn dome_matches_closed_form_and_texel_sum() {
    // Uniform dome of radiance 1: E = π on any surface.
    let uniform = Light::Dome(DomeLight::uniform(LightTransform::IDENTITY));
    assert_mc(
        "dome uniform",
        &uniform,
        &Reference::surface(DVec3::ZERO, DVec3::new(0.3, 0.8, 0.1).normalize()),
        PI,
    );
    // A textured dome (radiance = texel value, nearest-texel): E = Σ texel·∫_texel max(cos, 0) dω,
    // the inner integral by a 16×16 midpoint rule per texel.
    let (w, h) = (32, 16);
    let tex: Vec<f32> = (0..w * h)
        .map(|i| 0.1 + ((i * 37) % 11) as f32 + if i == 100 { 300.0 } else { 0.0 })
        .collect();
    let map = LatLongMap::new(w, h, tex.clone()).unwrap();
    let n = DVec3::new(0.2, 0.9, -0.3).normalize();
    let mut exact = 0.0;
    let k = 16;
    for y in 0..h {
        for x in 0..w {
            let mut s = 0.0;
            for i in 0..k {
                for j in 0..k {
                    let uv = [
                        (x as f64 + (j as f64 + 0.5) / k as f64) / w as f64,
                        (y as f64 + (i as f64 + 0.5) / k as f64) / h as f64,
                    ];
                    let d = latlong_direction(uv);
                    s += d.dot(n).max(0.0) * (PI * uv[1]).sin();
                }
            }
            exact += tex[y * w + x] as f64 * s * 2.0 * PI * PI / (w * h * k * k) as f64;
        }
    }
    for t in [DomeTechnique::Texture, DomeTechnique::MisCompensated] {
        let light = DomeLight::new(&map, LightTransform::IDENTITY, t).unwrap();
        let r = Reference::surface(DVec3::ZERO, n);
        let mut rng = SplitMix64::new(17);
        let (mut s1, mut s2) = (0.0, 0.0);
        for _ in 0..N {
            let v = light.sample(&r, rng.next_2d()).map_or(0.0, |ls| {
                let l = map.texel(latlong_uv(ls.wi));
                l * n.dot(ls.wi).max(0.0) / ls.pdf
            });
            s1 += v;
            s2 += v * v;
        }
        let mean = s1 / N as f64;
        let se = ((s2 / N as f64 - mean * mean) / N as f64).sqrt();
        if t == DomeTechnique::Texture {
            assert!(se < 0.01 * exact);
            assert!(
                (mean - exact).abs() < 4.0 * se,
                "dome {t:?}: {mean} ± {se} vs {exact}"
            );
        } else {
            // The compensated density is zero below the mean: alone it is biased (by design, it is
            // meant for MIS with BSDF sampling); the estimate must fall short.
            assert!(
                mean < exact - 4.0 * se,
                "dome {t:?}: {mean} ± {se} vs {exact}"
            );
        }
    }
}

/// Emission sampling of a mesh light ([`MeshLight::sample_area`]): points uniform on triangles
/// chosen by their weights, with density `pmf / area`. Over the unit square split into two
/// triangles (selection weights 1 : 3, not their areas), the estimate of `∫ x² dA` is its
/// closed form 1/3 within 4 standard errors, every point lies in the square, and the front
/// normal is +Z.
#[test]
fn mesh_area_samples_integrate_over_the_surface() {
    let points = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
    ];
    let mesh = MeshLight::new(
        &points,
        &[[0, 1, 2], [0, 2, 3]],
        Some(&[1.0, 3.0]),
        false,
        MeshTechnique::Area,
    )
    .unwrap();
    assert!(!mesh.two_sided());
    let mut rng = SplitMix64::new(11);
    let n = 200_000;
    let (mut sum, mut sum2, mut second) = (0.0, 0.0, 0usize);
    for _ in 0..n {
        let s = mesh
            .sample_area([rng.next_f64(), rng.next_f64()])
            .expect("non-degenerate");
        assert!((0.0..=1.0).contains(&s.point.x) && (0.0..=1.0).contains(&s.point.y));
        assert_eq!(s.point.z, 0.0);
        assert!((s.normal - DVec3::Z).length() < 1e-12);
        // (triangle 0 holds x ≥ y, triangle 1 x < y; each of area 1/2: pdf = 2·pmf)
        let t = (s.point.x < s.point.y) as usize;
        assert!((s.pdf - 2.0 * mesh.triangle_pmf(t)).abs() < 1e-12);
        second += t;
        let v = s.point.x * s.point.x / s.pdf;
        sum += v;
        sum2 += v * v;
    }
    let mean = sum / n as f64;
    let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
    assert!((mean - 1.0 / 3.0).abs() < 4.0 * se, "{mean} ± {se}");
    // (the 1 : 3 selection)
    let frac = second as f64 / n as f64;
    assert!((frac - 0.75).abs() < 0.005, "{frac}");
}

/// Emission sampling of the analytic shapes (`sample_area`) under rotations and non-uniform
/// scales: each point lies on the shape (its local equation), the normal is the world normal
/// of the emitting side there, and `1/pdf` is the world area (uniform densities: every
/// sample's, exactly) — rect 2 × 1 scaled (1.5, 0.5) → 1.5, disk r = 0.5 scaled (2, 1) → π/2,
/// sphere r = 0.5 scaled 2 → 4π, cylinder r = 0.5, length 1 scaled 2 → 4π.
#[test]
fn shape_area_samples_lie_on_the_surface_with_its_area() {
    let rot = DMat4::from_rotation_x(0.4) * DMat4::from_rotation_z(0.9);
    let xf = |s: DVec3| LightTransform::new(rot * DMat4::from_scale(s)).unwrap();
    let (rect_xf, disk_xf, round_xf) = (
        xf(DVec3::new(1.5, 0.5, 3.0)),
        xf(DVec3::new(2.0, 1.0, 1.0)),
        xf(DVec3::splat(2.0)),
    );
    let rect = RectLight::new(2.0, 1.0, rect_xf, RectTechnique::Area).unwrap();
    let disk = DiskLight::new(0.5, disk_xf, DiskTechnique::Area).unwrap();
    let sphere = SphereLight::new(0.5, round_xf, SphereTechnique::Area).unwrap();
    let cyl = CylinderLight::new(0.5, 1.0, round_xf, CylinderTechnique::Area).unwrap();
    let mut rng = SplitMix64::new(3);
    for _ in 0..2000 {
        let u = [rng.next_f64(), rng.next_f64()];
        for (name, s, t, area, local_n) in [
            ("rect", rect.sample_area(u), rect_xf, 1.5, None),
            ("disk", disk.sample_area(u), disk_xf, PI / 2.0, None),
            (
                "sphere",
                sphere.sample_area(u),
                round_xf,
                4.0 * PI,
                Some(1.0),
            ),
            (
                "cylinder",
                cyl.sample_area(u),
                round_xf,
                4.0 * PI,
                Some(0.0),
            ),
        ] {
            let s = s.expect("samples");
            assert!(
                (1.0 / s.pdf - area).abs() < 1e-9 * area,
                "{name}: {}",
                1.0 / s.pdf
            );
            let l = t.inv_point(s.point);
            let (on, nl) = match (name, local_n) {
                ("rect", _) => (l.z.abs() + (l.x.abs() > 1.0) as u8 as f64, DVec3::NEG_Z),
                ("disk", _) => (
                    l.z.abs() + (l.truncate().length() > 0.5) as u8 as f64,
                    DVec3::NEG_Z,
                ),
                (_, Some(1.0)) => (l.length() - 0.5, l),
                _ => (l.y.hypot(l.z) - 0.5, DVec3::new(0.0, l.y, l.z)),
            };
            assert!(on.abs() < 1e-9, "{name}: off the surface by {on}");
            assert!((s.normal - t.normal(nl)).length() < 1e-9, "{name}: normal");
        }
    }
}
