//! Exact penumbrae of sphere, rect and disk lights behind a few blockers.
//!
//! A light of uniform radiance L lights a Lambertian point with `L·Π_visible`, Π_visible the
//! projected solid angle of the part of the light its shadow rays reach. When every blocker
//! that can stop those rays is known and few (the point's patch of surface,
//! visibility/patches.rs), that part has a closed form: the light's Π less what the blockers
//! hide of it together (`lux_irradiance::hidden`: of a sphere's cap, a rect's parallelogram,
//! a disk, per convex polygon; their union by inclusion–exclusion where they overlap,
//! `lux_irradiance::overlap`), provided the blockers lie in front of the light (every ray through them meets
//! them before the light). A blocker is a triangle, a flat card's outline (`planar.rs`) or a
//! closed convex mesh's silhouette (`solid.rs`: a box, a faceted ball, however many
//! triangles). Then the penumbra is exact: no light sample, no shadow ray, no noise. (A
//! sphere drawn from its projected cap returns `L·Π` or nothing per sample, so its only noise
//! was the fraction of blocked samples; a rect's and a disk's samples add their samplers' own
//! noise.)

use super::solid::{MAX_SILHOUETTE, Solid};
use super::{FewTriangles, Shadows};
use crate::light::LightFrom;
use crate::material::SurfacePoint;
use glam::DVec3;
use lux_irradiance::hidden;
use lux_irradiance::overlap::{self, Poly};

/// The exact penumbra of the light `from` at the Lambertian point `sp` past the blockers `few`
/// (every triangle or solid that can stop its shadow rays: [`Shadows::blockers_in`] of a region
/// holding them; `room` the worker's buffers): the direction its BSDF is evaluated in (towards
/// the light's centre; a Lambertian f is the same everywhere) and the fraction of its closed
/// form ([`LightFrom::unshadowed`]) that passes. `None` (sample it instead) for other lights
/// and where [`sphere_visible`], [`rect_visible`] or [`disk_visible`] is.
pub fn visible(
    g: &Shadows,
    from: &LightFrom,
    sp: &SurfacePoint,
    few: &FewTriangles,
    room: &mut Room,
) -> Option<(DVec3, f64)> {
    if let Some(cap) = from.sphere_cap() {
        let pass = sphere_visible(g, sp, cap, few, room)?;
        return Some(((cap.0 - sp.p).normalize(), pass));
    }
    if let Some(corners) = from.rect_corners() {
        let pass = rect_visible(g, sp, &corners, few, room)?;
        let centre = 0.25 * corners.iter().sum::<DVec3>();
        return Some(((centre - sp.p).normalize(), pass));
    }
    let disk = from.world_disk()?;
    let pass = disk_visible(g, sp, disk, few, room)?;
    Some(((disk.0 - sp.p).normalize(), pass))
}

/// The fraction of a disk light's unshadowed integral (centre, unit normal, radius: `disk`) that
/// reaches the point `sp` past the blockers `few`: `1 − H / Π`, H what the blockers (triangles,
/// cards' outlines, solids' silhouettes: [`Seen::past`]) hide of it together
/// ([`hidden::disk_polygon`] of each, their overlaps once), Π the disk's projected solid angle
/// from `sp.p` with the shading normal; 0 within 10⁻¹² of all of it. `None` unless the disk
/// lies wholly above the horizon and every blocker that hides some of it lies wholly on the
/// point's side of the disk's plane. Its cone, for solids: the one holding its bounding
/// sphere.
pub fn disk_visible(
    g: &Shadows,
    sp: &SurfacePoint,
    disk: (DVec3, DVec3, f64),
    few: &FewTriangles,
    room: &mut Room,
) -> Option<f64> {
    let (centre, normal, radius) = disk;
    let pi = lux_irradiance::projected::disk(sp.p, sp.ns, centre, normal, radius)?;
    let side = normal.dot(sp.p - centre);
    if !(pi > 0.0 && side != 0.0) {
        return None;
    }
    let to = centre - sp.p;
    let dist = to.length();
    // (the disk wholly above the geometric horizon too: its rim's nearest point)
    let tilt = (sp.ng - sp.ng.dot(normal) * normal).length();
    Seen {
        pi,
        above: sp.ng.dot(to) > radius * tilt,
        cone: (dist > radius).then(|| {
            let sin = radius / dist;
            (to / dist, (1.0 - sin * sin).sqrt(), sin)
        }),
        hides: |tri: &[DVec3]| {
            let before = tri.iter().all(|v| normal.dot(*v - centre) * side > 0.0);
            Some((hidden::disk_polygon(sp.p, sp.ns, disk, tri)?, before))
        },
        before_ball: |c: DVec3, r: f64| normal.dot(c - centre) * side.signum() > r,
    }
    .past(g, sp, few, room)
}

/// The fraction of a rect light's unshadowed integral (over its world `corners`, a
/// parallelogram) that reaches the point `sp` past the blockers `few`: `1 − H / Π`, H what the
/// blockers ([`Seen::past`]) hide of it together ([`hidden::polygon_polygon`] of each, their overlaps
/// once), Π the rect's projected solid angle from `sp.p` with the shading normal, both clipped
/// to the horizon; 0 within 10⁻¹² of all of it. `None` unless Π > 0 and every blocker that
/// hides some of it lies wholly on the point's side of the light's plane (before the light
/// along every ray). Its cone, for solids: about the centre's direction, to the farthest
/// corner.
pub fn rect_visible(
    g: &Shadows,
    sp: &SurfacePoint,
    corners: &[DVec3; 4],
    few: &FewTriangles,
    room: &mut Room,
) -> Option<f64> {
    let pi = lux_irradiance::projected::polygon(sp.p, sp.ns, corners);
    let normal = (corners[1] - corners[0]).cross(corners[3] - corners[0]);
    let side = normal.dot(sp.p - corners[0]);
    if !(pi > 0.0 && side != 0.0) {
        return None;
    }
    // (its cone about the centre's direction, for solids)
    let cone = (!few.solids().is_empty())
        .then(|| {
            let axis = (0.25 * corners.iter().sum::<DVec3>() - sp.p).normalize();
            let cos = corners
                .iter()
                .map(|c| axis.dot((*c - sp.p).normalize()))
                .fold(1.0, f64::min);
            (cos > 0.0).then(|| (axis, cos, (1.0 - cos * cos).sqrt()))
        })
        .flatten();
    let unit = normal.normalize();
    Seen {
        pi,
        above: corners.iter().all(|c| sp.ng.dot(*c - sp.p) > 0.0),
        cone,
        hides: |tri: &[DVec3]| {
            let before = tri.iter().all(|v| normal.dot(*v - corners[0]) * side > 0.0);
            Some((hidden::polygon_polygon(sp.p, sp.ns, corners, tri), before))
        },
        before_ball: |c: DVec3, r: f64| unit.dot(c - corners[0]) * side.signum() > r,
    }
    .past(g, sp, few, room)
}

/// The fraction of a uniform sphere light's unshadowed integral that reaches the point `sp`
/// past the blockers `few` (every triangle or solid that can stop its shadow rays:
/// [`Shadows::blockers_in`] of a region holding them): `1 − H / Π` with H what the blockers
/// ([`Seen::past`]) hide of the cap together ([`hidden::cap_polygon`] of each, their overlaps once),
/// Π the cap's projected solid angle from `sp.p` with the shading normal (`pi`), the sphere of
/// world centre `centre` and radius `radius`; 0 within 10⁻¹² of the whole cap (the rounding
/// of the blockers' sum).
///
/// `None` (sample it instead) unless the cap lies wholly above both the shading and the
/// geometric horizon, every blocker that hides some of it lies on the point's side of the
/// plane through the sphere's nearest point (`(x − p)·a < D − R`, a the unit axis: before any
/// point of the sphere along every ray).
pub fn sphere_visible(
    g: &Shadows,
    sp: &SurfacePoint,
    (centre, radius, pi): (DVec3, f64, f64),
    few: &FewTriangles,
    room: &mut Room,
) -> Option<f64> {
    let to = centre - sp.p;
    let d = to.length();
    let axis = to / d;
    let sin_a = radius / d;
    if !(pi > 0.0 && sin_a < 1.0 && sp.ng.dot(axis) > sin_a) {
        return None;
    }
    let cos_a = (1.0 - sin_a * sin_a).sqrt();
    let near = d - radius;
    // (the cap lies above the shading normal's horizon: cap_polygon answers)
    Seen {
        pi,
        // (above both horizons, tested above)
        above: true,
        cone: Some((axis, cos_a, sin_a)),
        hides: |tri: &[DVec3]| {
            let before = tri.iter().all(|v| (*v - sp.p).dot(axis) < near);
            Some((hidden::cap_polygon(sp.p, sp.ns, axis, cos_a, tri)?, before))
        },
        before_ball: |c: DVec3, r: f64| (c - sp.p).dot(axis) + r < near,
    }
    .past(g, sp, few, room)
}

/// Most blockers that hide something at one point ([`Seen::past`]): more, and the light is sampled.
const MOST: usize = 8;

/// A worker's room for the exact penumbrae's polygons ([`visible`]), kept from point to point
/// so that none is cleared each time.
#[derive(Clone, Debug, Default)]
pub struct Room {
    /// The blockers as polygons seen from the point (and one slot more).
    polys: Vec<Poly>,
    /// What each hides.
    h: Vec<f64>,
    /// Intersections ([`overlap::union_hidden`]).
    bufs: Vec<Poly>,
    /// A solid's silhouette.
    rim: Vec<DVec3>,
    /// A clipping buffer.
    spare: Poly,
}

impl Room {
    /// Sized for [`Seen::past`] (once).
    fn ready(&mut self) {
        if self.polys.is_empty() {
            self.polys = vec![Poly::EMPTY; MOST + 1];
            self.h = vec![0.0; MOST];
            self.bufs = vec![Poly::EMPTY; 2 * overlap::MOST_DEEP];
            self.rim = vec![DVec3::ZERO; MAX_SILHOUETTE];
        }
    }
}

/// The blocker of world `corners` (made relative to `p` in place) as a polygon seen from `p`
/// into `out`, clipped to the light's pyramid when known (its planes `ω·k ≥ 0`; the one the
/// corners lie furthest outside of first: it leaves the fewest); `None` when a part has more
/// than [`overlap::POLY`] corners.
fn seen_from(
    r: &mut [DVec3],
    p: DVec3,
    pyramid: Option<&[DVec3; 4]>,
    out: &mut Poly,
    spare: &mut Poly,
) -> Option<()> {
    let mut mean = DVec3::ZERO;
    for r in r.iter_mut() {
        *r -= p;
        mean += *r;
    }
    let Some(planes) = pyramid else {
        *out = Poly::new(r)?;
        return Some(());
    };
    let first = (0..4)
        .min_by(|&a, &b| planes[a].dot(mean).total_cmp(&planes[b].dot(mean)))
        .unwrap_or(0);
    overlap::clip_into(r, planes[first], out)?;
    out.clip_all((0..4).filter(|&i| i != first).map(|i| planes[i]), spare)
}

/// The planes `ω·k ≥ 0` of the square pyramid about the cone `(axis, cos α, sin α)`
/// (cos α > 0): `|ω·u|, |ω·v| ≤ tan α (ω·axis)`, u, v ⟂ the axis. It holds the cone.
fn pyramid((axis, cos_a, sin_a): (DVec3, f64, f64)) -> [DVec3; 4] {
    let (u, v) = axis.any_orthonormal_pair();
    [
        axis * sin_a - u * cos_a,
        axis * sin_a + u * cos_a,
        axis * sin_a - v * cos_a,
        axis * sin_a + v * cos_a,
    ]
}

/// What the polygon `poly` seen from `p` hides (`hides` of a fan of pieces of up to
/// [`hidden::MAX_CORNERS`] corners, world points; they do not overlap) and whether every
/// piece lies before the light.
fn hidden_by(
    poly: &Poly,
    p: DVec3,
    hides: &impl Fn(&[DVec3]) -> Option<(f64, bool)>,
) -> Option<(f64, bool)> {
    const N: usize = hidden::MAX_CORNERS;
    let r = poly.corners();
    let (mut h, mut before) = (0.0, true);
    let mut i = 1;
    while i + 1 < r.len() {
        let end = (i + N - 2).min(r.len() - 1);
        let len = end - i + 2;
        let mut piece = [DVec3::ZERO; N];
        piece[0] = r[0] + p;
        for (x, r) in piece[1..len].iter_mut().zip(&r[i..=end]) {
            *x = *r + p;
        }
        i = end;
        let (hp, b) = hides(&piece[..len])?;
        h += hp;
        before &= b;
    }
    Some((h, before))
}

/// The solid's balls (`Solid::balls`) seen from `p` against the light's cone `(axis, cos α,
/// sin α)`: `Some(false)` when the outer ball's cone (half-angle β, `sin β = R/d`) misses it
/// (`θ > α + β`, θ the angle between the axes: nothing hidden), `Some(true)` when the inner
/// ball's cone (βᵢ) holds it (`θ + α ≤ βᵢ`) and that ball lies before the light (all of it
/// hidden), else `None` (and for `p` within the outer ball).
fn balls_against(
    solid: &Solid,
    p: DVec3,
    (axis, cos_a, sin_a): (DVec3, f64, f64),
    before_ball: &impl Fn(DVec3, f64) -> bool,
) -> Option<bool> {
    let (c, outer, inner) = solid.balls();
    let to = c - p;
    let dist = to.length();
    if dist.is_nan() || dist <= outer {
        return None;
    }
    let cos_t = axis.dot(to) / dist;
    let (sin_o, sin_i) = (outer / dist, inner / dist);
    let (cos_o, cos_i) = ((1.0 - sin_o * sin_o).sqrt(), (1.0 - sin_i * sin_i).sqrt());
    // (θ > α + β: cos θ < cos(α + β))
    if cos_t < cos_a * cos_o - sin_a * sin_o {
        return Some(false);
    }
    // (θ + α ≤ βᵢ: cos θ ≥ cos(βᵢ − α), βᵢ ≥ α)
    (sin_i >= sin_a && cos_t >= cos_i * cos_a + sin_i * sin_a && before_ball(c, inner))
        .then_some(true)
}

/// A light as [`Seen::past`] weighs blockers against it, seen from the point.
struct Seen<H, B> {
    /// Its projected solid angle Π.
    pi: f64,
    /// Whether it lies wholly above the point's geometric horizon.
    above: bool,
    /// A cone of directions holding it: unit axis, cosine and sine of the half-angle.
    cone: Option<(DVec3, f64, f64)>,
    /// What a blocking polygon (world corners) hides of it, and whether the polygon lies wholly
    /// before it along every ray; `None` where that has no closed form.
    hides: H,
    /// Whether the ball (centre, radius) lies wholly before it along every ray.
    before_ball: B,
}

impl<H: Fn(&[DVec3]) -> Option<(f64, bool)>, B: Fn(DVec3, f64) -> bool> Seen<H, B> {
    /// `1 − H / Π`, H what the blockers `few` hide together of the light seen from the point `sp`
    /// (`self`: what each hides, its cone), 0 within 10⁻¹² of all of Π (rounding: a quad's two
    /// triangles covering the light leave it black, as a hard shadow's samples do). `None` when a
    /// blocker that hides something is not wholly before the light, or where there is no closed
    /// form (`hides`, a silhouette, too many overlaps: [`overlap::union_hidden`]).
    ///
    /// Each blocker is a convex polygon seen from the point, clipped to the square pyramid about
    /// the light's cone (which holds the light, so nothing it leaves out hides any):
    /// - a closed convex mesh (`solid.rs`) is its silhouette, when the point lies outside it —
    ///   nothing when its bounding ball's cone misses the light's, all of the light when its
    ///   inner ball's cone holds the light's (and lies before it), nothing for the point's own
    ///   solid, which lies behind the plane of the point's face;
    /// - a flat card's triangles ([`Shadows::blocker_card`]) count as the whole outline, once: its
    ///   other triangles are not among `few` only where they stop no shadow ray of the patch, so
    ///   they hide nothing from the point. An outline not wholly before the light falls back to
    ///   its triangles;
    /// - any other triangle is itself.
    ///
    /// Where their projections overlap, what they hide together is their union's
    /// ([`overlap::union_hidden`]).
    fn past(
        self,
        g: &Shadows,
        sp: &SurfacePoint,
        few: &FewTriangles,
        room: &mut Room,
    ) -> Option<f64> {
        const N: usize = hidden::MAX_CORNERS;
        let p = sp.p;
        let Seen {
            pi,
            above,
            cone,
            hides,
            before_ball,
        } = self;
        let solids = few.solids();
        // (for solids)
        let pyramid = cone
            .filter(|c| c.1 > 0.0 && !solids.is_empty())
            .map(pyramid);
        let hidden_by = |poly: &Poly| hidden_by(poly, p, &hides);
        room.ready();
        let Room {
            polys,
            h: hs,
            bufs,
            rim,
            spare,
        } = room;
        // The blockers that hide something, as polygons seen from p: `polys[..k]` (the slot `k`
        // the next one's).
        let mut k = 0;
        // A solid's silhouette (world points) into slot k, clipped to the pyramid: what it hides,
        // and whether it lies before the light (nothing when it hides nothing).
        let mut take = |corners: &mut [DVec3], k: usize| -> Option<(f64, bool)> {
            let slot = &mut polys[k];
            seen_from(corners, p, pyramid.as_ref(), slot, spare)?;
            slot.tidy();
            if slot.is_empty() {
                return Some((0.0, true));
            }
            hidden_by(slot)
        };
        for &mesh in solids {
            let solid = g.solid(mesh)?;
            if mesh as usize == sp.mesh {
                // The point's own solid, seen from outside: wholly behind the plane of the
                // point's face, which the light lies wholly above.
                if above && solid.outward(sp.tri).is_some_and(|n| n.dot(sp.ng) > 0.0) {
                    continue;
                }
                return None;
            }
            match cone.map(|cone| balls_against(solid, p, cone, &before_ball)) {
                Some(Some(false)) => continue,
                Some(Some(true)) => return Some(0.0),
                _ => {}
            }
            let n = solid.silhouette(p, rim)?;
            let (h, before) = take(&mut rim[..n], k)?;
            if h == 0.0 {
                continue;
            }
            if !before || k == MOST {
                return None;
            }
            hs[k] = h;
            k += 1;
        }
        // A triangle or a card (world `corners`, up to N) hides what `hides` says, itself; into
        // slot k as a polygon seen from p where it hides something.
        let mut small = |corners: &[DVec3], k: usize| -> Option<(f64, bool)> {
            let (h, before) = hides(corners)?;
            if h != 0.0 && before && k < MOST {
                let mut r = [DVec3::ZERO; N];
                for (r, c) in r.iter_mut().zip(corners) {
                    *r = *c - p;
                }
                polys[k] = Poly::new(&r[..corners.len()])?;
            }
            Some((h, before))
        };
        // cards met: (mesh, whether its outline is used)
        let mut cards = [(u32::MAX, false); FewTriangles::CAP];
        let mut nc = 0;
        for &id in few.ids() {
            let card = g.blocker_card(id);
            let met = card.and_then(|(mesh, _)| cards[..nc].iter().find(|c| c.0 == mesh));
            // The card's outline the first time one of its triangles comes, when wholly before
            // the light; else the triangle itself.
            let h = match (card, met) {
                (Some(_), Some(&(_, true))) => continue,
                (Some((mesh, corners)), None) => {
                    let (h, before) = small(corners, k)?;
                    cards[nc] = (mesh, before);
                    nc += 1;
                    before.then_some(h)
                }
                _ => None,
            };
            let h = match h {
                Some(h) => h,
                None => {
                    let (h, before) = small(&g.blocker_vertices(id)?, k)?;
                    if h != 0.0 && !before {
                        return None;
                    }
                    h
                }
            };
            if h != 0.0 {
                if k == MOST {
                    return None;
                }
                hs[k] = h;
                k += 1;
            }
        }
        let hidden_sum = overlap::union_hidden(
            &polys[..k],
            &hs[..k],
            1e-12 * pi,
            &|poly| Some(hidden_by(poly)?.0),
            bufs,
        )?;
        let pass = 1.0 - hidden_sum / pi;
        Some(if pass < 1e-12 { 0.0 } else { pass.min(1.0) })
    }
}
