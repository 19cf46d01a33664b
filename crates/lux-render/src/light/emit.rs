//! Emission sampling (pbrt-v4's `Light::SampleLe`): a point on a light and a direction leaving
//! it, with the weight `Le·|cos θ| / (p_A · p_ω)` a particle carries — what a light tracer
//! starts from.
//!
//! - **Area lights** (rect, disk, sphere, cylinder, mesh): a point by area on the surface
//!   (lux-sample's `sample_area` of each shape: uniform in the light's local parameters, the
//!   density carried to the world through the transform's area scale), a direction cosine-distributed about the emitting side's normal
//!   (`p_ω = cos θ / π`), so the weight is `Le(ω)·π / p_A` with the light's own `Le`
//!   ([`Light::le`]: shaping, IES, texture and the emitting side included). A two-sided mesh
//!   light picks its side with probability ½.
//! - **Lights at infinity** (dome, distant): a direction by the light's own sampler from the
//!   centre of the scene's bounding sphere (radius `R`), and a point on the disk of radius `R`
//!   facing it beyond the scene, so the weight is `L·πR² / p_ω` (`E·πR²` for a delta distant
//!   light).

use super::{Light, Seen};
use glam::DVec3;
use lux_math::Frame;
use lux_sample::Reference;
use lux_sample::Strategy;
use lux_sample::warp::{sample_concentric_disk, sample_cosine_hemisphere};
use std::f64::consts::PI;

/// A particle leaving a light ([`Light::sample_le`]).
#[derive(Clone, Copy, Debug)]
pub struct LeSample {
    /// Where it starts (world; off a mesh light's surface by its ray offset).
    pub origin: DVec3,
    /// Its unit direction.
    pub dir: DVec3,
    /// Its weight `Le·|cos θ| / (p_A · p_ω)` (the light choice not included).
    pub weight: DVec3,
}

impl Light {
    /// A particle leaving the light with `u_pos`, `u_dir` ∈ \[0, 1)² (see the module's doc);
    /// `bounds`: the centre and radius of a sphere holding the scene (for lights at infinity).
    /// `None` when the sample carries nothing (outside a shaping cone, a degenerate point).
    pub fn sample_le(
        &self,
        u_pos: [f64; 2],
        u_dir: [f64; 2],
        bounds: (DVec3, f64),
    ) -> Option<LeSample> {
        let (area, two_sided) = match self {
            Light::Rect(l) => (l.sampler.sample_area(u_pos), false),
            Light::Disk(l) => (l.sampler.sample_area(u_pos), false),
            Light::Sphere(l) => (l.sampler.sample_area(u_pos), false),
            Light::Cylinder(l) => (l.sampler.sample_area(u_pos), false),
            Light::Mesh(l) => (l.sampler.sample_area(u_pos), l.sampler.two_sided()),
            Light::Distant(_) | Light::Dome(_) => {
                return self.sample_le_infinite(u_pos, u_dir, bounds);
            }
        };
        let area = area.filter(|a| a.pdf.is_finite() && a.pdf > 0.0)?;
        // (a two-sided surface: the side by u_dir[0], rescaled)
        let (n, u0, sides) = match two_sided {
            true if u_dir[0] < 0.5 => (area.normal, 2.0 * u_dir[0], 2.0),
            true => (-area.normal, 2.0 * u_dir[0] - 1.0, 2.0),
            false => (area.normal, u_dir[0], 1.0),
        };
        let dir = Frame::from_normal(n).to_world(sample_cosine_hemisphere([u0, u_dir[1]]));
        let le = self.le(self.base().to_local(area.point), dir, Seen::Lit);
        if le == DVec3::ZERO {
            return None;
        }
        let weight = le * (sides * PI / area.pdf);
        let origin = match self {
            Light::Mesh(_) => area.point + n * crate::geometry::offset_scale(area.point),
            _ => area.point,
        };
        weight.is_finite().then_some(LeSample {
            origin,
            dir,
            weight,
        })
    }

    /// [`Light::sample_le`] of a dome or distant light.
    fn sample_le_infinite(
        &self,
        u_pos: [f64; 2],
        u_dir: [f64; 2],
        (centre, radius): (DVec3, f64),
    ) -> Option<LeSample> {
        let ls = self.sample_li(&Reference::point(centre), u_dir, Strategy::Lux)?;
        if !(ls.pdf > 0.0 && radius > 0.0) || ls.l == DVec3::ZERO {
            return None;
        }
        let f = Frame::from_normal(ls.wi);
        let d = sample_concentric_disk(u_pos) * radius;
        let origin = centre + ls.wi * radius + f.t * d.x + f.b * d.y;
        let weight = ls.l * (PI * radius * radius / ls.pdf);
        weight.is_finite().then_some(LeSample {
            origin,
            dir: -ls.wi,
            weight,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::{LightOptions, LightSelection, LightSet};
    use glam::DMat4;
    use lux_math::LightShape;
    use lux_sample::SplitMix64;

    /// The light of `shape` placed by `xf`, default inputs (radiance 1, `normalize` off).
    fn light(shape: LightShape, xf: DMat4) -> Light {
        let mut s = lux_usd::Scene::empty("t.usda");
        s.lights
            .push(lux_usd::Light::with_defaults("/L", shape, xf));
        let options = LightOptions {
            profile: lux_math::Profile::Spec,
            selection: LightSelection::All,
            strict: true,
            cone_clipping: true,
        };
        let set = LightSet::new(&s, options).unwrap();
        set.lights.into_iter().next().unwrap()
    }

    /// A light sample's radiance is [`Light::le`] at its point towards the receiver, for
    /// every shape under a similarity (where rects, disks, spheres and cylinders of uniform
    /// radiance take it from a world side test) and under a shear and non-uniform scale
    /// (where they ask `le`), from receivers all around, with both strategies: bit for bit,
    /// away from the silhouette where the side test is a rounding error from 0.
    #[test]
    fn light_samples_carry_the_radiance_le_gives() {
        use lux_sample::{Reference, Strategy};
        let similar = DMat4::from_translation(DVec3::new(0.3, -0.2, 0.5))
            * DMat4::from_rotation_x(0.4)
            * DMat4::from_rotation_z(0.9)
            * DMat4::from_scale(DVec3::splat(1.7));
        let mut sheared = similar * DMat4::from_scale(DVec3::new(1.0, 2.0, 0.5));
        sheared.y_axis.x = 0.4;
        let shapes = [
            LightShape::Rect {
                width: 1.0,
                height: 2.0,
            },
            LightShape::Disk { radius: 0.7 },
            LightShape::Sphere { radius: 0.6 },
            LightShape::Cylinder {
                radius: 0.5,
                length: 1.5,
            },
        ];
        let mut rng = SplitMix64::new(11);
        let (mut checked, mut lit) = (0, 0);
        for shape in shapes {
            for xf in [similar, sheared] {
                let l = light(shape.clone(), xf);
                for _ in 0..400 {
                    let p = DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) * 8.0
                        - DVec3::splat(4.0);
                    let n = DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) - 0.5;
                    let r = Reference::surface(p, n.normalize());
                    for strategy in [Strategy::Lux, Strategy::HdEmbree] {
                        let u = [rng.next_f64(), rng.next_f64()];
                        let Some(s) = l.sample_li(&r, u, strategy) else {
                            continue;
                        };
                        let local = l.base().to_local(s.point);
                        let wl = l.base().local_direction(-s.wi).unwrap();
                        let side = match shape {
                            LightShape::Rect { .. } | LightShape::Disk { .. } => -wl.z,
                            LightShape::Sphere { .. } => local.normalize().dot(wl),
                            _ => DVec3::new(0.0, local.y, local.z).normalize().dot(wl),
                        };
                        if side.abs() < 1e-9 {
                            continue;
                        }
                        assert_eq!(
                            s.l,
                            l.le(local, -s.wi, Seen::Lit),
                            "{shape:?} {strategy:?} from {p}"
                        );
                        checked += 1;
                        lit += (s.l != DVec3::ZERO) as u32;
                    }
                }
            }
        }
        // (most samples count, both sides among them)
        assert!(
            checked > 4000 && lit > 1000 && lit < checked,
            "{checked} {lit}"
        );
    }

    /// A particle's expected weight is the light's emitted flux `L·π·A` (radiance 1; `A` its
    /// world area under rotations and non-uniform scales, both sides of nothing) — here every
    /// sample's weight is, since each density is uniform — its point lies on the surface, and
    /// its direction leaves the emitting side. A uniform dome's particles carry
    /// `4π·πR²` through the scene's disk.
    #[test]
    fn particles_carry_the_emitted_flux() {
        use std::f64::consts::PI;
        let rot = DMat4::from_rotation_x(0.4) * DMat4::from_rotation_z(0.9);
        let cases = [
            (
                LightShape::Rect {
                    width: 2.0,
                    height: 1.0,
                },
                rot * DMat4::from_scale(DVec3::new(1.5, 0.5, 3.0)),
                PI * 1.5,
            ),
            (
                LightShape::Disk { radius: 0.5 },
                rot * DMat4::from_scale(DVec3::new(2.0, 1.0, 1.0)),
                PI * PI * 0.5,
            ),
            (
                LightShape::Sphere { radius: 0.5 },
                rot * DMat4::from_scale(DVec3::splat(2.0)),
                PI * 4.0 * PI,
            ),
            (
                LightShape::Cylinder {
                    radius: 0.5,
                    length: 1.0,
                },
                rot * DMat4::from_scale(DVec3::splat(2.0)),
                PI * 4.0 * PI,
            ),
        ];
        let bounds = (DVec3::new(0.5, 0.0, -1.0), 3.0);
        let mut rng = SplitMix64::new(5);
        let mut u2 = || [rng.next_f64(), rng.next_f64()];
        for (shape, xf, flux) in cases {
            let l = light(shape.clone(), xf);
            for _ in 0..2000 {
                let s = l.sample_le(u2(), u2(), bounds).expect("emits");
                assert!(
                    (s.weight.x - flux).abs() < 1e-9 * flux,
                    "{shape:?}: {}",
                    s.weight.x
                );
                // on the surface, leaving it on the emitting side
                let local = l.base().to_local(s.origin);
                let on = match shape {
                    LightShape::Rect { .. } | LightShape::Disk { .. } => local.z.abs(),
                    LightShape::Sphere { radius } => local.length() - radius,
                    LightShape::Cylinder { radius, .. } => local.y.hypot(local.z) - radius,
                    _ => unreachable!(),
                };
                assert!(on.abs() < 1e-9, "{shape:?}: {on}");
                assert_ne!(l.le(local, s.dir, Seen::Lit), DVec3::ZERO, "{shape:?}");
            }
        }
        let dome = light(LightShape::Dome, DMat4::IDENTITY);
        let mut mean = 0.0;
        for _ in 0..2000 {
            let s = dome.sample_le(u2(), u2(), bounds).expect("emits");
            // (entering the scene's sphere from its disk)
            assert!((s.origin - bounds.0).length() <= 3.0 * 2f64.sqrt() + 1e-9);
            assert!((s.origin - bounds.0).dot(s.dir) < 0.0);
            mean += s.weight.x / 2000.0;
        }
        let want = 4.0 * PI * PI * 9.0;
        assert!((mean - want).abs() < 1e-9 * want, "{mean} vs {want}");
    }
}
