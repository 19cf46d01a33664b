//! Emission-cone clipping (`with_emission_cone`) of the rect and cylinder samplers: the clipped
//! samplers are χ²-consistent with their own `pdf`, and they integrate any emission confined to
//! the cone to the same value as the unclipped samplers (nothing inside the cone is missed),
//! with a lower variance.

mod common;

use common::*;
use glam::{DMat4, DVec3};
use lux_sample::*;

const N: usize = 200_000;
/// Quadrature points over the light's surface: many, since a narrow cone keeps only a small
/// part of it (the χ² expectation must be accurate there).
const G: usize = 8_000_000;

/// Whether the emission direction of a sample (from the light towards the receiver, in the
/// light's local frame) lies within `cut` of the light's −Z axis.
fn in_cone(m: &LightTransform, s: &LightSample, cut: f64) -> bool {
    let d = m.inv_vector(-s.wi).normalize();
    -d.z >= cut.cos()
}

/// Mean and standard error of `1{in cone}·max(0, n·wi)/pdf` (the irradiance of a unit-radiance
/// light whose shaping is a hard cone), failed samples counting 0.
fn coned_irradiance(
    light: &Light,
    m: &LightTransform,
    r: &Reference,
    cut: f64,
    seed: u64,
) -> (f64, f64) {
    let mut rng = SplitMix64::new(seed);
    let (mut s, mut s2) = (0.0, 0.0);
    for _ in 0..N {
        let v = light.sample(r, rng.next_2d()).map_or(0.0, |ls| {
            if in_cone(m, &ls, cut) {
                r.n.dot(ls.wi).max(0.0) / ls.pdf
            } else {
                0.0
            }
        });
        s += v;
        s2 += v * v;
    }
    let mean = s / N as f64;
    (
        mean,
        ((s2 / N as f64 - mean * mean).max(0.0) / N as f64).sqrt(),
    )
}

fn receivers(m: &LightTransform) -> Vec<(&'static str, Reference)> {
    [
        ("below", DVec3::new(0.1, -0.05, -1.0), DVec3::Z),
        (
            "beside",
            DVec3::new(0.9, 0.4, -0.6),
            DVec3::new(-0.3, 0.0, 1.0),
        ),
        (
            "near",
            DVec3::new(-0.2, 0.1, -0.25),
            DVec3::new(0.2, 0.1, 1.0),
        ),
        (
            "far",
            DVec3::new(2.0, -1.5, -4.0),
            DVec3::new(0.0, 0.3, 1.0),
        ),
    ]
    .into_iter()
    .map(|(n, p, nn)| (n, Reference::surface(m.point(p), m.vector(nn).normalize())))
    .collect()
}

#[test]
fn clipped_rect_is_consistent_and_unbiased() {
    for cut_deg in [10.0f64, 45.0] {
        let cut = cut_deg.to_radians();
        for (w, h, mm) in [(1.0, 0.6, DMat4::IDENTITY), (1.0, 0.7, skewed(DVec3::ZERO))] {
            let m = xf(mm);
            for t in [
                RectTechnique::SphericalRectangle,
                RectTechnique::SphericalRectangleCosine,
            ] {
                let full = Light::Rect(RectLight::new(w, h, m, t).unwrap());
                let clipped =
                    Light::Rect(RectLight::new(w, h, m, t).unwrap().with_emission_cone(cut));
                for (name, r) in receivers(&m) {
                    let name = format!("rect {t:?} cone {cut_deg}° {name} {mm:?}");
                    let (a, sa) = coned_irradiance(&full, &m, &r, cut, 1);
                    let (b, sb) = coned_irradiance(&clipped, &m, &r, cut, 2);
                    assert!(
                        (a - b).abs() <= 4.5 * (sa * sa + sb * sb).sqrt() + 1e-12,
                        "{name}: unclipped {a} ± {sa}, clipped {b} ± {sb}"
                    );
                    assert!(
                        sb <= sa * 1.05 + 1e-15,
                        "{name}: clipping raised the noise ({sb} vs {sa})"
                    );
                    if clipped.sample(&r, [0.5, 0.5]).is_some() {
                        let centre = m.point(DVec3::ZERO);
                        let cap = Cap::around(r.p, centre, 1.5, 40, 80);
                        let e = expected_surface(&cap, r.p, G, &rect_surface(w, h, m), &|d| {
                            clipped.pdf(&r, d)
                        });
                        check_light(&name, &clipped, &r, cap, N / 4, &e);
                    }
                }
            }
        }
    }
}

#[test]
fn clipped_cylinder_is_consistent_and_unbiased() {
    for cut_deg in [10.0f64, 45.0] {
        let cut = cut_deg.to_radians();
        for mm in [
            DMat4::IDENTITY,
            DMat4::from_rotation_x(std::f64::consts::FRAC_PI_4),
        ] {
            let m = xf(mm);
            let full = Light::Cylinder(
                CylinderLight::new(0.3, 1.5, m, CylinderTechnique::SolidAngle).unwrap(),
            );
            let clipped = Light::Cylinder(
                CylinderLight::new(0.3, 1.5, m, CylinderTechnique::SolidAngle)
                    .unwrap()
                    .with_emission_cone(cut),
            );
            for (name, r) in receivers(&m) {
                let name = format!("cylinder cone {cut_deg}° {name} {mm:?}");
                let (a, sa) = coned_irradiance(&full, &m, &r, cut, 3);
                let (b, sb) = coned_irradiance(&clipped, &m, &r, cut, 4);
                assert!(
                    (a - b).abs() <= 4.5 * (sa * sa + sb * sb).sqrt() + 1e-12,
                    "{name}: unclipped {a} ± {sa}, clipped {b} ± {sb}"
                );
                // Only samples that can succeed are drawn, so the clipped sampler succeeds at
                // least as often; its density stays consistent with its samples.
                let ok = (0..1000)
                    .filter(|i| clipped.sample(&r, r2(*i).into()).is_some())
                    .count();
                if ok > 200 {
                    let cap = Cap::around(r.p, m.point(DVec3::ZERO), 2.0, 40, 80);
                    let e =
                        expected_surface(&cap, r.p, G, &cylinder_surface(0.3, 1.5, m, r.p), &|d| {
                            clipped.pdf(&r, d)
                        });
                    check_light(&name, &clipped, &r, cap, N / 4, &e);
                }
            }
        }
    }
}
