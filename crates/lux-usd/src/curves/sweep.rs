//! Sweeping an evaluated curve into triangles: a round tube of diameter `widths` around it
//! (curves without `normals`), or a flat ribbon of width `widths` facing the authored normals
//! (UsdGeomBasisCurves, "Tubes and Ribbons": "Curves with only widths defined are imaged as
//! tubes with radius width / 2. Curves with both widths and normals are imaged as ribbons
//! oriented in the direction of the interpolated normal vectors").
//!
//! **Tubes.** A ring of `sides` vertices at every sample, in the plane perpendicular to the
//! tangent `T` (the mean of the directions of the two sample-to-sample chords meeting there).
//! Rings are oriented by a rotation-minimising frame (the double-reflection method of Wang,
//! Jüttler, Zheng and Liu, 2008), so tubes do not twist; on a closed curve the frame's
//! mismatch after one turn is spread evenly along the arc length. Where the chords meet at an
//! angle, the ring is stretched along the bend by `1 / cos(half angle)` (a mitre, capped at
//! [`MITER_LIMIT`]) so that the tube keeps its radius around both chords. Open tubes are closed
//! by flat caps at the end samples (a fan over the ring: no vertex on the axis), so the surface
//! is closed and single-sided; an open curve that ends where it starts (a NURBS circle, a
//! bezier loop) is swept as a closed one, without caps meeting inside the tube. Shading normals are the smooth ring normals, tilted by the slope
//! of the radius (`normalize(o − r′·T)` for the ring direction `o` and `r′ = dr/ds`); caps get
//! the flat `±T`.
//!
//! **Ribbons.** Two vertices per sample at `p ± (w/2)·b`, `b = normalize(T × N)` for the
//! interpolated normal `N`; triangles wound so that their geometric normal is `N` made
//! perpendicular to the tangent, which is also the shading normal. Double-sided.

use glam::DVec3;

/// The largest stretch of a mitred ring (the ring of a joint turning by more than ~151° is
/// not stretched further and pinches a little).
pub const MITER_LIMIT: f64 = 4.0;

/// An evaluated curve: samples along it with their width (diameter) and, when authored, colour
/// and normal. All the vectors have one entry per sample (colours and normals may be empty).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CurvePath {
    /// Positions along the curve.
    pub points: Vec<DVec3>,
    /// Width (diameter) at each point.
    pub widths: Vec<f64>,
    /// `primvars:displayColor` at each point, or empty.
    pub colors: Vec<DVec3>,
    /// The ribbon normal at each point, or empty (a tube).
    pub normals: Vec<DVec3>,
    /// Whether the last point connects back to the first.
    pub closed: bool,
}

/// Triangles with per-corner shading normals and optional per-corner colours, in the space of
/// the curve's points.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tessellation {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Triangles, wound with `(b − a) × (c − a)` towards the front (outside of a tube or
    /// sphere, the normal side of a ribbon).
    pub triangles: Vec<[u32; 3]>,
    /// Unit shading normal per triangle corner.
    pub normals: Vec<[DVec3; 3]>,
    /// Colour per triangle corner, when the prim has `primvars:displayColor`.
    pub colors: Option<Vec<[DVec3; 3]>>,
    /// Whether the surface is open and seen from both sides (ribbons); tubes and spheres are
    /// closed and single-sided.
    pub double_sided: bool,
}

impl Tessellation {
    /// An empty tessellation, with colours or without.
    pub fn new(colored: bool) -> Tessellation {
        Tessellation {
            colors: colored.then(Vec::new),
            ..Tessellation::default()
        }
    }

    /// Adds a vertex; its index.
    pub fn vertex(&mut self, p: DVec3) -> u32 {
        self.positions.push(p);
        (self.positions.len() - 1) as u32
    }

    /// Adds a triangle with its corner normals and (when the tessellation has colours) corner
    /// colours.
    pub fn triangle(&mut self, t: [u32; 3], normals: [DVec3; 3], colors: [DVec3; 3]) {
        self.triangles.push(t);
        self.normals.push(normals);
        if let Some(c) = &mut self.colors {
            c.push(colors);
        }
    }
}

/// The path without repeated points (closer than 1e-12 of its size; a closed path's last
/// points equal to its first too), closed when it ends where it starts. `None` when fewer than
/// 2 distinct points remain (3 for a closed path), or every width is zero.
fn clean(path: &CurvePath) -> Option<CurvePath> {
    let size = path
        .points
        .iter()
        .fold(0.0f64, |m, p| m.max(p.abs().max_element()));
    let eps = 1e-12 * size.max(f64::MIN_POSITIVE);
    let mut out = CurvePath {
        closed: path.closed,
        ..CurvePath::default()
    };
    for (i, p) in path.points.iter().enumerate() {
        if out.points.last().is_some_and(|q| (*p - *q).length() <= eps) {
            continue;
        }
        out.points.push(*p);
        out.widths.push(path.widths[i]);
        if !path.colors.is_empty() {
            out.colors.push(path.colors[i]);
        }
        if !path.normals.is_empty() {
            out.normals.push(path.normals[i]);
        }
    }
    // An open path ending where it starts (a NURBS circle, a bezier loop) is swept closed: one
    // seamless tube instead of two caps meeting inside it.
    if !out.closed
        && out.points.len() > 3
        && (out.points[out.points.len() - 1] - out.points[0]).length() <= eps
    {
        out.closed = true;
    }
    while out.closed
        && out.points.len() > 1
        && (out.points[out.points.len() - 1] - out.points[0]).length() <= eps
    {
        out.points.pop();
        out.widths.pop();
        out.colors.truncate(out.points.len());
        out.normals.truncate(out.points.len());
    }
    let min = if out.closed { 3 } else { 2 };
    (out.points.len() >= min && out.widths.iter().any(|w| *w > 0.0)).then_some(out)
}

/// A unit vector perpendicular to the unit `t`.
fn perpendicular(t: DVec3) -> DVec3 {
    let a = t.abs();
    let axis = if a.x <= a.y && a.x <= a.z {
        DVec3::X
    } else if a.y <= a.z {
        DVec3::Y
    } else {
        DVec3::Z
    };
    (axis - axis.dot(t) * t).normalize()
}

/// Tangents and mitres of a cleaned path.
struct Frames {
    /// Unit tangent per point.
    tangent: Vec<DVec3>,
    /// Per point: the unit bend direction (perpendicular to the tangent) and the stretch along
    /// it, for joints between chords that are not parallel.
    miter: Vec<Option<(DVec3, f64)>>,
    /// Unit ring axis `u` per point (rotation-minimising); the other is `tangent × u`.
    u: Vec<DVec3>,
}

fn frames(p: &CurvePath) -> Frames {
    let n = p.points.len();
    let chords = if p.closed { n } else { n - 1 };
    let dir: Vec<DVec3> = (0..chords)
        .map(|i| (p.points[(i + 1) % n] - p.points[i]).normalize())
        .collect();
    let mut tangent = Vec::with_capacity(n);
    let mut miter = Vec::with_capacity(n);
    for i in 0..n {
        let incoming = if i > 0 {
            Some(dir[i - 1])
        } else if p.closed {
            Some(dir[n - 1])
        } else {
            None
        };
        let outgoing = (i < chords).then(|| dir[i]);
        let (t, m) = match (incoming, outgoing) {
            (Some(a), Some(b)) => {
                let t = (a + b).normalize_or_zero();
                if t == DVec3::ZERO {
                    (b, None)
                } else {
                    let bend = b - a;
                    let m = (bend.length() > 1e-12).then(|| {
                        let k = 1.0 / t.dot(a).max(1.0 / MITER_LIMIT);
                        (bend.normalize(), k)
                    });
                    (t, m)
                }
            }
            (Some(a), None) => (a, None),
            (None, Some(b)) => (b, None),
            (None, None) => unreachable!("a cleaned path has at least 2 points"),
        };
        tangent.push(t);
        miter.push(m);
    }
    // Arc length along the chords from point 0, and of the whole (closed) path.
    let mut s = Vec::with_capacity(n);
    let mut acc = 0.0;
    for i in 0..n {
        if i > 0 {
            acc += (p.points[i] - p.points[i - 1]).length();
        }
        s.push(acc);
    }
    let total = if p.closed {
        acc + (p.points[0] - p.points[n - 1]).length()
    } else {
        acc
    };
    // Double reflection: reflect the frame in the bisector plane of the chord, then in the one
    // taking the reflected tangent onto the next tangent.
    let transport = |u: DVec3, from: usize, to: usize| -> DVec3 {
        let v1 = p.points[to] - p.points[from];
        let c1 = v1.dot(v1);
        let r_l = u - (2.0 / c1) * v1.dot(u) * v1;
        let t_l = tangent[from] - (2.0 / c1) * v1.dot(tangent[from]) * v1;
        let v2 = tangent[to] - t_l;
        let c2 = v2.dot(v2);
        let next = if c2 > 1e-30 {
            r_l - (2.0 / c2) * v2.dot(r_l) * v2
        } else {
            r_l
        };
        let next = next - next.dot(tangent[to]) * tangent[to];
        next.try_normalize()
            .unwrap_or_else(|| perpendicular(tangent[to]))
    };
    let mut u = Vec::with_capacity(n);
    u.push(perpendicular(tangent[0]));
    for i in 1..n {
        let next = transport(u[i - 1], i - 1, i);
        u.push(next);
    }
    if p.closed {
        let back = transport(u[n - 1], n - 1, 0);
        let t0 = tangent[0];
        let phi = back.cross(u[0]).dot(t0).atan2(back.dot(u[0]));
        for i in 1..n {
            let a = phi * s[i] / total;
            let w = tangent[i].cross(u[i]);
            u[i] = u[i] * a.cos() + w * a.sin();
        }
    }
    Frames { tangent, miter, u }
}

/// Sweeps a round tube of `sides` sides (at least 3) along `path` into `out`. `false` (nothing
/// added) when the path is degenerate: fewer than 2 distinct points (3 when closed) or zero
/// width everywhere.
pub fn tube(path: &CurvePath, sides: usize, out: &mut Tessellation) -> bool {
    let Some(p) = clean(path) else {
        return false;
    };
    let sides = sides.max(3);
    let n = p.points.len();
    let f = frames(&p);
    let colored = !p.colors.is_empty();
    let color = |i: usize| if colored { p.colors[i] } else { DVec3::ZERO };
    let radius = |i: usize| p.widths[i] / 2.0;
    // dr/ds by differences along the chords.
    let dist = |a: usize, b: usize| (p.points[b] - p.points[a]).length();
    let slope = |i: usize| -> f64 {
        let prev = if i > 0 {
            Some(i - 1)
        } else {
            p.closed.then_some(n - 1)
        };
        let next = if i + 1 < n {
            Some(i + 1)
        } else {
            p.closed.then_some(0)
        };
        let (a, b, ds) = match (prev, next) {
            (Some(a), Some(b)) => (a, b, dist(a, i) + dist(i, b)),
            (Some(a), None) => (a, i, dist(a, i)),
            (None, Some(b)) => (i, b, dist(i, b)),
            (None, None) => return 0.0,
        };
        if ds > 0.0 {
            (radius(b) - radius(a)) / ds
        } else {
            0.0
        }
    };
    let base = out.positions.len() as u32;
    let mut ring_normals = Vec::with_capacity(n * sides);
    for i in 0..n {
        let t = f.tangent[i];
        let u = f.u[i];
        let w = t.cross(u);
        let r = radius(i);
        let dr = slope(i);
        for j in 0..sides {
            let a = std::f64::consts::TAU * j as f64 / sides as f64;
            let o = u * a.cos() + w * a.sin();
            let stretched = match f.miter[i] {
                Some((m, k)) => o + (k - 1.0) * o.dot(m) * m,
                None => o,
            };
            out.vertex(p.points[i] + r * stretched);
            ring_normals.push((o - dr * t).normalize());
        }
    }
    let v = |i: usize, j: usize| base + (i * sides + j % sides) as u32;
    let nv = |i: usize, j: usize| ring_normals[i * sides + j % sides];
    let quads = if p.closed { n } else { n - 1 };
    for i in 0..quads {
        let k = (i + 1) % n;
        let (ci, ck) = (color(i), color(k));
        for j in 0..sides {
            let (a, b, c, d) = (v(i, j), v(k, j), v(k, j + 1), v(i, j + 1));
            if radius(i) > 0.0 {
                out.triangle(
                    [a, d, c],
                    [nv(i, j), nv(i, j + 1), nv(k, j + 1)],
                    [ci, ci, ck],
                );
            }
            if radius(k) > 0.0 {
                out.triangle([a, c, b], [nv(i, j), nv(k, j + 1), nv(k, j)], [ci, ck, ck]);
            }
        }
    }
    if !p.closed {
        for (i, sign) in [(0, -1.0), (n - 1, 1.0)] {
            if radius(i) <= 0.0 {
                continue;
            }
            let normal = sign * f.tangent[i];
            let c = color(i);
            for j in 1..sides - 1 {
                let tri = if sign > 0.0 {
                    [v(i, 0), v(i, j), v(i, j + 1)]
                } else {
                    [v(i, 0), v(i, j + 1), v(i, j)]
                };
                out.triangle(tri, [normal; 3], [c; 3]);
            }
        }
    }
    true
}

/// Sweeps a flat ribbon along `path` (whose `normals` must be set) into `out`, facing the
/// normals. `false` (nothing added) when the path is degenerate.
pub fn ribbon(path: &CurvePath, out: &mut Tessellation) -> bool {
    let Some(p) = clean(path) else {
        return false;
    };
    if p.normals.len() != p.points.len() {
        return false;
    }
    let n = p.points.len();
    let f = frames(&p);
    let colored = !p.colors.is_empty();
    let base = out.positions.len() as u32;
    let mut facing = Vec::with_capacity(n);
    let mut previous: Option<DVec3> = None;
    for i in 0..n {
        let t = f.tangent[i];
        let b = t
            .cross(p.normals[i])
            .try_normalize()
            .or(previous)
            .unwrap_or_else(|| t.cross(f.u[i]));
        previous = Some(b);
        let h = p.widths[i] / 2.0;
        out.vertex(p.points[i] - h * b);
        out.vertex(p.points[i] + h * b);
        facing.push(b.cross(t).normalize());
    }
    let quads = if p.closed { n } else { n - 1 };
    for i in 0..quads {
        let k = (i + 1) % n;
        let (li, ri) = (base + 2 * i as u32, base + 2 * i as u32 + 1);
        let (lk, rk) = (base + 2 * k as u32, base + 2 * k as u32 + 1);
        let (ci, ck) = if colored {
            (p.colors[i], p.colors[k])
        } else {
            (DVec3::ZERO, DVec3::ZERO)
        };
        if p.widths[i] > 0.0 {
            out.triangle(
                [li, ri, lk],
                [facing[i], facing[i], facing[k]],
                [ci, ci, ck],
            );
        }
        if p.widths[k] > 0.0 {
            out.triangle(
                [ri, rk, lk],
                [facing[i], facing[k], facing[k]],
                [ci, ck, ck],
            );
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn signed_volume(t: &Tessellation) -> f64 {
        t.triangles
            .iter()
            .map(|tri| {
                let [a, b, c] = tri.map(|k| t.positions[k as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    fn path(points: Vec<DVec3>, width: f64, closed: bool) -> CurvePath {
        CurvePath {
            widths: vec![width; points.len()],
            points,
            closed,
            ..CurvePath::default()
        }
    }

    #[test]
    fn straight_tube_is_a_closed_outward_prism() {
        let p = path(vec![DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0)], 0.5, false);
        let mut t = Tessellation::new(false);
        assert!(tube(&p, 12, &mut t));
        // 12 quads + 2 caps of 10 triangles.
        assert_eq!(t.triangles.len(), 2 * 12 + 2 * 10);
        // A regular 12-gon prism of circumradius 0.25 and length 2, wound outward.
        let exact = 0.5 * 12.0 * 0.25f64.powi(2) * (std::f64::consts::TAU / 12.0).sin() * 2.0;
        assert!(
            (signed_volume(&t) - exact).abs() < 1e-12,
            "{}",
            signed_volume(&t)
        );
        for q in &t.positions {
            assert!(((q.y * q.y + q.z * q.z).sqrt() - 0.25).abs() < 1e-15);
        }
    }

    #[test]
    fn closed_tube_is_closed_and_untwisted() {
        // A square loop: the frame after one turn matches, and the tube encloses volume.
        let sq = vec![
            DVec3::ZERO,
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(4.0, 4.0, 1.0),
            DVec3::new(0.0, 4.0, 1.0),
        ];
        let mut t = Tessellation::new(false);
        assert!(tube(&path(sq, 0.5, true), 8, &mut t));
        assert_eq!(t.triangles.len(), 4 * 2 * 8);
        assert!(signed_volume(&t) > 0.0);
        // Every edge is shared by exactly two triangles in opposite directions: watertight.
        let mut edges = std::collections::HashMap::new();
        for tri in &t.triangles {
            for k in 0..3 {
                *edges.entry((tri[k], tri[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &c) in &edges {
            assert_eq!(c, 1);
            assert_eq!(edges.get(&(b, a)), Some(&1));
        }
    }

    #[test]
    fn ribbon_faces_its_normal() {
        let mut p = path(
            vec![DVec3::ZERO, DVec3::X, DVec3::new(2.0, 0.5, 0.0)],
            0.2,
            false,
        );
        p.normals = vec![DVec3::Z; 3];
        let mut t = Tessellation::new(false);
        assert!(ribbon(&p, &mut t));
        for (tri, n) in t.triangles.iter().zip(&t.normals) {
            let [a, b, c] = tri.map(|k| t.positions[k as usize]);
            assert!((b - a).cross(c - a).normalize().dot(DVec3::Z) > 1.0 - 1e-12);
            assert!(n.iter().all(|n| (*n - DVec3::Z).length() < 1e-12));
        }
    }

    #[test]
    fn degenerate_paths_draw_nothing() {
        let mut t = Tessellation::new(false);
        assert!(!tube(&path(vec![DVec3::ONE; 3], 1.0, false), 8, &mut t));
        assert!(!tube(
            &path(vec![DVec3::ZERO, DVec3::X], 0.0, false),
            8,
            &mut t
        ));
        assert!(!tube(
            &path(vec![DVec3::ZERO, DVec3::X], 1.0, true),
            8,
            &mut t
        ));
        assert!(t.triangles.is_empty());
    }
}
