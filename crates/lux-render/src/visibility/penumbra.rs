//! Exact penumbrae of sphere, rect and disk lights behind a few triangles.
//!
//! A light of uniform radiance L lights a Lambertian point with `L·Π_visible`, Π_visible the
//! projected solid angle of the part of the light its shadow rays reach. When every triangle
//! that can block those rays is known and few (the point's patch of surface,
//! visibility/patches.rs), that part has a closed form: the light's Π less what each triangle
//! hides of it (`lux_irradiance::hidden`: of a sphere's cap, a rect's parallelogram, a disk), provided
//! the triangles lie in front of the light (every ray through them meets them before the
//! light) and their projections do not overlap (nothing hidden twice). Then the penumbra is
//! exact: no light sample, no shadow ray, no noise. (A sphere drawn from its projected cap
//! returns `L·Π` or nothing per sample, so its only noise was the fraction of blocked samples;
//! a rect's and a disk's samples add their samplers' own noise.)

use super::{FewTriangles, Shadows};
use crate::light::LightFrom;
use crate::material::SurfacePoint;
use glam::DVec3;
use lux_irradiance::hidden;

/// The exact penumbra of the light `from` at the Lambertian point `sp` past the triangles `few`
/// (every triangle that can stop its shadow rays: [`Shadows::blockers_in`] of a region holding
/// them): the direction its BSDF is evaluated in (towards the light's centre; a Lambertian f is
/// the same everywhere) and the fraction of its closed form ([`LightFrom::unshadowed`]) that
/// passes. `None` (sample it instead) for other lights and where [`sphere_visible`],
/// [`rect_visible`] or [`disk_visible`] is.
pub fn visible(
    g: &Shadows,
    from: &LightFrom,
    sp: &SurfacePoint,
    few: &FewTriangles,
) -> Option<(DVec3, f64)> {
    if let Some(cap) = from.sphere_cap() {
        let pass = sphere_visible(g, sp, cap, few)?;
        return Some(((cap.0 - sp.p).normalize(), pass));
    }
    if let Some(corners) = from.rect_corners() {
        let pass = rect_visible(g, sp, &corners, few)?;
        let centre = 0.25 * corners.iter().sum::<DVec3>();
        return Some(((centre - sp.p).normalize(), pass));
    }
    let disk = from.world_disk()?;
    let pass = disk_visible(g, sp, disk, few)?;
    Some(((disk.0 - sp.p).normalize(), pass))
}

/// The fraction of a disk light's unshadowed integral (centre, unit normal, radius: `disk`) that
/// reaches the point `sp` past the triangles `few`: `1 − Σ Hᵢ / Π`, Hᵢ what blocker i (a
/// triangle or a card's outline: [`past`]) hides of it ([`hidden::disk_polygon`]), Π the disk's
/// projected solid angle from `sp.p` with the shading normal; 0 within 10⁻¹² of all of it.
/// `None` unless the disk lies wholly above the horizon, every blocker that hides some of it
/// lies wholly on the point's side of the disk's plane, and no two of them overlap as seen from
/// the point ([`hidden::apart`]).
pub fn disk_visible(
    g: &Shadows,
    sp: &SurfacePoint,
    disk: (DVec3, DVec3, f64),
    few: &FewTriangles,
) -> Option<f64> {
    let (centre, normal, radius) = disk;
    let pi = lux_irradiance::projected::disk(sp.p, sp.ns, centre, normal, radius)?;
    let side = normal.dot(sp.p - centre);
    if !(pi > 0.0 && side != 0.0) {
        return None;
    }
    past(g, sp.p, few, pi, |tri| {
        let before = tri.iter().all(|v| normal.dot(*v - centre) * side > 0.0);
        Some((hidden::disk_polygon(sp.p, sp.ns, disk, tri)?, before))
    })
}

/// The fraction of a rect light's unshadowed integral (over its world `corners`, a
/// parallelogram) that reaches the point `sp` past the triangles `few`: `1 − Σ Hᵢ / Π`, Hᵢ what
/// blocker i (a triangle or a card's outline: [`past`]) hides of it
/// ([`hidden::polygon_polygon`]), Π the rect's projected solid angle
/// from `sp.p` with the shading normal, both clipped to the horizon; 0 within 10⁻¹² of all of
/// it. `None` unless Π > 0, every blocker that hides some of it lies wholly on the point's side
/// of the light's plane (before the light along every ray), and no two of them overlap as seen
/// from the point ([`hidden::apart`]).
pub fn rect_visible(
    g: &Shadows,
    sp: &SurfacePoint,
    corners: &[DVec3; 4],
    few: &FewTriangles,
) -> Option<f64> {
    let pi = lux_irradiance::projected::polygon(sp.p, sp.ns, corners);
    let normal = (corners[1] - corners[0]).cross(corners[3] - corners[0]);
    let side = normal.dot(sp.p - corners[0]);
    if !(pi > 0.0 && side != 0.0) {
        return None;
    }
    past(g, sp.p, few, pi, |tri| {
        let before = tri.iter().all(|v| normal.dot(*v - corners[0]) * side > 0.0);
        Some((hidden::polygon_polygon(sp.p, sp.ns, corners, tri), before))
    })
}

/// The fraction of a uniform sphere light's unshadowed integral that reaches the point `sp`
/// past the triangles `few` (every triangle that can stop its shadow rays:
/// [`Shadows::blockers_in`] of a region holding them): `1 − Σ Hᵢ / Π` with Hᵢ what blocker i (a
/// triangle or a card's outline: [`past`]) hides of the cap ([`hidden::cap_polygon`]), Π the
/// cap's projected solid angle from `sp.p`
/// with the shading normal (`pi`), the sphere of world centre `centre` and radius `radius`;
/// 0 within 10⁻¹² of the whole cap (the rounding of the triangles' sum).
///
/// `None` (sample it instead) unless the cap lies wholly above both the shading and the
/// geometric horizon, every blocker that hides some of it lies on the point's side of the
/// plane through the sphere's nearest point (`(x − p)·a < D − R`, a the unit axis: before any
/// point of the sphere along every ray), and no two of them overlap as seen from the point
/// ([`hidden::apart`]).
pub fn sphere_visible(
    g: &Shadows,
    sp: &SurfacePoint,
    (centre, radius, pi): (DVec3, f64, f64),
    few: &FewTriangles,
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
    past(g, sp.p, few, pi, |tri| {
        let before = tri.iter().all(|v| (*v - sp.p).dot(axis) < near);
        Some((hidden::cap_polygon(sp.p, sp.ns, axis, cos_a, tri)?, before))
    })
}

/// `1 − Σ Hᵢ / Π` over the triangles `few` seen from `p`, `hides` giving each one's Hᵢ (what it
/// hides of the light, 0 for nothing) and whether it lies wholly before the light, or nothing
/// where it has no closed form; 0 within
/// 10⁻¹² of all of Π (the rounding of the triangles' sum: a quad's two triangles covering the
/// light leave it black, as a hard shadow's samples do). `None` when a triangle that hides
/// something is not before the light, when two such overlap as seen from `p`
/// ([`hidden::apart`]), or when `hides` has no answer.
///
/// Triangles of a flat card's outline ([`Geometry::blocker_card`]) count as the whole outline,
/// once: its other triangles are not among `few` only where they stop no shadow ray of the
/// patch, so they hide nothing from `p` and the outline hides what its triangles in `few` do,
/// in one convex polygon rather than several triangles and the test that they do not overlap.
/// An outline not wholly before the light falls back to its triangles.
fn past(
    g: &Shadows,
    p: DVec3,
    few: &FewTriangles,
    pi: f64,
    hides: impl Fn(&[DVec3]) -> Option<(f64, bool)>,
) -> Option<f64> {
    const N: usize = hidden::MAX_CORNERS;
    let mut hiding = [([DVec3::ZERO; N], 0); FewTriangles::CAP];
    let mut k = 0;
    let mut hidden_sum = 0.0;
    // cards met: (mesh, whether its outline is used)
    let mut cards = [(u32::MAX, false); FewTriangles::CAP];
    let mut nc = 0;
    for &id in few.ids() {
        let mut shape = [DVec3::ZERO; N];
        let mut len = 3;
        let card = g.blocker_card(id);
        let met = card.and_then(|(mesh, _)| cards[..nc].iter().find(|c| c.0 == mesh));
        // The card's outline the first time one of its triangles comes, when wholly before
        // the light; else the triangle itself.
        let outline = match (card, met) {
            (Some(_), Some(&(_, true))) => continue,
            (Some((mesh, corners)), None) => {
                let (h, before) = hides(corners)?;
                cards[nc] = (mesh, before);
                nc += 1;
                before.then_some((corners, h))
            }
            _ => None,
        };
        let (h, before) = match outline {
            Some((corners, h)) => {
                len = corners.len();
                shape[..len].copy_from_slice(corners);
                (h, true)
            }
            None => {
                shape[..3].copy_from_slice(&g.blocker_vertices(id)?);
                hides(&shape[..3])?
            }
        };
        if h == 0.0 {
            continue;
        }
        if !before
            || hiding[..k]
                .iter()
                .any(|(o, n)| !hidden::apart(p, &o[..*n], &shape[..len]))
        {
            return None;
        }
        hiding[k] = (shape, len);
        k += 1;
        hidden_sum += h;
    }
    let pass = 1.0 - hidden_sum / pi;
    Some(if pass < 1e-12 { 0.0 } else { pass.min(1.0) })
}
