//! `Strategy::HdEmbree` chosen per call: it is exactly the area technique of each shape (same
//! samples, same densities, bit for bit, so that one prepared light serves both strategies), and
//! the dome's hemisphere sampling around the receiver normal is uniform (χ²) with density 1/(2π).

mod common;

use common::*;
use glam::{DMat4, DVec3};
use lux_math::Frame;
use lux_sample::*;

fn references() -> Vec<Reference> {
    vec![
        Reference::point(DVec3::new(0.3, -0.2, -1.5)),
        Reference::surface(
            DVec3::new(0.1, 0.4, -0.7),
            DVec3::new(0.2, -0.1, 1.0).normalize(),
        ),
        Reference::surface(
            DVec3::new(2.5, 1.0, -0.2),
            DVec3::new(-1.0, 0.0, 0.3).normalize(),
        ),
        Reference::point(DVec3::new(-0.05, 0.02, -0.01)),
    ]
}

/// `light` sampled with `HdEmbree` against `area` (the same light prepared with the area
/// technique) sampled as prepared: identical samples and densities.
fn same_as_area(name: &str, light: &Light, area: &Light) {
    let mut rng = SplitMix64::new(17);
    let mut hits = 0;
    for r in references() {
        for _ in 0..4000 {
            let u = rng.next_2d();
            let a = light.sample_with(&r, u, Strategy::HdEmbree);
            let b = area.sample(&r, u);
            assert_eq!(a, b, "{name}: sample at {u:?} from {r:?}");
            if let Some(s) = a {
                hits += 1;
                assert_eq!(
                    light.pdf_with(&r, s.wi, Strategy::HdEmbree).to_bits(),
                    area.pdf(&r, s.wi).to_bits(),
                    "{name}: pdf"
                );
            }
            // The lux strategy is the prepared technique.
            assert_eq!(light.sample_with(&r, u, Strategy::Lux), light.sample(&r, u));
        }
    }
    assert!(hits > 1000, "{name}: {hits} samples");
}

#[test]
fn hdembree_is_the_area_technique_of_every_shape() {
    let m = LightTransform::new(
        DMat4::from_translation(DVec3::new(0.1, 0.0, 0.2))
            * DMat4::from_rotation_y(0.3)
            * DMat4::from_scale(DVec3::new(1.5, 0.8, 1.0)),
    )
    .unwrap();
    let rect = |t| Light::Rect(RectLight::new(1.2, 0.7, m, t).unwrap());
    same_as_area(
        "rect",
        &rect(RectTechnique::SphericalRectangleCosine),
        &rect(RectTechnique::Area),
    );
    let disk = |t| Light::Disk(DiskLight::new(0.6, m, t).unwrap());
    same_as_area(
        "disk",
        &disk(DiskTechnique::EllipticCone),
        &disk(DiskTechnique::Area),
    );
    let sphere = |t| Light::Sphere(SphereLight::new(0.4, m, t).unwrap());
    same_as_area(
        "sphere",
        &sphere(SphereTechnique::Cone),
        &sphere(SphereTechnique::Area),
    );
    // A world-space sphere (uniform scale): the cone takes its fast path, the area does not.
    let w = LightTransform::new(DMat4::from_translation(DVec3::new(0.0, 0.0, 0.5))).unwrap();
    let ws = |t| Light::Sphere(SphereLight::new(0.3, w, t).unwrap());
    same_as_area(
        "world sphere",
        &ws(SphereTechnique::Cone),
        &ws(SphereTechnique::Area),
    );
    let cyl = |t| Light::Cylinder(CylinderLight::new(0.2, 1.5, m, t).unwrap());
    same_as_area(
        "cylinder",
        &cyl(CylinderTechnique::SolidAngle),
        &cyl(CylinderTechnique::Area),
    );
    let p = vec![
        DVec3::new(-0.5, -0.5, 0.0),
        DVec3::new(0.5, -0.5, 0.0),
        DVec3::new(0.5, 0.5, 0.1),
        DVec3::new(-0.5, 0.5, -0.1),
    ];
    let i = vec![[0, 1, 2], [0, 2, 3]];
    let mesh = |t| Light::Mesh(MeshLight::new(&p, &i, None, true, t).unwrap());
    same_as_area(
        "mesh",
        &mesh(MeshTechnique::SphericalTriangle),
        &mesh(MeshTechnique::Area),
    );
    let distant = Light::Distant(DistantLight::new(5.0, &m).unwrap());
    same_as_area("distant", &distant, &distant);
}

#[test]
fn hdembree_dome_without_normal_is_the_uniform_dome() {
    let m = LightTransform::new(DMat4::from_rotation_x(0.7)).unwrap();
    let textured = Light::Dome(DomeLight::new(&sky(), m, DomeTechnique::Texture).unwrap());
    let uniform = Light::Dome(DomeLight::uniform(m));
    let mut rng = SplitMix64::new(3);
    let r = Reference::point(DVec3::new(1.0, 2.0, 3.0));
    for _ in 0..2000 {
        let u = rng.next_2d();
        let a = textured.sample_with(&r, u, Strategy::HdEmbree).unwrap();
        assert_eq!(Some(a), uniform.sample(&r, u));
        assert_eq!(
            textured.pdf_with(&r, a.wi, Strategy::HdEmbree).to_bits(),
            uniform.pdf(&r, a.wi).to_bits()
        );
    }
}

fn sky() -> LatLongMap {
    let (w, h) = (16, 8);
    let t = (0..w * h)
        .map(|k| if k % w < 3 && k / w < 3 { 50.0 } else { 0.5 })
        .collect();
    LatLongMap::new(w, h, t).unwrap()
}

/// Uniform over the hemisphere around `n`: χ² of (cos θ, φ) in 10 × 8 equal-solid-angle bins,
/// every density 1/(2π), nothing below the tangent plane; `pdf_with` is 1/(2π) above and 0
/// below it whatever the texture.
#[test]
fn hdembree_dome_is_uniform_over_the_receiver_hemisphere() {
    let light = Light::Dome(
        DomeLight::new(&sky(), LightTransform::IDENTITY, DomeTechnique::Texture).unwrap(),
    );
    let n = DVec3::new(0.3, 0.9, -0.2).normalize();
    let r = Reference::surface(DVec3::ZERO, n);
    let frame = Frame::from_normal(n);
    let (nt, np, count) = (10usize, 8usize, 80_000usize);
    let mut bins = vec![0usize; nt * np];
    let mut rng = SplitMix64::new(11);
    for _ in 0..count {
        let s = light
            .sample_with(&r, rng.next_2d(), Strategy::HdEmbree)
            .unwrap();
        assert_eq!(s.pdf, 0.5 * std::f64::consts::FRAC_1_PI);
        assert!(s.distance.is_infinite() && !s.delta);
        let l = frame.to_local(s.wi);
        assert!(l.z >= 0.0 && (s.wi.length() - 1.0).abs() < 1e-12);
        let it = ((l.z * nt as f64) as usize).min(nt - 1);
        let phi = l.y.atan2(l.x).rem_euclid(std::f64::consts::TAU);
        let ip = ((phi / std::f64::consts::TAU * np as f64) as usize).min(np - 1);
        bins[it * np + ip] += 1;
    }
    let e = count as f64 / (nt * np) as f64;
    let chi2: f64 = bins.iter().map(|&o| (o as f64 - e).powi(2) / e).sum();
    let p = chi2_p_value(chi2, nt * np - 1);
    assert!(p > ALPHA, "χ² {chi2}, p {p}");
    let up = frame.to_world(DVec3::new(0.6, 0.0, 0.8));
    let down = frame.to_world(DVec3::new(0.6, 0.0, -0.8));
    assert_eq!(
        light.pdf_with(&r, up, Strategy::HdEmbree),
        0.5 * std::f64::consts::FRAC_1_PI
    );
    assert_eq!(light.pdf_with(&r, down, Strategy::HdEmbree), 0.0);
}
