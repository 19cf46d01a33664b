//! Rays through UsdPreviewSurface `opacity`: what a ray stops at when some surfaces let light
//! through (partial opacity or an `opacityThreshold` cut-out, [`Materials::opacity`]).
//!
//! - A camera or BSDF ray stops at a surface of opacity `o` with probability `o` (a cut-out:
//!   0 or 1), decided by a hash of the hit so the image does not depend on threads; it
//!   passes otherwise (no refraction: `opacity` is presence, as Hydra Storm blends it).
//! - A shadow ray is attenuated by `∏(1 − oᵢ)` over the surfaces it crosses (exact, no noise).
//!
//! Scenes without such surfaces take one BVH query, as before.
//!
//! [`Materials::opacity`]: crate::material::Materials::opacity

use crate::geometry::Hit;
use crate::world::World;
use glam::DVec3;
use lux_sample::SplitMix64;

/// Most surfaces a ray passes through before it is treated as stopped.
const MAX_LAYERS: usize = 64;

/// A uniform number in \[0, 1) from a hit point and direction (deterministic stochastic
/// opacity): lux-sample's SplitMix64 chained over the coordinates' bits.
fn hash01(p: DVec3, d: DVec3) -> f64 {
    let mut h = 0;
    for x in [p.x, p.y, p.z, d.x, d.y, d.z] {
        h = SplitMix64::new(h ^ x.to_bits()).next_u64();
    }
    SplitMix64::new(h).next_f64()
}

/// The origin just past `h` along `d` (its `f32` clearance on the far side).
#[inline]
fn past(h: &Hit, d: DVec3) -> DVec3 {
    let n = if h.ng.dot(d) > 0.0 { h.ng } else { -h.ng };
    h.p + n * h.offset
}

/// The closest surface that stops a ray from `o` along unit `d` in `[tmin, tmax]` (`t` from
/// `o`); `any_side`: back faces of single-sided meshes too (BSDF rays), else culled as
/// camera rays are.
#[inline]
pub fn closest(w: &World, o: DVec3, d: DVec3, tmin: f64, tmax: f64, any_side: bool) -> Option<Hit> {
    let query = |o: DVec3, tmin: f64, tmax: f64| {
        if any_side {
            w.geometry.intersect_any_side(w.scene, o, d, tmin, tmax)
        } else {
            w.geometry.intersect(w.scene, o, d, tmin, tmax)
        }
    };
    if !w.transparent {
        return query(o, tmin, tmax);
    }
    let (mut origin, mut t0, mut lo) = (o, 0.0, tmin);
    for _ in 0..MAX_LAYERS {
        let mut h = query(origin, lo, tmax - t0)?;
        let op = w.materials.opacity(w.scene, &h);
        if op >= 1.0 || (op > 0.0 && hash01(h.p, d) < op) {
            h.t += t0;
            return Some(h);
        }
        t0 += h.t;
        origin = past(&h, d);
        lo = 0.0;
    }
    None
}

/// The fraction of light that passes from `o` along unit `d` up to `tmax` through the
/// surfaces in between: `∏(1 − oᵢ)` (0 at the first opaque one), with the distance of the
/// first surface that stops any of it. Surfaces for which `casts` is false (outside a
/// light's `shadowLink`) are passed through.
pub fn transmission(
    w: &World,
    o: DVec3,
    d: DVec3,
    tmax: f64,
    casts: impl Fn(&Hit) -> bool,
) -> (f64, Option<f64>) {
    let (mut origin, mut t0, mut tr) = (o, 0.0, 1.0);
    let mut first = None;
    for _ in 0..MAX_LAYERS {
        let Some(h) = w
            .geometry
            .intersect_any_side(w.scene, origin, d, 0.0, tmax - t0)
        else {
            return (tr, first);
        };
        let op = if casts(&h) {
            w.materials.opacity(w.scene, &h)
        } else {
            0.0
        };
        if op > 0.0 && first.is_none() {
            first = Some(t0 + h.t);
        }
        tr *= 1.0 - op;
        if tr <= 0.0 {
            return (0.0, first);
        }
        t0 += h.t;
        origin = past(&h, d);
    }
    (0.0, first)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hash is uniform enough for presence: its mean and a 10-bin histogram.
    #[test]
    fn hash_is_uniform() {
        let n = 100_000;
        let mut bins = [0u32; 10];
        let mut sum = 0.0;
        for i in 0..n {
            let p = DVec3::new(i as f64 * 0.37, (i % 97) as f64, 1.0 / (i + 1) as f64);
            let u = hash01(p, DVec3::Y);
            assert!((0.0..1.0).contains(&u));
            sum += u;
            bins[(u * 10.0) as usize] += 1;
        }
        assert!((sum / n as f64 - 0.5).abs() < 0.005);
        for b in bins {
            assert!((b as f64 - 10_000.0).abs() < 500.0, "{bins:?}");
        }
    }
}
