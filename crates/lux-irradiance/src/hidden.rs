//! What triangles hide of a spherical cap, a convex polygon or a disk, in closed form: the
//! exact shadowed irradiance of a uniform sphere, rect or disk light behind a few opaque
//! triangles ([`cap_triangle`], [`polygon_triangle`], [`disk_triangle`]).
//!
//! A sphere light of uniform radiance L seen from a receiver `p` (unit normal `n`) fills the
//! cap of directions `ω·a ≥ cos α` (a the unit axis towards its centre, sin α = R/D). Wholly
//! above the horizon (`n·a ≥ sin α`), its unshadowed irradiance is `L·Π`, Π = π sin²α (n·a)
//! ([`crate::projected::sphere`]). A triangle between `p` and the sphere hides the directions
//! of the cap that meet its projection from `p`, a spherical triangle T; what it hides is
//!
//! ```text
//! H = ∫_{cap ∩ T} n·ω dω = ½ ∮_{∂(cap ∩ T)} n·(ω × dω)
//! ```
//!
//! (the vector-irradiance identity of [`crate::projected`], with ∂ counter-clockwise seen from
//! outside the unit sphere). The boundary of cap ∩ T is made of pieces of two kinds:
//! - the parts of T's edges inside the cap: a great arc of angle t from `w₁` towards `w₂`
//!   contributes `t · n·m`, m = (w₁ × w₂)/|w₁ × w₂| (Lambert's polygon formula);
//! - the parts of the cap's rim inside T: on the rim `ω(φ) = cos α·a + sin α (u cos φ + v sin φ)`
//!   (u, v, a right-handed), the arc from ω₀ to ω₁ (Δφ counter-clockwise about a) contributes
//!   `sin²α (n·a) Δφ + cos α (ω₁ − ω₀)·(n × a)`.
//!
//! An edge's great circle (unit normal m) crosses the rim at
//! `(cos α/|g|) ĝ ∓ √(1 − cos²α/|g|²) (m × ĝ)`, g = a − (a·m) m: with `−` where the edge, run
//! from `w₁` to `w₂`, enters the cap, with `+` where it leaves. Each edge has one piece inside
//! the cap or none (a vertex inside, or a crossing on the edge, at each end); walking the
//! boundary counter-clockwise, each point where an edge leaves the cap is joined along the rim
//! to the next point, counter-clockwise, where an edge enters it. With no crossing, T lies in
//! the cap (Lambert's formula alone), holds it (all of Π) or misses it (nothing).
//!
//! A rect (any planar convex polygon) seen from `p` is bounded by great circles too: what a
//! triangle hides of it is the triangle clipped by the planes through `p` and the polygon's
//! edges, whose Π is Lambert's formula ([`polygon_triangle`]). A disk seen from `p` is bounded
//! by its rim, whose arcs [`crate::projected::disk`] integrates in closed form; the pieces are
//! joined as for the cap ([`disk_triangle`]).
//!
//! Several triangles hide the sum of what each hides when their projections do not overlap
//! ([`apart`]): then the shadowed irradiance is `L·(Π − Σ H)` exactly, with no sample and no
//! ray. The caller checks that the triangles lie wholly in front of the light (every shadow
//! ray would meet them before the light).
//!
//! Nothing in the above needs three corners: a planar convex blocker of up to
//! [`MAX_CORNERS`] corners projects to a convex spherical polygon whose edges are handled
//! alike ([`cap_polygon`], [`polygon_polygon`], [`disk_polygon`]). A flat card is one such
//! polygon rather than its triangles (and the test that they do not overlap).

use core::f64::consts::TAU;
use glam::DVec3;

/// Most corners of a blocking convex polygon ([`cap_polygon`], [`polygon_polygon`],
/// [`disk_polygon`], [`apart`]).
pub const MAX_CORNERS: usize = 8;

/// The projection of a planar convex polygon (corners `r` relative to the receiver, in order
/// around it): its corner directions, counter-clockwise from outside the unit sphere, and its
/// edges' unit inward normals `mᵢ = (wᵢ × wᵢ₊₁)/|wᵢ × wᵢ₊₁|` (inside: `ω·mᵢ ≥ 0` for all).
/// `None` for a polygon whose plane holds the receiver (its projection has no area) or a
/// non-finite one. The side is `r₀·N`, N = Σ rᵢ × rᵢ₊₁ (Newell's normal: the sum of the fan
/// triangles' `r₀·(rᵢ × rᵢ₊₁)`; for a triangle `r₀·(r₁ × r₂)`), against 10⁻¹² of the first
/// three corners' distances multiplied.
#[inline]
fn spherical<const N: usize>(r: &[DVec3; N]) -> Option<([DVec3; N], [DVec3; N])> {
    let lens = r.map(|v| v.length());
    let det = if N == 3 {
        r[0].dot(r[1].cross(r[2]))
    } else {
        let normal: DVec3 = (0..N).map(|i| r[i].cross(r[(i + 1) % N])).sum();
        r[0].dot(normal)
    };
    // (relative to the vertices' distances: a polygon seen edge-on hides nothing)
    if crate::not_positive(det.abs() - 1e-12 * lens[0] * lens[1] * lens[2]) {
        return None;
    }
    let mut w: [DVec3; N] = core::array::from_fn(|i| r[i] / lens[i]);
    if det < 0.0 {
        w[1..].reverse();
    }
    let m: [DVec3; N] = core::array::from_fn(|i| w[i].cross(w[(i + 1) % N]).normalize());
    m.iter().all(|m| m.is_finite()).then_some((w, m))
}

/// `$body` with `$a` bound to `$poly` as an array of its length (3 to [`MAX_CORNERS`]), else
/// `$none`: one compiled body per corner count.
macro_rules! by_corners {
    ($poly:expr, $none:expr, |$a:ident| $body:expr) => {
        match $poly.len() {
            3 => by_corners!(@ 3, $poly, $none, $a, $body),
            4 => by_corners!(@ 4, $poly, $none, $a, $body),
            5 => by_corners!(@ 5, $poly, $none, $a, $body),
            6 => by_corners!(@ 6, $poly, $none, $a, $body),
            7 => by_corners!(@ 7, $poly, $none, $a, $body),
            8 => by_corners!(@ 8, $poly, $none, $a, $body),
            _ => $none,
        }
    };
    (@ $n:literal, $poly:expr, $none:expr, $a:ident, $body:expr) => {{
        let Ok($a) = <&[DVec3; $n]>::try_from($poly) else {
            return $none;
        };
        $body
    }};
}

/// The projection of a planar convex polygon of up to [`MAX_CORNERS`] corners (world points)
/// seen from `p`, in arrays of that size with its corner count: [`spherical`].
fn spherical_any(
    poly: &[DVec3],
    p: DVec3,
) -> Option<(usize, [DVec3; MAX_CORNERS], [DVec3; MAX_CORNERS])> {
    fn widen<const N: usize>(
        (w, m): ([DVec3; N], [DVec3; N]),
    ) -> (usize, [DVec3; MAX_CORNERS], [DVec3; MAX_CORNERS]) {
        let mut out = (N, [DVec3::ZERO; MAX_CORNERS], [DVec3::ZERO; MAX_CORNERS]);
        out.1[..N].copy_from_slice(&w);
        out.2[..N].copy_from_slice(&m);
        out
    }
    by_corners!(poly, None, |a| spherical(&a.map(|v| v - p)).map(widen))
}

/// Whether the cap of directions around the unit `axis` with `cos α = cos_a` certainly misses
/// the projection from `p` of the planar convex polygon `poly` (world points in order around
/// it, 3 to [`MAX_CORNERS`]): the polygon then meets no ray from `p` within α of the axis. The
/// projection meets the cap iff a corner lies in it (`axis·wᵢ ≥ cos α`), the axis lies inside
/// the projection (`axis·mᵢ ≥ 0` for every edge), or an edge's great-circle arc passes within
/// α of the axis (`|axis·mᵢ| < sin α`, its nearest point to the axis `axis − (axis·mᵢ)mᵢ`
/// between the corners); each test has 10⁻⁹ of slack towards "meets". False when unsure: the
/// polygon's plane holds `p` (its projection has no area), more corners, non-finite input.
pub fn cap_misses_polygon(p: DVec3, axis: DVec3, cos_a: f64, poly: &[DVec3]) -> bool {
    by_corners!(poly, false, |a| cap_misses(p, axis, cos_a, a))
}

/// [`cap_misses_polygon`] for `N` corners.
fn cap_misses<const N: usize>(p: DVec3, axis: DVec3, cos_a: f64, poly: &[DVec3; N]) -> bool {
    const SLACK: f64 = 1e-9;
    let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
    let Some((w, m)) = spherical(&poly.map(|v| v - p)) else {
        return false;
    };
    if !(axis.is_finite() && cos_a.is_finite()) || w.iter().any(|w| axis.dot(*w) >= cos_a - SLACK) {
        return false;
    }
    let mut inside = true;
    for i in 0..N {
        let am = axis.dot(m[i]);
        inside &= am >= 0.0;
        if am.abs() < sin_a + SLACK {
            let g = axis - m[i] * am;
            if w[i].cross(g).dot(m[i]) >= -SLACK && g.cross(w[(i + 1) % N]).dot(m[i]) >= -SLACK {
                return false;
            }
        }
    }
    !inside
}

/// Π of the part of the cap around the unit axis `axis` with `cos α = cos_a` hidden by the
/// triangle `tri` (world points; either face) from the receiver at `p` with unit normal `n`:
/// `∫ n·ω dω` over the cap's directions that meet the triangle's projection from `p` (module
/// docs). The cap must lie wholly above the horizon (`n·axis ≥ sin α`, so that `n·ω > 0` over
/// it); `None` otherwise or for non-finite input. 0 when the triangle's plane holds `p` or its
/// projection misses the cap; the cap's own Π (π sin²α (n·axis)) when it covers the cap. Where
/// the triangle lies along the rays (in front of the light or behind it) is the caller's.
pub fn cap_triangle(p: DVec3, n: DVec3, axis: DVec3, cos_a: f64, tri: &[DVec3; 3]) -> Option<f64> {
    cap(p, n, axis, cos_a, tri)
}

/// [`cap_triangle`] for a planar convex polygon `poly` (world points in order around it, 3 to
/// [`MAX_CORNERS`]; `None` for more): the same boundary integral over its edges.
pub fn cap_polygon(p: DVec3, n: DVec3, axis: DVec3, cos_a: f64, poly: &[DVec3]) -> Option<f64> {
    by_corners!(poly, None, |a| cap(p, n, axis, cos_a, a))
}

/// [`cap_polygon`] for `N` corners.
fn cap<const N: usize>(
    p: DVec3,
    n: DVec3,
    axis: DVec3,
    cos_a: f64,
    poly: &[DVec3; N],
) -> Option<f64> {
    let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
    if !(cos_a > 0.0 && cos_a < 1.0 && n.dot(axis) >= sin_a && axis.is_finite() && p.is_finite()) {
        return None;
    }
    let Some((w, m)) = spherical(&poly.map(|v| v - p)) else {
        return Some(0.0);
    };
    let na = n.dot(axis);
    let full = core::f64::consts::PI * sin_a * sin_a * na;
    // The cap against each edge's half-space ω·m ≥ 0: wholly outside one, nothing is hidden;
    // inside all three, all of it.
    let am = m.map(|m| axis.dot(m));
    if am.iter().any(|&x| x <= -sin_a) {
        return Some(0.0);
    }
    if am.iter().all(|&x| x >= sin_a) {
        return Some(full);
    }
    // Each edge's part inside the cap, from `start` to `end` (a vertex, or where its great
    // circle crosses the rim: entering the cap, or leaving it), and its contribution
    // `angle · n·m`. On the great circle of unit normal m the rim's crossings are
    // `(cos α/|g|) ĝ ± √(1 − cos²α/|g|²) (m × ĝ)`, g = axis − (axis·m) m: the one with `−`
    // enters the cap along the edge's direction of travel `m × ω`, the one with `+` leaves it.
    let mut sum = 0.0;
    let (mut entries, mut exits) = ([DVec3::ZERO; N], [DVec3::ZERO; N]);
    let (mut ne, mut nx) = (0, 0);
    let inside = w.map(|w| axis.dot(w) >= cos_a);
    for i in 0..N {
        let (a, b, mi) = (w[i], w[(i + 1) % N], m[i]);
        let crossings = || {
            let g = axis - am[i] * mi;
            let g_len = g.length();
            if g_len <= cos_a {
                return None;
            }
            let g_hat = g / g_len;
            let along = cos_a / g_len;
            let side = mi.cross(g_hat) * (1.0 - along * along).max(0.0).sqrt();
            Some((g_hat * along - side, g_hat * along + side))
        };
        // (a point of the edge's great circle between its vertices)
        let on_arc = |x: DVec3| a.cross(x).dot(mi) >= 0.0 && x.cross(b).dot(mi) >= 0.0;
        let piece = match (inside[i], inside[(i + 1) % N]) {
            (true, true) => Some((a, b)),
            (true, false) => crossings().map(|(_, exit)| {
                exits[nx] = exit;
                nx += 1;
                (a, exit)
            }),
            (false, true) => crossings().map(|(entry, _)| {
                entries[ne] = entry;
                ne += 1;
                (entry, b)
            }),
            (false, false) => crossings()
                .filter(|&(entry, exit)| on_arc(entry) && on_arc(exit))
                .map(|(entry, exit)| {
                    entries[ne] = entry;
                    exits[nx] = exit;
                    (ne, nx) = (ne + 1, nx + 1);
                    (entry, exit)
                }),
        };
        if let Some((s, e)) = piece {
            sum += s.cross(e).length().atan2(s.dot(e)) * n.dot(mi);
        }
    }
    if ne == 0 && nx == 0 {
        // The rim meets no edge: the triangle inside the cap (its edges, whole, are the
        // boundary), or the cap inside the triangle, or apart.
        return Some(if inside.iter().all(|&x| x) {
            (0.5 * sum).clamp(0.0, full)
        } else if am.iter().all(|&x| x >= 0.0) {
            full
        } else {
            0.0
        });
    }
    // The rim from each exit counter-clockwise (about the axis) to the next entry lies in the
    // triangle: on the rim ω = cos α·axis + sin α (u cos φ + v sin φ), the arc from ω₀ to ω₁
    // contributes `sin²α (n·axis) Δφ + cos α (ω₁ − ω₀)·(n × axis)`.
    let nxa = n.cross(axis);
    let arc = |x: DVec3, e: DVec3, d: f64| sin_a * sin_a * na * d + cos_a * (e - x).dot(nxa);
    if (ne, nx) == (1, 1) {
        // One exit and one entry (the common case): Δφ from their offsets to the rim's centre.
        let (qx, qe) = (exits[0] - cos_a * axis, entries[0] - cos_a * axis);
        let d = qx.cross(qe).dot(axis).atan2(qx.dot(qe)).rem_euclid(TAU);
        return Some((0.5 * (sum + arc(exits[0], entries[0], d))).clamp(0.0, full));
    }
    let u = axis.any_orthonormal_vector();
    let v = axis.cross(u);
    let phi = |x: DVec3| x.dot(v).atan2(x.dot(u));
    let entry_phi: [f64; N] = core::array::from_fn(|j| if j < ne { phi(entries[j]) } else { 0.0 });
    for &x in &exits[..nx] {
        let fx = phi(x);
        let mut best: Option<(f64, DVec3)> = None;
        for j in 0..ne {
            let d = (entry_phi[j] - fx).rem_euclid(TAU);
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, entries[j]));
            }
        }
        if let Some((d, e)) = best {
            sum += arc(x, e, d);
        }
    }
    Some((0.5 * sum).clamp(0.0, full))
}

/// Π of the part of the planar convex polygon `light` (world points in order around it, at
/// most 5) hidden by the triangle `tri` (world points; either face) from the receiver at `p`
/// with unit normal `n`: `∫ max(0, n·ω) dω` over the directions that meet both. Both
/// projections are bounded by great circles, so their intersection is the triangle clipped by
/// the planes through `p` and the polygon's edges (Sutherland–Hodgman: the clipped polygon
/// lies in the pyramid from `p` over the light), whose Π is Lambert's formula, clipped to the
/// horizon ([`crate::projected::polygon`]). 0 when the triangle's or the polygon's plane holds
/// `p`. Where the triangle lies along the rays is the caller's.
pub fn polygon_triangle(p: DVec3, n: DVec3, light: &[DVec3], tri: &[DVec3; 3]) -> f64 {
    polygon_clip(p, n, light, tri)
}

/// [`polygon_triangle`] for a planar convex blocking polygon `blocker` (world points in order
/// around it, 3 to [`MAX_CORNERS`]; 0 for more): the blocker clipped by the light's edge planes.
pub fn polygon_polygon(p: DVec3, n: DVec3, light: &[DVec3], blocker: &[DVec3]) -> f64 {
    by_corners!(blocker, 0.0, |a| polygon_clip(p, n, light, a))
}

/// [`polygon_polygon`] for a blocker of `N` corners.
fn polygon_clip<const N: usize>(p: DVec3, n: DVec3, light: &[DVec3], blocker: &[DVec3; N]) -> f64 {
    let k = light.len();
    let r = blocker.map(|v| v - p);
    if !(3..=5).contains(&k) || spherical(&r).is_none() {
        return 0.0;
    }
    let l: [DVec3; 5] = core::array::from_fn(|i| if i < k { light[i] - p } else { DVec3::ZERO });
    let det = l[0].dot(l[1].cross(l[2]));
    let lens = l[0].length() * l[1].length() * l[2].length();
    if crate::not_positive(det.abs() - 1e-12 * lens) {
        return 0.0;
    }
    // Clip the blocker (relative to p) by each edge plane, kept side towards the polygon (a
    // convex clip adds at most one corner: at most MAX_CORNERS + 5 in all).
    const MOST: usize = MAX_CORNERS + 5;
    let mut poly = [DVec3::ZERO; MOST];
    let mut m = N;
    poly[..N].copy_from_slice(&r);
    for i in 0..k {
        let inward = l[i].cross(l[(i + 1) % k]) * det.signum();
        let mut out = [DVec3::ZERO; MOST];
        let mut j = 0;
        for a in 0..m {
            let (x, y) = (poly[a], poly[(a + 1) % m]);
            let (hx, hy) = (inward.dot(x), inward.dot(y));
            if hx >= 0.0 && j < MOST {
                out[j] = x;
                j += 1;
            }
            if (hx >= 0.0) != (hy >= 0.0) && j < MOST {
                out[j] = x + (y - x) * (hx / (hx - hy));
                j += 1;
            }
        }
        (poly, m) = (out, j);
        if m < 3 {
            return 0.0;
        }
    }
    crate::projected::polygon(DVec3::ZERO, n, &poly[..m])
}

/// Π of the part of the disk of centre `c`, unit normal `axis` and radius `radius` hidden by
/// the triangle `tri` (world points; either face) from the receiver at `p` with unit normal
/// `n`: `∫ n·ω dω` over the directions that meet both. The disk seen from `p` is bounded by
/// its rim, `r(t) = c − p + R(u cos t + v sin t)` (u, v, axis right-handed), whose arcs
/// contribute [`crate::projected::disk`]'s rim integral; an edge's great circle (unit normal m)
/// crosses the rim where `m·r(t) = 0`. As in [`cap_triangle`], each edge has one piece inside the
/// disk or none, and each point where an edge leaves it is joined along the rim to the next
/// where an edge enters it (counter-clockwise seen from outside the unit sphere: t increasing
/// when `axis` points away from `p`, decreasing otherwise). The disk must lie wholly above the horizon (every rim point:
/// `None` otherwise, so `n·ω > 0` over it); `None` too where the crossings are ambiguous
/// (an edge grazing the rim) — the caller samples instead. 0 when the triangle's or the disk's
/// plane holds `p`.
pub fn disk_triangle(
    p: DVec3,
    n: DVec3,
    disk: (DVec3, DVec3, f64),
    tri: &[DVec3; 3],
) -> Option<f64> {
    disk_n(p, n, disk, tri)
}

/// [`disk_triangle`] for a planar convex blocking polygon `poly` (world points in order around
/// it, 3 to [`MAX_CORNERS`]; `None` for more): the same pieces over its `k` edges.
pub fn disk_polygon(p: DVec3, n: DVec3, disk: (DVec3, DVec3, f64), poly: &[DVec3]) -> Option<f64> {
    by_corners!(poly, None, |a| disk_n(p, n, disk, a))
}

/// [`disk_polygon`] for `N` corners.
fn disk_n<const N: usize>(
    p: DVec3,
    n: DVec3,
    (c, axis, radius): (DVec3, DVec3, f64),
    poly: &[DVec3; N],
) -> Option<f64> {
    let d = c - p;
    let tilt = (n - n.dot(axis) * axis).length();
    if !(radius > 0.0 && n.dot(d) > radius * tilt && d.is_finite() && axis.is_finite()) {
        return None;
    }
    let side = axis.dot(d);
    if crate::not_positive(side.abs() - 1e-12 * d.length()) {
        return Some(0.0);
    }
    let Some((w, m)) = spherical(&poly.map(|v| v - p)) else {
        return Some(0.0);
    };
    let u = axis.any_orthonormal_vector();
    let v = axis.cross(u);
    let rim = |t: f64| {
        let (st, ct) = t.sin_cos();
        d + radius * (u * ct + v * st)
    };
    // A direction's ray meets the disk.
    let meets = |x: DVec3| {
        let s = side / x.dot(axis);
        s > 0.0 && (x * s - d).length_squared() <= radius * radius
    };
    let inside = w.map(meets);
    let mut sum = 0.0;
    // Where edges enter and leave the disk: direction and rim parameter.
    let (mut entries, mut exits) = ([(DVec3::ZERO, 0.0); N], [(DVec3::ZERO, 0.0); N]);
    let (mut ne, mut nx) = (0, 0);
    for i in 0..N {
        let (a, b, mi) = (w[i], w[(i + 1) % N], m[i]);
        let on_arc = |x: DVec3| a.cross(x).dot(mi) >= 0.0 && x.cross(b).dot(mi) >= 0.0;
        // m·r(t) = K + P cos t + Q sin t = 0 at t = θ ± β.
        let (kd, pu, qv) = (mi.dot(d), radius * mi.dot(u), radius * mi.dot(v));
        let s = (pu * pu + qv * qv).sqrt();
        let mut on = [(DVec3::ZERO, 0.0); 2];
        let mut count = 0;
        if s > kd.abs() {
            let (theta, beta) = (qv.atan2(pu), (-kd / s).acos());
            for t in [theta - beta, theta + beta] {
                let x = rim(t).normalize();
                if on_arc(x) {
                    on[count] = (x, t);
                    count += 1;
                }
            }
        }
        let piece = match (inside[i], inside[(i + 1) % N], count) {
            (true, true, _) => Some((a, b)),
            (true, false, 1) => {
                exits[nx] = on[0];
                nx += 1;
                Some((a, on[0].0))
            }
            (false, true, 1) => {
                entries[ne] = on[0];
                ne += 1;
                Some((on[0].0, b))
            }
            (false, false, 0) => None,
            (false, false, 2) => {
                // (the crossing nearer the edge's start is where it enters)
                let (x0, x1) = if a.dot(on[0].0) >= a.dot(on[1].0) {
                    (on[0], on[1])
                } else {
                    (on[1], on[0])
                };
                entries[ne] = x0;
                exits[nx] = x1;
                (ne, nx) = (ne + 1, nx + 1);
                Some((x0.0, x1.0))
            }
            _ => return None,
        };
        if let Some((s0, e0)) = piece {
            sum += s0.cross(e0).length().atan2(s0.dot(e0)) * n.dot(mi);
        }
    }
    let full = crate::projected::disk(p, n, c, axis, radius)?;
    if ne == 0 && nx == 0 {
        // The rim meets no edge: the triangle inside the disk, the disk inside the triangle,
        // or apart.
        let rim_in = m.iter().all(|mi| mi.dot(rim(0.0)) >= 0.0);
        return Some(if inside.iter().all(|&x| x) {
            (0.5 * sum).clamp(0.0, full)
        } else if rim_in {
            full
        } else {
            0.0
        });
    }
    if ne != nx {
        return None;
    }
    let sigma = side.signum();
    for &(_, tx) in &exits[..nx] {
        let gap = |te: f64| (sigma * (te - tx)).rem_euclid(TAU);
        let (_, te) = entries[..ne]
            .iter()
            .copied()
            .min_by(|x, y| gap(x.1).total_cmp(&gap(y.1)))?;
        let g = gap(te);
        sum += if sigma > 0.0 {
            crate::projected::rim_arc(n, d, (u, v), radius, tx, tx + g)?
        } else {
            -crate::projected::rim_arc(n, d, (u, v), radius, tx - g, tx)?
        };
    }
    Some((0.5 * sum).clamp(0.0, full))
}

/// Whether the planar convex polygons `a` and `b` (world points in order around each, 3 to
/// [`MAX_CORNERS`] corners; triangles most often) seen from `p` have projections whose
/// interiors do not overlap: one of their edges' great circles (the plane through `p` and the
/// edge) has one polygon on each side, within 10⁻⁹ rad (a shared edge separates two triangles
/// of a flat card). False when none does (for two convex spherical polygons, overlapping), for
/// a polygon seen edge-on or with more corners — a conservative answer: what [`cap_triangle`]
/// hides may then be counted twice.
pub fn apart(p: DVec3, a: &[DVec3], b: &[DVec3]) -> bool {
    let (Some((ka, wa, ma)), Some((kb, wb, mb))) = (spherical_any(a, p), spherical_any(b, p))
    else {
        return false;
    };
    let outside = |m: &[DVec3], w: &[DVec3]| m.iter().any(|m| w.iter().all(|w| m.dot(*w) <= 1e-9));
    outside(&ma[..ka], &wb[..kb]) || outside(&mb[..kb], &wa[..ka])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projected;
    use core::f64::consts::PI;

    /// Sutherland–Hodgman: the part of the polygon `poly` where `keep(x) ≥ 0` (`keep` affine).
    fn clip<
        T: Copy
            + core::ops::Add<Output = T>
            + core::ops::Sub<Output = T>
            + core::ops::Mul<f64, Output = T>,
    >(
        poly: &[T],
        keep: impl Fn(T) -> f64,
    ) -> Vec<T> {
        let mut out = Vec::new();
        for i in 0..poly.len() {
            let (x, y) = (poly[i], poly[(i + 1) % poly.len()]);
            let (hx, hy) = (keep(x), keep(y));
            if hx >= 0.0 {
                out.push(x);
            }
            if (hx >= 0.0) != (hy >= 0.0) {
                out.push(x + (y - x) * (hx / (hx - hy)));
            }
        }
        out
    }

    /// An independent reference for [`cap_triangle`]: in the gnomonic chart around the axis
    /// (the plane at unit distance along it, where great circles are straight lines and the
    /// cap is the disk of radius tan α), the inscribed 4096-gon of the disk clipped by the
    /// triangle (cut to the half-space in front of `p`), mapped back to directions and summed
    /// with Lambert's polygon formula. The 4096-gon's area is short of the disk's by 4·10⁻⁷.
    fn reference(p: DVec3, n: DVec3, axis: DVec3, cos_a: f64, tri: &[DVec3; 3]) -> f64 {
        let u = axis.any_orthonormal_vector();
        let v = axis.cross(u);
        let front = clip(&tri.map(|x| x - p), |r| r.dot(axis) - 1e-9);
        let mut chart: Vec<glam::DVec2> = front
            .iter()
            .map(|r| glam::DVec2::new(r.dot(u), r.dot(v)) / r.dot(axis))
            .collect();
        if chart.len() < 3 {
            return 0.0;
        }
        let area2: f64 = (0..chart.len())
            .map(|i| chart[i].perp_dot(chart[(i + 1) % chart.len()]))
            .sum();
        if area2 < 0.0 {
            chart.reverse();
        }
        let rho = (1.0 - cos_a * cos_a).sqrt() / cos_a;
        let k = 4096;
        let mut poly: Vec<glam::DVec2> = (0..k)
            .map(|j| {
                let t = TAU * j as f64 / k as f64;
                glam::DVec2::new(rho * t.cos(), rho * t.sin())
            })
            .collect();
        for i in 0..chart.len() {
            let (a, b) = (chart[i], chart[(i + 1) % chart.len()]);
            poly = clip(&poly, |x| (b - a).perp_dot(x - a));
        }
        let dirs: Vec<DVec3> = poly.iter().map(|x| u * x.x + v * x.y + axis).collect();
        lambert(n, &dirs)
    }

    /// Lambert's formula for the polygon of (not necessarily unit) directions `dirs` in order,
    /// any length, unclipped: `½ |Σ θᵢ n·(aᵢ × bᵢ)/|aᵢ × bᵢ||`.
    fn lambert(n: DVec3, dirs: &[DVec3]) -> f64 {
        let mut sum = 0.0;
        for i in 0..dirs.len() {
            let (a, b) = (dirs[i], dirs[(i + 1) % dirs.len()]);
            let c = a.cross(b);
            let s = c.length();
            if s > 0.0 {
                sum += s.atan2(a.dot(b)) * n.dot(c) / s;
            }
        }
        0.5 * sum.abs()
    }

    /// Whether the ray from `p` along `w` meets the triangle (either face).
    fn meets(p: DVec3, w: DVec3, t: &[DVec3; 3]) -> bool {
        let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
        let q = w.cross(e2);
        let det = e1.dot(q);
        if det.abs() < 1e-300 {
            return false;
        }
        let s = p - t[0];
        let b1 = s.dot(q) / det;
        let r = s.cross(e1);
        let b2 = w.dot(r) / det;
        let t = e2.dot(r) / det;
        b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 && t > 0.0
    }

    /// A deterministic stream of numbers in [0, 1) (SplitMix64, Steele et al. 2014).
    fn stream(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed;
        move || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
        }
    }

    #[test]
    fn covering_inside_and_missing_triangles_are_closed_forms() {
        let p = DVec3::new(0.2, 0.0, -0.1);
        let n = DVec3::Y;
        let centre = DVec3::new(0.5, 2.0, 0.3);
        let (d, rad) = ((centre - p).length(), 0.4);
        let axis = (centre - p) / d;
        let cos_a = (1.0 - rad * rad / (d * d)).sqrt();
        let cap = projected::sphere(p, n, centre, rad).unwrap();
        // A huge triangle across the rays: the whole cap.
        let big = [
            DVec3::new(-50.0, 1.0, -50.0),
            DVec3::new(50.0, 1.0, -50.0),
            DVec3::new(0.0, 1.0, 80.0),
        ];
        let h = cap_triangle(p, n, axis, cos_a, &big).unwrap();
        assert!((h - cap).abs() <= 1e-12 * cap, "{h} vs {cap}");
        // A small triangle well inside the cap's cone: Lambert's polygon formula.
        let mid = p + (centre - p) * 0.5;
        let small = [
            mid + DVec3::new(-0.03, 0.0, -0.02),
            mid + DVec3::new(0.04, 0.01, -0.01),
            mid + DVec3::new(0.0, -0.01, 0.05),
        ];
        let h = cap_triangle(p, n, axis, cos_a, &small).unwrap();
        let lambert = projected::polygon(p, n, &small);
        assert!(
            h > 0.0 && (h - lambert).abs() <= 1e-12 * lambert,
            "{h} vs {lambert}"
        );
        // Its reverse winding hides the same.
        let rev = [small[0], small[2], small[1]];
        assert_eq!(cap_triangle(p, n, axis, cos_a, &rev), Some(h));
        // Aside, and seen edge-on (the receiver's own plane): nothing.
        let aside = small.map(|v| v + DVec3::new(3.0, 0.0, 0.0));
        assert_eq!(cap_triangle(p, n, axis, cos_a, &aside), Some(0.0));
        let flat = [
            DVec3::new(-1.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, -1.0),
            DVec3::new(0.0, 0.0, 1.0),
        ];
        assert_eq!(cap_triangle(p, n, axis, cos_a, &flat), Some(0.0));
        // A cap the horizon cuts, and bad input.
        assert_eq!(cap_triangle(p, DVec3::X, axis, cos_a, &small), None);
        assert_eq!(cap_triangle(p, n, axis, f64::NAN, &small), None);
        assert_eq!(cap_triangle(p, n, axis, 1.0, &small), None);
    }

    #[test]
    fn a_half_plane_through_the_axis_hides_half_the_cap() {
        // The cap straight above the receiver (n = axis): Π is symmetric about any plane
        // through the axis, and a triangle reaching far beyond the cap on one side of the
        // plane x = 0 hides exactly half of it.
        let (p, n) = (DVec3::ZERO, DVec3::Y);
        let cos_a = 0.8;
        let half = [
            DVec3::new(0.0, 1.0, -100.0),
            DVec3::new(0.0, 1.0, 100.0),
            DVec3::new(100.0, 1.0, 0.0),
        ];
        let h = cap_triangle(p, n, n, cos_a, &half).unwrap();
        let cap = PI * (1.0 - cos_a * cos_a);
        assert!((h - 0.5 * cap).abs() <= 1e-12 * cap, "{h} vs {}", 0.5 * cap);
    }

    #[test]
    fn random_triangles_match_quadrature() {
        // Triangles at random around the cap's cone (crossing its rim, holding it, corners
        // inside, missing it), caps of several sizes and tilts: the closed form against the
        // clipped 4096-gon (`reference`).
        let mut r = stream(7);
        let mut kinds = [0usize; 3];
        for case in 0..200 {
            let p = DVec3::new(r() - 0.5, 0.0, r() - 0.5);
            let n = DVec3::Y;
            let centre = DVec3::new(2.0 * r() - 1.0, 1.5 + r(), 2.0 * r() - 1.0);
            let d = (centre - p).length();
            let rad = 0.1 + 0.5 * r();
            let axis = (centre - p) / d;
            let cos_a = (1.0 - rad * rad / (d * d)).sqrt();
            if n.dot(axis) < (1.0 - cos_a * cos_a).sqrt() {
                continue;
            }
            // Vertices on a plane partway to the light, spread around where the cone crosses it.
            let s = 0.2 + 0.6 * r();
            let at = p + (centre - p) * s;
            let spread = rad * s * (0.5 + 3.0 * r());
            let tri = [0, 1, 2].map(|_| {
                at + DVec3::new(
                    spread * (2.0 * r() - 1.0),
                    0.3 * spread * (2.0 * r() - 1.0),
                    spread * (2.0 * r() - 1.0),
                )
            });
            let h = cap_triangle(p, n, axis, cos_a, &tri).unwrap();
            let q = reference(p, n, axis, cos_a, &tri);
            let cap = projected::sphere(p, n, centre, rad).unwrap();
            assert!(
                (h - q).abs() <= 2e-6 * cap,
                "case {case}: closed form {h}, reference {q} (cap {cap})"
            );
            kinds[if h == 0.0 {
                0
            } else if h < 0.999 * cap {
                1
            } else {
                2
            }] += 1;
        }
        // Misses, partial covers and whole covers all occur.
        assert!(kinds.iter().all(|&k| k > 0), "{kinds:?}");
    }

    /// An independent reference for [`polygon_triangle`] with the triangle between `p` and the
    /// light's plane: the triangle projected from `p` onto that plane, clipped there by the
    /// light polygon's edges (in the plane), and Lambert's formula of the result.
    fn in_plane(p: DVec3, n: DVec3, light: &[DVec3], tri: &[DVec3; 3]) -> f64 {
        let nl = (light[1] - light[0]).cross(light[2] - light[0]);
        let h = nl.dot(light[0] - p);
        let mut shadow: Vec<DVec3> = tri
            .iter()
            .map(|&v| p + (v - p) * (h / nl.dot(v - p)))
            .collect();
        let k = light.len();
        for i in 0..k {
            let (a, b) = (light[i], light[(i + 1) % k]);
            let inward = nl.cross(b - a);
            let inward = if inward.dot(light[(i + 2) % k] - a) > 0.0 {
                inward
            } else {
                -inward
            };
            shadow = clip(&shadow, |x| inward.dot(x - a));
        }
        if shadow.len() < 3 {
            return 0.0;
        }
        let rel: Vec<DVec3> = shadow.iter().map(|&x| x - p).collect();
        lambert(n, &rel)
    }

    /// A random triangle around the point a fraction s ∈ [0.2, 0.9) of the way from `p` to
    /// `to`, its vertices within 0.8·s·(a random fraction) of it (a fifth of that vertically).
    fn on_the_way(r: &mut impl FnMut() -> f64, p: DVec3, to: DVec3) -> [DVec3; 3] {
        let s = 0.2 + 0.7 * r();
        let at = p + (to - p) * s;
        let spread = 0.8 * s * r();
        [0, 1, 2].map(|_| {
            at + DVec3::new(
                spread * (2.0 * r() - 1.0),
                0.2 * spread * (2.0 * r() - 1.0),
                spread * (2.0 * r() - 1.0),
            )
        })
    }

    #[test]
    fn polygon_triangle_matches_its_shadow_on_the_light() {
        // A tilted rect light (a parallelogram under shear) above a receiver and triangles
        // between them at random: what each hides equals its shadow on the light's plane
        // clipped to the light; covering and inner triangles are the closed forms.
        let (p, n) = (DVec3::new(0.1, 0.0, -0.2), DVec3::Y);
        let light = [
            DVec3::new(-0.4, 1.5, -0.3),
            DVec3::new(0.5, 1.7, -0.3),
            DVec3::new(0.6, 1.8, 0.4),
            DVec3::new(-0.3, 1.6, 0.4),
        ];
        let full = projected::polygon(p, n, &light);
        let big = [
            DVec3::new(-50.0, 1.0, -50.0),
            DVec3::new(50.0, 1.0, -50.0),
            DVec3::new(0.0, 1.0, 80.0),
        ];
        let h = polygon_triangle(p, n, &light, &big);
        assert!((h - full).abs() <= 1e-12 * full, "{h} vs {full}");
        let small = [
            DVec3::new(0.05, 0.8, -0.1),
            DVec3::new(0.12, 0.82, -0.08),
            DVec3::new(0.08, 0.79, 0.0),
        ];
        let h = polygon_triangle(p, n, &light, &small);
        let lambert = projected::polygon(p, n, &small);
        assert!(
            h > 0.0 && (h - lambert).abs() <= 1e-12 * lambert,
            "{h} vs {lambert}"
        );
        // (the reversed light and triangle hide the same; a triangle seen edge-on nothing)
        let rev = [light[3], light[2], light[1], light[0]];
        assert!((polygon_triangle(p, n, &rev, &small) - h).abs() <= 1e-15);
        let flat = [p + DVec3::X, p + DVec3::Z, p - DVec3::X - DVec3::Z];
        assert_eq!(polygon_triangle(p, n, &light, &flat), 0.0);
        let mut r = stream(5);
        let mut partial = 0;
        for case in 0..200 {
            let tri = on_the_way(&mut r, p, DVec3::new(0.1, 1.65, 0.05));
            let (h, want) = (
                polygon_triangle(p, n, &light, &tri),
                in_plane(p, n, &light, &tri),
            );
            assert!(
                (h - want).abs() <= 1e-12 * full,
                "case {case}: {h} vs {want}"
            );
            partial += usize::from(
                h > 0.0 && h < 0.999 * full && h < 0.999 * projected::polygon(p, n, &tri),
            );
        }
        assert!(partial > 50, "{partial}");
    }

    #[test]
    fn disk_triangle_matches_its_shadow_on_the_disk() {
        // A tilted disk above a receiver, its axis either way, and triangles between them at
        // random: what each hides equals its shadow on the disk's plane clipped to the disk
        // (its inscribed 4096-gon, short of the disk's area by 4·10⁻⁷); covering and inner
        // triangles are the closed forms.
        let (p, n) = (DVec3::new(0.1, 0.0, -0.2), DVec3::Y);
        let c = DVec3::new(0.2, 1.6, 0.1);
        let axis = DVec3::new(0.3, -1.0, 0.2).normalize();
        let radius = 0.45;
        let full = projected::disk(p, n, c, axis, radius).unwrap();
        let u = axis.any_orthonormal_vector();
        let v = axis.cross(u);
        let gon: Vec<DVec3> = (0..4096)
            .map(|j| {
                let t = TAU * j as f64 / 4096.0;
                c + radius * (u * t.cos() + v * t.sin())
            })
            .collect();
        let big = [
            DVec3::new(-50.0, 1.0, -50.0),
            DVec3::new(50.0, 1.0, -50.0),
            DVec3::new(0.0, 1.0, 80.0),
        ];
        for ax in [axis, -axis] {
            let h = disk_triangle(p, n, (c, ax, radius), &big).unwrap();
            assert!((h - full).abs() <= 1e-12 * full, "{h} vs {full}");
        }
        let small = [
            DVec3::new(0.12, 0.8, -0.05),
            DVec3::new(0.18, 0.82, -0.03),
            DVec3::new(0.14, 0.79, 0.02),
        ];
        let h = disk_triangle(p, n, (c, axis, radius), &small).unwrap();
        let lambert = projected::polygon(p, n, &small);
        assert!(
            h > 0.0 && (h - lambert).abs() <= 1e-12 * lambert,
            "{h} vs {lambert}"
        );
        // A disk the horizon cuts, and the disk's own plane through p.
        assert_eq!(disk_triangle(p, DVec3::X, (c, axis, radius), &small), None);
        let edge_on = (c, (c - p).cross(DVec3::Z).normalize(), radius);
        assert_eq!(disk_triangle(p, n, edge_on, &small), Some(0.0));
        let mut r = stream(9);
        let mut partial = 0;
        for case in 0..200 {
            let tri = on_the_way(&mut r, p, c);
            let want = in_plane(p, n, &gon, &tri);
            for ax in [axis, -axis] {
                let h = disk_triangle(p, n, (c, ax, radius), &tri).unwrap();
                assert!(
                    (h - want).abs() <= 2e-6 * full,
                    "case {case}: {h} vs {want} (full {full})"
                );
            }
            partial += usize::from(
                want > 0.0 && want < 0.999 * full && want < 0.999 * projected::polygon(p, n, &tri),
            );
        }
        assert!(partial > 50, "{partial}");
    }

    #[test]
    fn apart_triangles_never_share_a_direction() {
        let p = DVec3::new(0.1, 0.0, 0.2);
        // Two halves of a card seen from p: apart (their shared edge separates them).
        let q = [
            DVec3::new(-0.5, 1.0, -0.5),
            DVec3::new(0.5, 1.2, -0.5),
            DVec3::new(0.5, 1.4, 0.5),
            DVec3::new(-0.5, 1.2, 0.5),
        ];
        let (a, b) = ([q[0], q[1], q[2]], [q[0], q[2], q[3]]);
        assert!(apart(p, &a, &b) && apart(p, &b, &a));
        // The same triangle twice, and one behind the other: overlapping.
        assert!(!apart(p, &a, &a));
        let behind = a.map(|v| v * 1.5 + DVec3::new(0.05, 0.0, 0.0));
        assert!(!apart(p, &a, &behind));
        // Random pairs: when `apart` says so, no direction meets both.
        let mut r = stream(11);
        let mut said = 0;
        for _ in 0..300 {
            let tri = |r: &mut dyn FnMut() -> f64| {
                [0, 1, 2].map(|_| DVec3::new(2.0 * r() - 1.0, 0.5 + r(), 2.0 * r() - 1.0))
            };
            let (s, t) = (tri(&mut r), tri(&mut r));
            if !apart(p, &s, &t) {
                continue;
            }
            said += 1;
            for i in 0..64 {
                for j in 0..64 {
                    let w = DVec3::new(
                        (i as f64 + 0.5) / 32.0 - 1.0,
                        1.0,
                        (j as f64 + 0.5) / 32.0 - 1.0,
                    )
                    .normalize();
                    assert!(
                        !(meets(p, w, &s) && meets(p, w, &t)),
                        "{s:?} {t:?} share {w}"
                    );
                }
            }
        }
        assert!(said > 50, "{said}");
    }

    /// A random convex polygon of `k` corners around the point a fraction of the way from `p`
    /// to `to`: points of a tilted ellipse at sorted random angles, in either direction.
    fn convex_on_the_way(r: &mut impl FnMut() -> f64, p: DVec3, to: DVec3, k: usize) -> Vec<DVec3> {
        let s = 0.2 + 0.7 * r();
        let at = p + (to - p) * s;
        let normal = DVec3::new(r() - 0.5, 1.0, r() - 0.5).normalize();
        let u = normal.any_orthonormal_vector();
        let v = normal.cross(u);
        let (a, b) = (0.8 * s * (0.1 + r()), 0.8 * s * (0.1 + r()));
        let mut t: Vec<f64> = (0..k).map(|_| TAU * r()).collect();
        t.sort_by(f64::total_cmp);
        let mut poly: Vec<DVec3> = t
            .iter()
            .map(|t| at + a * t.cos() * u + b * t.sin() * v)
            .collect();
        if r() < 0.5 {
            poly.reverse();
        }
        poly
    }

    /// `cap_misses_polygon` is sound and tight: where it says "misses", the polygon hides
    /// nothing of the cap (`cap_polygon` is 0) and no ray within α of the axis meets it;
    /// where the polygon hides some of the cap, it never says so. Random convex polygons of
    /// 3 to 8 corners around the cone, from small to much larger than the cap.
    #[test]
    fn cap_misses_polygon_only_where_nothing_is_hidden() {
        let mut r = stream(31);
        let (p, n) = (DVec3::new(0.1, 0.0, -0.2), DVec3::Y);
        let centre = DVec3::new(0.2, 1.6, 0.1);
        let d = (centre - p).length();
        let axis = (centre - p) / d;
        let (mut missed, mut hiding) = (0, 0);
        for case in 0..600 {
            let rad = 0.05 + 0.4 * r();
            let cos_a = (1.0 - rad * rad / (d * d)).sqrt();
            let k = 3 + case % 6;
            let scale = 0.2 + 4.0 * r();
            let poly: Vec<DVec3> = convex_on_the_way(&mut r, p, centre, k)
                .into_iter()
                .map(|v| centre * 0.5 + (v - centre * 0.5) * scale)
                .collect();
            let h = cap_polygon(p, n, axis, cos_a, &poly).unwrap();
            if cap_misses_polygon(p, axis, cos_a, &poly) {
                missed += 1;
                assert_eq!(h, 0.0, "case {case}");
                // Rays at the rim, in 64 directions, and the axis: none meets the polygon.
                let frame = lux_math::Frame::from_normal(axis);
                let sin_a = (1.0 - cos_a * cos_a).sqrt();
                for j in 0..=64 {
                    let phi = j as f64 / 64.0 * core::f64::consts::TAU;
                    let w = if j == 64 {
                        axis
                    } else {
                        frame.to_world(DVec3::new(sin_a * phi.cos(), sin_a * phi.sin(), cos_a))
                    };
                    let fan = (1..k - 1).map(|i| [poly[0], poly[i], poly[i + 1]]);
                    assert!(
                        !fan.clone().any(|t| meets(p, w, &t)),
                        "case {case}, ray {j}"
                    );
                }
            } else if h > 0.0 {
                hiding += 1;
            }
        }
        assert!(
            missed > 50 && hiding > 50,
            "missed {missed}, hiding {hiding}"
        );
    }

    #[test]
    fn a_convex_polygon_hides_what_its_fan_triangles_hide() {
        // cap_polygon, polygon_polygon and disk_polygon of a convex polygon of 4 to 8 corners
        // equal the sums over its fan triangles (which tile it without overlap), for random
        // polygons around each light's cone; `apart` holds between its fan triangles and fails
        // between the polygon and each of them.
        let mut r = stream(23);
        let (p, n) = (DVec3::new(0.1, 0.0, -0.2), DVec3::Y);
        let centre = DVec3::new(0.2, 1.6, 0.1);
        let rad = 0.4;
        let d = (centre - p).length();
        let axis = (centre - p) / d;
        let cos_a = (1.0 - rad * rad / (d * d)).sqrt();
        let cap = projected::sphere(p, n, centre, rad).unwrap();
        let rect = [
            DVec3::new(-0.3, 1.5, -0.2),
            DVec3::new(0.5, 1.6, -0.2),
            DVec3::new(0.6, 1.7, 0.4),
            DVec3::new(-0.2, 1.6, 0.4),
        ];
        let rect_pi = projected::polygon(p, n, &rect);
        let disk = (centre, DVec3::new(0.3, -1.0, 0.2).normalize(), rad);
        let disk_pi = projected::disk(p, n, disk.0, disk.1, disk.2).unwrap();
        let mut partial = [0usize; 3];
        for case in 0..300 {
            let k = 4 + case % 5;
            let poly = convex_on_the_way(&mut r, p, centre, k);
            let fan: Vec<[DVec3; 3]> = (1..k - 1)
                .map(|i| [poly[0], poly[i], poly[i + 1]])
                .collect();
            let h = cap_polygon(p, n, axis, cos_a, &poly).unwrap();
            let sum: f64 = fan
                .iter()
                .map(|t| cap_triangle(p, n, axis, cos_a, t).unwrap())
                .sum();
            assert!(
                (h - sum).abs() <= 1e-10 * cap,
                "case {case}: cap {h} vs fan {sum}"
            );
            let h = polygon_polygon(p, n, &rect, &poly);
            let sum: f64 = fan.iter().map(|t| polygon_triangle(p, n, &rect, t)).sum();
            assert!(
                (h - sum).abs() <= 1e-10 * rect_pi,
                "case {case}: rect {h} vs fan {sum}"
            );
            let parts: Option<Vec<f64>> =
                fan.iter().map(|t| disk_triangle(p, n, disk, t)).collect();
            if let (Some(h), Some(parts)) = (disk_polygon(p, n, disk, &poly), parts) {
                let sum: f64 = parts.iter().sum();
                assert!(
                    (h - sum).abs() <= 1e-10 * disk_pi,
                    "case {case}: disk {h} vs fan {sum}"
                );
                partial[2] += (h > 0.0 && h < 0.999 * disk_pi) as usize;
            }
            let hc = cap_polygon(p, n, axis, cos_a, &poly).unwrap();
            partial[0] += (hc > 0.0 && hc < 0.999 * cap) as usize;
            let hr = polygon_polygon(p, n, &rect, &poly);
            partial[1] += (hr > 0.0 && hr < 0.999 * rect_pi) as usize;
            assert!(apart(p, &fan[0], &fan[1]), "case {case}");
            assert!(
                fan.iter()
                    .all(|t| !apart(p, &poly, t) && !apart(p, t, &poly))
            );
        }
        // Most polygons hide part of each light (cut by its outline).
        assert!(partial.iter().all(|&c| c > 100), "{partial:?}");
        // More corners than MAX_CORNERS: no answer.
        let many = convex_on_the_way(&mut r, p, centre, MAX_CORNERS + 1);
        assert_eq!(cap_polygon(p, n, axis, cos_a, &many), None);
        assert_eq!(disk_polygon(p, n, disk, &many), None);
        assert_eq!(polygon_polygon(p, n, &rect, &many), 0.0);
        assert!(!apart(p, &many, &many[..3]));
    }
}
