//! Planar meshes that tile a convex polygon, as shadow rays see them.
//!
//! A shadow ray asks only whether something blocks it (and, for shadow linking and shadow
//! falloff, which mesh and how far). A flat card subdivided into a grid of `n` triangles —
//! floors, walls, the luxtest occluders (162 triangles each) — blocks exactly what its outline
//! blocks; when that outline is a convex polygon of `k` corners, its `k − 2` fan triangles
//! answer every shadow ray and cone search as the `n` triangles do, from a much smaller BVH.
//!
//! [`tiled_hull`] proves the tiling before replacing anything: every vertex on one plane, every
//! triangle wound the same way around its normal, each directed edge used once, every edge
//! without a reversed twin (the mesh's boundary) on the boundary of the vertices' convex hull,
//! and the triangles' areas summing to the hull's. Then the winding number of the triangles is
//! constant inside the hull (it changes only across boundary edges), and the areas make it 1:
//! the triangles cover the hull exactly once, no more and no less.

use glam::{DVec2, DVec3};
use std::collections::{HashMap, HashSet};

/// Relative tolerance of the planarity, boundary and area tests (of the mesh's extent, its
/// hull's area): far above `f64` rounding of `f32` input, far below any real gap.
const TOLERANCE: f64 = 1e-9;

/// The fan triangles of the convex polygon that the triangles of a planar mesh tile exactly
/// (see the module doc), corners among the mesh's own points; `None` when the mesh is not such
/// a tiling (any non-finite or out-of-range vertex, a vertex off the plane, a triangle wound
/// the other way, an edge used twice, a boundary edge inside the hull, areas that do not sum to
/// the hull's) or when the fan would not have fewer triangles. Zero-area triangles are left out
/// first, as the BVH leaves them out.
pub(super) fn tiled_hull(positions: &[DVec3], triangles: &[[u32; 3]]) -> Option<Vec<[DVec3; 3]>> {
    let point = |i: u32| positions.get(i as usize).copied().filter(|p| p.is_finite());
    let mut tris = Vec::with_capacity(triangles.len());
    let mut normal = DVec3::ZERO;
    for t in triangles {
        let [a, b, c] = [point(t[0])?, point(t[1])?, point(t[2])?];
        let n = (b - a).cross(c - a);
        if n.length_squared() > 0.0 {
            normal += n;
            tris.push(*t);
        }
    }
    if tris.len() < 3 {
        return None;
    }
    let n = normal.try_normalize()?;
    // The plane's frame, through the first vertex.
    let origin = point(tris[0][0])?;
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for t in &tris {
        for &i in t {
            let p = point(i)?;
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    let extent = (hi - lo).max_element().max(f64::MIN_POSITIVE);
    let eps = TOLERANCE * extent;
    let mut flat: HashMap<u32, DVec2> = HashMap::new();
    for t in &tris {
        for &i in t {
            let d = point(i)? - origin;
            if n.dot(d).abs() > eps {
                return None;
            }
            flat.insert(i, DVec2::new(u.dot(d), v.dot(d)));
        }
    }
    // One winding, each directed edge once; the edges without a reversed twin are the
    // boundary.
    let mut edges: HashSet<(u32, u32)> = HashSet::with_capacity(3 * tris.len());
    let mut area = 0.0;
    for t in &tris {
        let [a, b, c] = t.map(|i| flat[&i]);
        let twice = (b - a).perp_dot(c - a);
        if twice <= 0.0 {
            return None;
        }
        area += 0.5 * twice;
        for e in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            if !edges.insert(e) {
                return None;
            }
        }
    }
    let mut ids: Vec<u32> = flat.keys().copied().collect();
    ids.sort_unstable();
    let hull = convex_hull(&ids, &flat, eps * extent);
    if hull.len() < 3 || hull.len() - 2 >= tris.len() {
        return None;
    }
    let ring: Vec<DVec2> = hull.iter().map(|i| flat[i]).collect();
    let hull_area = polygon_area(&ring);
    if hull_area.is_nan() || hull_area <= 0.0 || (area - hull_area).abs() > TOLERANCE * hull_area {
        return None;
    }
    for &(i, j) in &edges {
        if !edges.contains(&(j, i)) && !on_boundary(&ring, flat[&i], flat[&j], eps) {
            return None;
        }
    }
    let corner = |k: usize| positions[hull[k] as usize];
    Some(
        (1..hull.len() - 1)
            .map(|k| [corner(0), corner(k), corner(k + 1)])
            .collect(),
    )
}

/// The convex hull of the points `ids` counter-clockwise, without points within `tol` (a
/// cross product: length²) of collinear (Andrew's monotone chain on `f64` coordinates).
pub(super) fn convex_hull(ids: &[u32], flat: &HashMap<u32, DVec2>, tol: f64) -> Vec<u32> {
    let mut order = ids.to_vec();
    order.sort_by(|a, b| {
        let (p, q) = (flat[a], flat[b]);
        p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y))
    });
    let turn = |o: u32, a: u32, b: u32| (flat[&a] - flat[&o]).perp_dot(flat[&b] - flat[&o]);
    // The lower chain left to right, then the upper one back; each chain's last point is the
    // other's first.
    let mut hull: Vec<u32> = Vec::with_capacity(order.len() + 1);
    let mut chain = |points: &mut dyn Iterator<Item = &u32>| {
        let start = hull.len();
        for &p in points {
            while hull.len() >= start + 2
                && turn(hull[hull.len() - 2], hull[hull.len() - 1], p) <= tol
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    };
    chain(&mut order.iter());
    chain(&mut order.iter().rev());
    hull
}

/// The area of the counter-clockwise polygon `ring` (shoelace formula).
fn polygon_area(ring: &[DVec2]) -> f64 {
    let n = ring.len();
    0.5 * (0..n)
        .map(|k| ring[k].perp_dot(ring[(k + 1) % n]))
        .sum::<f64>()
}

/// Whether the segment `a`–`b` lies on one edge of the convex polygon `ring` (both ends within
/// `eps` of the edge's line and between its ends).
fn on_boundary(ring: &[DVec2], a: DVec2, b: DVec2, eps: f64) -> bool {
    let n = ring.len();
    (0..n).any(|k| {
        let (p, q) = (ring[k], ring[(k + 1) % n]);
        let d = q - p;
        let len = d.length();
        let near = |x: DVec2| {
            let s = (x - p).dot(d) / (len * len);
            (d.perp_dot(x - p) / len).abs() <= eps && (-eps / len..=1.0 + eps / len).contains(&s)
        };
        len > 0.0 && near(a) && near(b)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An `nx × nz` grid of quads over `[0, w] × [0, d]` in the plane `y = h`, two triangles
    /// each, wound counter-clockwise seen from +Y... or from −Y with `flip`.
    fn grid(nx: u32, nz: u32, w: f64, d: f64, flip: bool) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let mut p = Vec::new();
        for j in 0..=nz {
            for i in 0..=nx {
                p.push(DVec3::new(
                    w * i as f64 / nx as f64,
                    0.5,
                    d * j as f64 / nz as f64,
                ));
            }
        }
        let at = |i: u32, j: u32| j * (nx + 1) + i;
        let mut t = Vec::new();
        for j in 0..nz {
            for i in 0..nx {
                let (a, b, c, e) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                if flip {
                    t.extend([[a, c, b], [a, e, c]]);
                } else {
                    t.extend([[a, b, c], [a, c, e]]);
                }
            }
        }
        (p, t)
    }

    fn area(tris: &[[DVec3; 3]]) -> f64 {
        tris.iter()
            .map(|[a, b, c]| 0.5 * (*b - *a).cross(*c - *a).length())
            .sum()
    }

    #[test]
    fn a_subdivided_card_becomes_two_triangles() {
        for flip in [false, true] {
            let (p, t) = grid(9, 9, 2.0, 1.5, flip);
            let fan = tiled_hull(&p, &t).expect("a 9 × 9 grid tiles its rectangle");
            assert_eq!(fan.len(), 2);
            assert!((area(&fan) - 3.0).abs() < 1e-12);
            // The corners are the card's.
            for v in fan.iter().flatten() {
                assert!(v.x == 0.0 || v.x == 2.0);
                assert!(v.z == 0.0 || v.z == 1.5);
                assert_eq!(v.y, 0.5);
            }
        }
        // Tilted out of every axis plane and moved: still exact.
        let (p, t) = grid(5, 3, 1.0, 1.0, false);
        let m = glam::DMat3::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1);
        let p: Vec<DVec3> = p
            .iter()
            .map(|&x| m * x + DVec3::new(40.0, -3.0, 7.0))
            .collect();
        assert_eq!(tiled_hull(&p, &t).map(|f| f.len()), Some(2));
    }

    #[test]
    fn meshes_that_do_not_tile_a_convex_polygon_stay() {
        let (p, t) = grid(4, 4, 1.0, 1.0, false);
        // A hole: one quad missing (its boundary edges lie inside the hull).
        let mut holed = t.clone();
        holed.drain(10..12);
        assert_eq!(tiled_hull(&p, &holed), None);
        // An L: three quads of a 2 × 2 grid (a concave outline).
        let (p2, t2) = grid(2, 2, 1.0, 1.0, false);
        assert_eq!(tiled_hull(&p2, &t2[..6]), None);
        // One triangle wound the other way.
        let mut turned = t.clone();
        turned[5].swap(1, 2);
        assert_eq!(tiled_hull(&p, &turned), None);
        // A triangle twice (a double cover of part of the card).
        let mut doubled = t.clone();
        doubled.push(t[0]);
        assert_eq!(tiled_hull(&p, &doubled), None);
        // A vertex lifted off the plane by 1e-6 of the size.
        let mut bent = p.clone();
        bent[12].y += 1e-6;
        assert_eq!(tiled_hull(&bent, &t), None);
        // Unwelded quads (each with its own corners): no shared edges, so every edge is
        // boundary, most inside the hull.
        let mut loose_p = Vec::new();
        let mut loose_t = Vec::new();
        for [a, b, c] in &t {
            let k = loose_p.len() as u32;
            loose_p.extend([p[*a as usize], p[*b as usize], p[*c as usize]]);
            loose_t.push([k, k + 1, k + 2]);
        }
        assert_eq!(tiled_hull(&loose_p, &loose_t), None);
        // A vertex index out of range or a NaN.
        let mut bad = t.clone();
        bad[3][0] = 999;
        assert_eq!(tiled_hull(&p, &bad), None);
        let mut nan = p.clone();
        nan[0].x = f64::NAN;
        assert_eq!(tiled_hull(&nan, &t), None);
        // Two triangles: nothing to gain.
        assert_eq!(tiled_hull(&p, &t[..2]), None);
    }

    #[test]
    fn a_fan_of_a_convex_polygon_with_inner_points() {
        // A hexagon around its centre (6 triangles) becomes its 4-triangle fan.
        let mut p = vec![DVec3::ZERO];
        for k in 0..6 {
            let a = std::f64::consts::TAU * k as f64 / 6.0;
            p.push(DVec3::new(a.cos(), 0.0, -a.sin()));
        }
        let t: Vec<[u32; 3]> = (0..6).map(|k| [0, 1 + k, 1 + (k + 1) % 6]).collect();
        let fan = tiled_hull(&p, &t).expect("a hexagon tiled from its centre");
        assert_eq!(fan.len(), 4);
        assert!((area(&fan) - 1.5 * 3f64.sqrt()).abs() < 1e-12);
    }
}
