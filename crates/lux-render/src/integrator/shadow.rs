//! Shadow rays: what passes from a point towards a light, `ShadowAPI` and shadow linking
//! included.

use super::{Ctx, trace};
use crate::geometry::{Geometry, offset_scale};
use crate::light::{LightBase, MAX_PASS_THROUGH};
use crate::visibility::{ShadowHint, Visibility};
use crate::world::World;
use glam::DVec3;

/// Transmission of a shadow ray from `origin` along `dir` up to `tmax` towards the light
/// `l` (`ShadowAPI`): `None` when fully blocked, else the RGB multiplier (1 unoccluded;
/// `lux_math::shadowed` of the occluder's `shadow_strength` otherwise). Shadows disabled: no
/// ray is traced. Through surfaces with UsdPreviewSurface `opacity` the multiplier is
/// `T = ∏(1 − oᵢ)` (`trace.rs`); with `ShadowAPI` inputs, `T + (1 − T)·shadowed` where
/// `shadowed` is the ShadowAPI multiplier at the first surface of opacity > 0.
/// Occluders outside the light's `collection:shadowLink` cast no shadow
/// ([`first_shadow_occluder`]). Opaque plain shadows ask `vis` ([`Visibility::occluded`],
/// with what it knows of the ray, `hint`).
#[inline]
pub fn shadow_ray(
    world: &World,
    vis: &Visibility,
    l: &LightBase,
    (origin, dir, tmax): (DVec3, DVec3, f64),
    hint: &ShadowHint,
    ctx: &mut Ctx,
) -> Option<DVec3> {
    if !l.shadow.enable {
        return Some(DVec3::ONE);
    }
    let c = &mut ctx.counters;
    c.rays += 1;
    c.shadow += 1;
    if world.transparent {
        let (tr, first) = trace::transmission(world, origin, dir, tmax, |h| {
            l.casts_shadow(h.mesh, h.instance)
        });
        let Some(t) = first else {
            return Some(DVec3::ONE);
        };
        c.blocked += 1;
        if l.plain_shadows() {
            return (tr > 0.0).then_some(DVec3::splat(tr));
        }
        let sh = &l.shadow;
        let s = lux_math::shadow_strength(t, sh.distance, sh.falloff, sh.falloff_gamma);
        // What passes the surfaces, plus the ShadowAPI's light where they stop it.
        let tr = tr.clamp(0.0, 1.0);
        let m = DVec3::splat(tr) + (1.0 - tr) * lux_math::shadowed(s, sh.color);
        return (m != DVec3::ZERO).then_some(m);
    }
    if l.plain_shadows() {
        let blocked = vis.occluded(world.geometry, hint, origin, dir, tmax);
        c.blocked += blocked as u64;
        return (!blocked).then_some(DVec3::ONE);
    }
    // Shadow linking: occluders outside the light's shadowLink are passed through.
    let Some(t) = first_shadow_occluder(world.geometry, vis, l, origin, dir, tmax) else {
        return Some(DVec3::ONE);
    };
    c.blocked += 1;
    let sh = &l.shadow;
    let s = lux_math::shadow_strength(t, sh.distance, sh.falloff, sh.falloff_gamma);
    let m = lux_math::shadowed(s, sh.color);
    (m != DVec3::ZERO).then_some(m)
}

/// Distance to the first occluder on `origin + t·dir`, `t ∈ (0, tmax)`, that casts the
/// shadows of `l` in `g` as `vis` traces shadow rays: the first occluder without a
/// shadowLink; with one, occluders outside it are passed through (the ray cast again from
/// [`offset_scale`] past each, in order, deterministically); after [`MAX_PASS_THROUGH`] of
/// them the ray counts as blocked there.
#[inline]
pub fn first_shadow_occluder(
    g: &Geometry,
    vis: &Visibility,
    l: &LightBase,
    origin: DVec3,
    dir: DVec3,
    tmax: f64,
) -> Option<f64> {
    let Some(set) = &l.links.shadow else {
        return vis.first_occluder(g, origin, dir, 0.0, tmax);
    };
    let mut tmin = 0.0;
    for _ in 0..MAX_PASS_THROUGH {
        let o = vis.first_occluder_at(g, origin, dir, tmin, tmax)?;
        if set.contains(o.mesh, o.instance) {
            return Some(o.t);
        }
        tmin = o.t + offset_scale(origin + o.t * dir);
        if tmin >= tmax {
            return None;
        }
    }
    Some(tmin)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Geometry;
    use crate::light::GeomSet;
    use crate::light::linking_tests::{rules, tri};
    use crate::visibility::VisibilityMode;
    use lux_usd::{Rule, Scene};
    use std::sync::Arc;

    /// With either visibility: the first occluder without a shadowLink; with one, those
    /// outside it are passed through.
    #[test]
    fn shadow_rays_pass_through_unlinked_occluders() {
        let mut scene = Scene::empty("t.usda");
        scene.meshes = vec![tri("/a", 1.0), tri("/b", 2.0), tri("/c", 3.0)];
        let g = Geometry::new(&scene);
        for mode in [VisibilityMode::Exact, VisibilityMode::Rays] {
            let vis = Visibility::new(mode, &scene, &g);
            let mut l = LightBase::new(
                "/L",
                lux_sample::LightTransform::IDENTITY,
                lux_shaping::Shaping::identity(),
                lux_usd::ShadowInputs::default(),
            );
            let o = DVec3::new(0.0, 0.0, 0.0);
            let t =
                |l: &LightBase, tmax: f64| first_shadow_occluder(&g, &vis, l, o, DVec3::Y, tmax);
            assert!((t(&l, 10.0).unwrap() - 1.0).abs() < 1e-6);
            l.links.shadow = Some(Arc::new(GeomSet::new(
                &scene,
                &rules(&[("/c", Rule::ExpandPrims)]),
            )));
            assert!(l.links.shadow.is_some() && !l.plain_shadows());
            assert!((t(&l, 10.0).unwrap() - 3.0).abs() < 1e-6);
            assert_eq!(t(&l, 2.5), None);
            l.links.shadow = Some(Arc::new(GeomSet::new(&scene, &rules(&[]))));
            assert_eq!(t(&l, 10.0), None);
        }
    }
}
