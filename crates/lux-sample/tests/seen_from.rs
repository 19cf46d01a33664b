//! `seen_from`: a rect, disk, sphere or cylinder light seen from one receiver (the setup its samples
//! share, done once for the k light samples of a shading point) samples exactly as
//! `sample_with` from that receiver, bit for bit, for every technique and both strategies,
//! and whichever of its samples is drawn first.

use glam::{DMat4, DVec3};
use lux_sample::*;

/// Receivers in front of, behind, far from, inside and beside the lights below (with and
/// without a normal, so that the cosine-aware techniques and their fallbacks all run).
fn receivers() -> Vec<Reference> {
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
        // far away: the solid angle falls below MIN_SOLID_ANGLE
        Reference::surface(DVec3::new(0.0, 0.0, -400.0), DVec3::Z),
        // behind the planar lights, inside the spheres
        Reference::surface(DVec3::new(0.05, 0.0, 0.1), DVec3::NEG_Z),
        Reference::point(DVec3::new(-0.05, 0.02, -0.01)),
        // a cap cut by the receiver's horizon
        Reference::surface(
            DVec3::new(0.9, 0.0, -0.1),
            DVec3::new(1.0, 0.0, -0.2).normalize(),
        ),
    ]
}

fn us() -> Vec<[f64; 2]> {
    let mut rng = SplitMix64::new(5);
    let mut u: Vec<[f64; 2]> = (0..64).map(|_| rng.next_2d()).collect();
    u.extend([[0.0, 0.0], [0.999_999, 0.5], [0.5, 0.999_999]]);
    u
}

/// `sample(from, u)` equals `sample_with(r, u, strategy)` for every receiver and `u`, the
/// samples drawn from one view in reverse order.
fn check<F>(
    name: &str,
    sample_with: impl Fn(&Reference, [f64; 2], Strategy) -> Option<LightSample>,
    view: F,
) where
    F: Fn(&Reference, Strategy, &mut dyn FnMut(&dyn Fn([f64; 2]) -> Option<LightSample>)),
{
    let mut some = 0;
    for strategy in [Strategy::Lux, Strategy::HdEmbree] {
        for r in receivers() {
            let want: Vec<Option<LightSample>> =
                us().iter().map(|&u| sample_with(&r, u, strategy)).collect();
            view(&r, strategy, &mut |sample| {
                for (u, w) in us().iter().zip(&want).rev() {
                    assert_eq!(sample(*u), *w, "{name} {strategy:?} from {r:?} at {u:?}");
                }
            });
            some += want.iter().flatten().count();
        }
    }
    assert!(some > 200, "{name}: {some} samples");
}

#[test]
fn seen_from_samples_as_sample_with() {
    let m = LightTransform::new(
        DMat4::from_translation(DVec3::new(0.1, 0.0, 0.2))
            * DMat4::from_rotation_y(0.3)
            * DMat4::from_scale(DVec3::new(1.5, 0.8, 1.0)),
    )
    .unwrap();
    let world = LightTransform::new(
        DMat4::from_translation(DVec3::new(0.0, 0.1, 0.5)) * DMat4::from_rotation_x(0.4),
    )
    .unwrap();
    for xf in [m, world] {
        for t in [
            RectTechnique::Area,
            RectTechnique::SphericalRectangle,
            RectTechnique::SphericalRectangleCosine,
        ] {
            for cone in [core::f64::consts::PI, 0.6] {
                let l = RectLight::new(1.2, 0.7, xf, t)
                    .unwrap()
                    .with_emission_cone(cone);
                check(
                    &format!("rect {t:?} cone {cone}"),
                    |r, u, s| l.sample_with(r, u, s),
                    |r, s, f| l.seen_from(r, s, |from| f(&|u| from.sample(u))),
                );
            }
        }
        for t in [
            DiskTechnique::Area,
            DiskTechnique::PolarChord,
            DiskTechnique::EllipticCone,
        ] {
            let l = DiskLight::new(0.6, xf, t).unwrap();
            check(
                &format!("disk {t:?}"),
                |r, u, s| l.sample_with(r, u, s),
                |r, s, f| l.seen_from(r, s, |from| f(&|u| from.sample(u))),
            );
        }
        for t in [
            CylinderTechnique::Area,
            CylinderTechnique::VisibleArea,
            CylinderTechnique::SolidAngle,
        ] {
            for cone in [core::f64::consts::PI, 0.6] {
                let l = CylinderLight::new(0.2, 1.5, xf, t)
                    .unwrap()
                    .with_emission_cone(cone);
                check(
                    &format!("cylinder {t:?} cone {cone}"),
                    |r, u, s| l.sample_with(r, u, s),
                    |r, s, f| l.seen_from(r, s, |from| f(&|u| from.sample(u))),
                );
            }
        }
        for t in [
            SphereTechnique::Area,
            SphereTechnique::Cone,
            SphereTechnique::ProjectedCap,
        ] {
            let l = SphereLight::new(0.4, xf, t).unwrap();
            check(
                &format!("sphere {t:?}"),
                |r, u, s| l.sample_with(r, u, s),
                |r, s, f| l.seen_from(r, s, |from| f(&|u| from.sample(u))),
            );
        }
    }
}
