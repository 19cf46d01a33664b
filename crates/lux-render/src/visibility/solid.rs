//! Closed convex meshes (a box, an icosphere, a faceted ball) as blockers of the exact
//! penumbrae: seen from a point outside, what they hide is their silhouette.
//!
//! A convex solid seen from a point `p` outside it projects to a convex spherical polygon
//! bounded by its silhouette: the edges between its faces turned towards `p` (outward normal
//! n, `n·(p − a) > 0`) and those turned away. A ray from `p` meets the solid iff its direction
//! lies in that polygon, and then it enters the solid before it meets the fan of triangles
//! spanned by the silhouette's corners (inside the solid, as every point of their convex
//! hull). So what the solid hides of a light is what that polygon hides, provided every
//! silhouette corner lies before the light (then so does the fan, and the entry before it) —
//! however many triangles the mesh has, one polygon's boundary integral, and no test that its
//! faces do not overlap. [`Solid::silhouette`] finds it by walking the faces turned towards
//! `p` around its rim.

use glam::DVec3;
use std::collections::HashMap;

/// Most triangles of a mesh taken as a closed convex solid (a level-3 icosphere has 1,280).
pub const MAX_SOLID_TRIANGLES: usize = 2048;

/// Most corners of a silhouette ([`Solid::silhouette`]).
pub const MAX_SILHOUETTE: usize = 96;

/// A closed convex mesh: its welded vertices and triangles (wound counter-clockwise about
/// their outward normals), their planes, and for each triangle edge the triangle across it.
#[derive(Clone, Debug)]
pub struct Solid {
    verts: Vec<DVec3>,
    tris: Vec<[u32; 3]>,
    /// Per triangle its plane, as four arrays (for [`Solid::silhouette`]'s vectorised test):
    /// the outward unit normal n's x, y, z and `n·a + ε`, a its first corner — a triangle
    /// turns towards a point only beyond ε of its plane.
    soa: [Vec<f64>; 4],
    /// Per triangle and edge i (from corner i to corner i + 1): the triangle across it.
    across: Vec<[u32; 3]>,
    /// Per mesh triangle (`PrimRef::tri`): its index in `tris`, `u32::MAX` for none.
    of_mesh: Vec<u32>,
    /// The vertices' mean c, the greatest distance of a vertex from it and the least of a
    /// triangle's plane: balls about c holding the solid and held by it.
    ball: (DVec3, f64, f64),
}

impl Solid {
    /// The closed convex solid that the triangles `tris` (each with its index in the mesh)
    /// make, or `None` when they do not make one: fewer than 4 or more than
    /// [`MAX_SOLID_TRIANGLES`], a degenerate triangle, a directed edge (between vertices of
    /// equal coordinates, each triangle wound about its normal turned away from the vertices'
    /// mean) used twice or without its reverse, a vertex more than 10⁻⁵ of the mesh's box
    /// diagonal before a triangle's plane, or the mean within 10⁻⁴ of it of a triangle's plane
    /// (a flat mesh).
    pub fn new(tris: &[(u32, [DVec3; 3])]) -> Option<Solid> {
        if tris.len() < 4 || tris.len() > MAX_SOLID_TRIANGLES {
            return None;
        }
        let mut index: HashMap<[u64; 3], u32> = HashMap::new();
        let mut verts = Vec::new();
        let mut weld = |v: DVec3| {
            *index
                .entry(v.to_array().map(f64::to_bits))
                .or_insert_with(|| {
                    verts.push(v);
                    verts.len() as u32 - 1
                })
        };
        let mut faces: Vec<[u32; 3]> = tris.iter().map(|(_, t)| t.map(&mut weld)).collect();
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for v in &verts {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
        let mean = verts.iter().sum::<DVec3>() / verts.len() as f64;
        let diag = (hi - lo).length();
        if !(diag > 0.0 && diag.is_finite()) {
            return None;
        }
        let mut planes = Vec::with_capacity(faces.len());
        let mut inner = f64::INFINITY;
        // (the vertices as three arrays: the test of every vertex against every plane below is
        // a loop the compiler vectorises)
        let [xs, ys, zs] = [0, 1, 2].map(|k| verts.iter().map(|v| v[k]).collect::<Vec<f64>>());
        let beyond = |n: DVec3, limit: f64| {
            let mut out = false;
            for ((x, y), z) in xs.iter().zip(&ys).zip(&zs) {
                out |= n.x * x + n.y * y + n.z * z > limit;
            }
            out
        };
        for f in &mut faces {
            let [a, b, c] = f.map(|i| verts[i as usize]);
            let mut n = (b - a).cross(c - a).try_normalize()?;
            if n.dot(a - mean) < 0.0 {
                n = -n;
                f.swap(1, 2);
            }
            let d = n.dot(a);
            if d - n.dot(mean) < 1e-4 * diag || beyond(n, d + 1e-5 * diag) {
                return None;
            }
            inner = inner.min(d - n.dot(mean));
            planes.push((n, d));
        }
        let outer = verts
            .iter()
            .map(|v| (*v - mean).length())
            .fold(0.0, f64::max);
        // (ε: coplanar triangles rounded to f32 differ in their planes by ~10⁻⁷ of the
        // coordinates; within ε of a plane a point sees the triangle edge-on either way)
        let edge_on = 1e-6 * (lo.abs().max(hi.abs()).max_element() + diag);
        let mut edges: HashMap<(u32, u32), u32> = HashMap::with_capacity(3 * faces.len());
        for (k, f) in faces.iter().enumerate() {
            for i in 0..3 {
                if edges.insert((f[i], f[(i + 1) % 3]), k as u32).is_some() {
                    return None;
                }
            }
        }
        let across = faces
            .iter()
            .map(|f| {
                let mut a = [0; 3];
                for i in 0..3 {
                    a[i] = *edges.get(&(f[(i + 1) % 3], f[i]))?;
                }
                Some(a)
            })
            .collect::<Option<Vec<_>>>()?;
        let top = tris.iter().map(|(i, _)| *i).max()? as usize;
        let mut of_mesh = vec![u32::MAX; top + 1];
        for (k, (i, _)) in tris.iter().enumerate() {
            of_mesh[*i as usize] = k as u32;
        }
        Some(Solid {
            verts,
            tris: faces,
            across,
            of_mesh,
            ball: (mean, outer, inner),
            soa: [
                planes.iter().map(|(n, _)| n.x).collect(),
                planes.iter().map(|(n, _)| n.y).collect(),
                planes.iter().map(|(n, _)| n.z).collect(),
                planes.iter().map(|(_, d)| *d + edge_on).collect(),
            ],
        })
    }

    /// A centre c and radii R ≥ r: the ball (c, R) holds the solid, the ball (c, r) lies
    /// inside it.
    pub fn balls(&self) -> (DVec3, f64, f64) {
        self.ball
    }

    /// The outward unit normal of the mesh triangle `tri` (`PrimRef::tri`).
    pub fn outward(&self, tri: usize) -> Option<DVec3> {
        let k = *self.of_mesh.get(tri)? as usize;
        let [x, y, z, _] = &self.soa;
        Some(DVec3::new(*x.get(k)?, y[k], z[k]))
    }

    /// The silhouette of the solid seen from `p` into `out` (room for [`MAX_SILHOUETTE`]), its
    /// corners in order (counter-clockwise seen from `p`), and their count; `None` when `p`
    /// lies before no triangle's plane by more than ε (10⁻⁶ of the solid's coordinates and
    /// size: inside the solid or on it), or the silhouette has more than [`MAX_SILHOUETTE`]
    /// corners. A triangle within ε of `p`'s plane counts as turned away: it is seen edge-on
    /// and hides nothing, and so the coplanar triangles of a face (their planes differing by
    /// the f32 rounding) all count alike — the faces towards `p` make one patch of the
    /// surface, whose rim is one loop, as for a convex solid seen from outside.
    pub fn silhouette(&self, p: DVec3, out: &mut [DVec3]) -> Option<usize> {
        // Which triangles turn towards p, 64 to a word (a loop the compiler vectorises).
        let mut toward = [0u64; MAX_SOLID_TRIANGLES / 64];
        let [nx, ny, nz, d] = &self.soa;
        let words = nx.len().div_ceil(64);
        for (w, word) in toward[..words].iter_mut().enumerate() {
            let lo = 64 * w;
            let hi = (lo + 64).min(nx.len());
            let mut bits = 0u64;
            for k in lo..hi {
                let t = nx[k] * p.x + ny[k] * p.y + nz[k] * p.z > d[k];
                bits |= (t as u64) << (k - lo);
            }
            *word = bits;
        }
        let is = |k: u32| toward[k as usize / 64] >> (k % 64) & 1 == 1;
        // A rim edge to start from: a triangle towards p across from one turned away (the
        // walk below checks it closes within MAX_SILHOUETTE edges).
        let mut start = None;
        'find: for (w, &word) in toward[..words].iter().enumerate() {
            let mut bits = word;
            while bits != 0 {
                let k = 64 * w + bits.trailing_zeros() as usize;
                bits &= bits - 1;
                for (i, &g) in self.across[k].iter().enumerate() {
                    if !is(g) {
                        start = Some((k, i));
                        break 'find;
                    }
                }
            }
        }
        let start = start?;
        let (mut f, mut i) = start;
        let mut len = 0;
        loop {
            if len == out.len().min(MAX_SILHOUETTE) {
                return None;
            }
            out[len] = self.verts[self.tris[f][i] as usize];
            len += 1;
            // The next rim edge starts where this one ends, b: turn about b through the
            // faces towards p.
            let b = self.tris[f][(i + 1) % 3];
            let mut j = (i + 1) % 3;
            let mut turns = 0;
            while is(self.across[f][j]) {
                f = self.across[f][j] as usize;
                j = self.tris[f].iter().position(|&v| v == b)?;
                turns += 1;
                if turns > 64 {
                    return None;
                }
            }
            i = j;
            if (f, i) == start {
                break;
            }
        }
        Some(len)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 12 triangles of the box [lo, hi], each with its index (either winding: the solid
    /// orients them).
    fn box_tris(lo: DVec3, hi: DVec3) -> Vec<(u32, [DVec3; 3])> {
        let mut tris = Vec::new();
        // Each face: the axis it is normal to, its side, its corners around it.
        for axis in 0..3 {
            for side in [lo[axis], hi[axis]] {
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let corner = |a: f64, b: f64| {
                    let mut x = DVec3::ZERO;
                    x[axis] = side;
                    x[u] = a;
                    x[v] = b;
                    x
                };
                let q = [
                    corner(lo[u], lo[v]),
                    corner(hi[u], lo[v]),
                    corner(hi[u], hi[v]),
                    corner(lo[u], hi[v]),
                ];
                tris.extend([[q[0], q[1], q[2]], [q[0], q[2], q[3]]]);
            }
        }
        tris.into_iter()
            .enumerate()
            .map(|(i, t)| (i as u32, t))
            .collect()
    }

    #[test]
    fn a_box_is_a_solid_and_an_open_dented_or_flat_one_is_not() {
        let (lo, hi) = (DVec3::new(-1.0, 0.0, 2.0), DVec3::new(0.5, 0.25, 3.0));
        let tris = box_tris(lo, hi);
        assert!(Solid::new(&tris).is_some());
        // Open: two triangles gone.
        assert!(Solid::new(&tris[2..]).is_none());
        // One triangle wound the other way is still the same surface.
        let mut flipped = tris.clone();
        flipped[5].1.swap(1, 2);
        assert!(Solid::new(&flipped).is_some());
        // A corner pushed in: closed, not convex.
        let mut dented = tris.clone();
        for v in dented.iter_mut().flat_map(|(_, t)| t.iter_mut()) {
            if *v == hi {
                *v = 0.9 * hi + 0.1 * lo;
            }
        }
        assert!(Solid::new(&dented).is_none());
        // A flat box: closed, no inside.
        assert!(Solid::new(&box_tris(lo, DVec3::new(hi.x, lo.y, hi.z))).is_none());
    }

    #[test]
    fn a_box_seen_from_outside_has_the_silhouette_of_its_faces_towards_the_point() {
        let solid = Solid::new(&box_tris(DVec3::ZERO, DVec3::ONE)).unwrap();
        let mut out = [DVec3::ZERO; MAX_SILHOUETTE];
        // Beyond a corner: three faces, a hexagon of the six other corners.
        let n = solid
            .silhouette(DVec3::new(2.0, 3.0, 4.0), &mut out)
            .unwrap();
        assert_eq!(n, 6);
        assert!(!out[..n].contains(&DVec3::ONE) && !out[..n].contains(&DVec3::ZERO));
        // Counter-clockwise seen from the point (a triangle so wound has its normal towards
        // it: a·(b × c) < 0 relative to it), every turn.
        let p = DVec3::new(2.0, 3.0, 4.0);
        for i in 0..n {
            let [a, b, c] = [0, 1, 2].map(|k| out[(i + k) % n] - p);
            assert!(a.cross(b).dot(c) < 0.0, "turn {i}");
        }
        // Straight above the top: its outline, a square.
        let n = solid
            .silhouette(DVec3::new(0.5, 5.0, 0.5), &mut out)
            .unwrap();
        assert_eq!(n, 4);
        assert!(out[..n].iter().all(|v| v.y == 1.0));
        // Before one face's plane and beside another's: a quad's two faces, six corners.
        let n = solid
            .silhouette(DVec3::new(0.5, 5.0, 2.0), &mut out)
            .unwrap();
        assert_eq!(n, 6);
        // Inside and on the surface: none.
        assert_eq!(solid.silhouette(DVec3::splat(0.5), &mut out), None);
        assert_eq!(solid.silhouette(DVec3::new(0.3, 1.0, 0.6), &mut out), None);
    }

    /// A latitude–longitude ball of radius 1 about `c`: `rings` bands of `segments` quads (two
    /// triangles each; one at the poles).
    fn uv_ball(c: DVec3, rings: u32, segments: u32) -> Vec<(u32, [DVec3; 3])> {
        let at = |i: u32, j: u32| {
            let (t, f) = (
                std::f64::consts::PI * i as f64 / rings as f64,
                std::f64::consts::TAU * j as f64 / segments as f64,
            );
            c + DVec3::new(t.sin() * f.cos(), t.cos(), t.sin() * f.sin())
        };
        let mut tris = Vec::new();
        for i in 0..rings {
            for j in 0..segments {
                let (a, b, cc, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
                if i > 0 {
                    tris.push([a, b, cc]);
                }
                if i + 1 < rings {
                    tris.push([a, cc, d]);
                }
            }
        }
        // (the poles and the seam as the same points: welded by their coordinates)
        let snap = |v: DVec3| (v * 1e9).round() / 1e9;
        tris.into_iter()
            .enumerate()
            .map(|(k, t)| (k as u32, t.map(snap)))
            .collect()
    }

    /// Whether the ray from `p` along `d` meets the triangle `t` (Möller–Trumbore).
    fn meets(p: DVec3, d: DVec3, t: &[DVec3; 3]) -> bool {
        let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
        let q = d.cross(e2);
        let det = e1.dot(q);
        if det.abs() < 1e-15 {
            return false;
        }
        let s = p - t[0];
        let u = s.dot(q) / det;
        let r = s.cross(e1);
        let v = d.dot(r) / det;
        u >= 0.0 && v >= 0.0 && u + v <= 1.0 && e2.dot(r) / det > 0.0
    }

    #[test]
    fn a_direction_is_inside_the_silhouette_exactly_when_its_ray_meets_the_solid() {
        let c = DVec3::new(0.3, -0.2, 0.5);
        let tris = uv_ball(c, 9, 14);
        let solid = Solid::new(&tris).expect("a latitude-longitude ball is a convex solid");
        let mut rng = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut out = [DVec3::ZERO; MAX_SILHOUETTE];
        let (mut hits, mut misses) = (0, 0);
        for _ in 0..40 {
            let dir = DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
            let p = c + dir * (1.3 + 3.0 * next());
            let n = solid.silhouette(p, &mut out).expect("seen from outside");
            let r: Vec<DVec3> = out[..n].iter().map(|v| *v - p).collect();
            for _ in 0..200 {
                // Directions about the ball's centre, within twice its angular radius.
                let to = (c - p).normalize();
                let d =
                    (to + 0.8 * DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5)).normalize();
                // (counter-clockwise seen from p: inside is (rᵢ × rᵢ₊₁)·d ≤ 0 for every edge)
                let inside = (0..n).all(|i| r[i].cross(r[(i + 1) % n]).dot(d) <= 0.0);
                let hit = tris.iter().any(|(_, t)| meets(p, d, t));
                assert_eq!(inside, hit, "from {p} along {d}");
                if hit {
                    hits += 1;
                } else {
                    misses += 1;
                }
            }
        }
        assert!(hits > 1000 && misses > 1000, "{hits} {misses}");
    }

    #[test]
    fn a_tilted_box_seen_from_the_plane_of_its_bottom_has_one_rim() {
        // A box turned about two axes, its corners rounded to f32 as the BVHs hold them (its
        // bottom's two triangles then lie on planes ~1e-7 apart), seen from points of the
        // plane of its bottom (a floor it rests on) all around it.
        let turn = glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.31, 0.0, 0.17);
        let at = DVec3::new(12.3, 4.56, -7.89);
        let tris: Vec<(u32, [DVec3; 3])> =
            box_tris(DVec3::new(-0.4, 0.0, -0.3), DVec3::new(0.4, 0.5, 0.3))
                .into_iter()
                .map(|(i, t)| (i, t.map(|v| (at + turn * v).as_vec3().as_dvec3())))
                .collect();
        let solid = Solid::new(&tris).expect("a box");
        let (up, right, ahead) = (turn * DVec3::Y, turn * DVec3::X, turn * DVec3::Z);
        let mut out = [DVec3::ZERO; MAX_SILHOUETTE];
        let mut checked = 0;
        for k in 0..64 {
            let a = k as f64 / 64.0 * std::f64::consts::TAU;
            let p = at + (right * a.cos() + ahead * a.sin()) * (0.55 + 0.3 * (k % 5) as f64);
            let n = solid.silhouette(p, &mut out).expect("outside, beside it");
            let r: Vec<DVec3> = out[..n].iter().map(|v| *v - p).collect();
            for j in 0..64 {
                // Directions above the floor towards the box.
                let b = j as f64 / 64.0 * std::f64::consts::TAU;
                let d = ((at + up * 0.25 - p).normalize()
                    + 0.5
                        * (right * b.cos() + up * (0.5 + 0.5 * b.sin()) + ahead * (1.7 * b).sin()))
                .normalize();
                if d.dot(up) <= 1e-3 {
                    continue;
                }
                let inside = (0..n).all(|i| r[i].cross(r[(i + 1) % n]).dot(d) <= 0.0);
                let hit = tris.iter().any(|(_, t)| meets(p, d, t));
                assert_eq!(inside, hit, "from {p} along {d}: {n} corners");
                checked += 1;
            }
        }
        assert!(checked > 2000, "{checked}");
    }
}
