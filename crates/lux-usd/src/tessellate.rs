//! Tessellation of the implicit UsdGeom gprims (Sphere, Cube, Cylinder, Cone, Capsule, Plane)
//! with their schema defaults, as right-handed triangle lists in local space.

use crate::mesh::Topology;
use glam::{DVec2, DVec3};

/// Segments around the axis of every surface of revolution.
pub const SEGMENTS: usize = 64;
/// Segments along a quarter circle (sphere and capsule caps).
pub const ARC_SEGMENTS: usize = 16;

/// Which local axis a gprim's `axis` attribute names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// `"X"`.
    X,
    /// `"Y"`.
    Y,
    /// `"Z"` (the default).
    Z,
}

impl Axis {
    /// Parses a `token axis`, `Z` when unauthored or unknown.
    pub fn parse(s: Option<&str>) -> Axis {
        match s {
            Some("X") => Axis::X,
            Some("Y") => Axis::Y,
            _ => Axis::Z,
        }
    }

    /// Maps a point built around +Z onto this axis by a cyclic (orientation-preserving)
    /// permutation of coordinates.
    fn map(self, p: DVec3) -> DVec3 {
        match self {
            Axis::Z => p,
            Axis::X => DVec3::new(p.z, p.x, p.y),
            Axis::Y => DVec3::new(p.y, p.z, p.x),
        }
    }
}

/// Revolves a profile `(ρ, z)` around +Z. The profile must run from the top of the shape to the
/// bottom along its surface, so that "down the profile" × "eastward" points outward.
fn revolve(profile: &[DVec2], axis: Axis) -> Topology {
    let n = SEGMENTS;
    let mut points = Vec::with_capacity(profile.len() * n);
    for q in profile {
        for j in 0..n {
            let phi = std::f64::consts::TAU * j as f64 / n as f64;
            points.push(axis.map(DVec3::new(q.x * phi.cos(), q.x * phi.sin(), q.y)));
        }
    }
    let mut triangles = Vec::new();
    for i in 0..profile.len() - 1 {
        for j in 0..n {
            let a = (i * n + j) as u32;
            let b = ((i + 1) * n + j) as u32;
            let c = ((i + 1) * n + (j + 1) % n) as u32;
            let d = (i * n + (j + 1) % n) as u32;
            for t in [[a, b, c], [a, c, d]] {
                let [p, q, r] = t.map(|k| points[k as usize]);
                if (q - p).cross(r - p).length_squared() > 0.0 {
                    triangles.push(t);
                }
            }
        }
    }
    finish(points, triangles)
}

fn finish(points: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Topology {
    let corners = (0..triangles.len()).map(|f| (f, [0, 0, 0])).collect();
    Topology {
        face_count: triangles.len(),
        points,
        triangles,
        corners,
        faces: None,
    }
}

/// An arc of `(ρ, z)` points on a circle of radius `r` centred at `(0, zc)`, polar angle from
/// `t0` to `t1` (0 = +Z).
fn arc(r: f64, zc: f64, t0: f64, t1: f64, steps: usize) -> impl Iterator<Item = DVec2> {
    (0..=steps).map(move |k| {
        let t = t0 + (t1 - t0) * k as f64 / steps as f64;
        // sin(π) is 1.2e-16, not 0: snap the poles onto the axis so that the revolved pole
        // copies coincide and their sliver triangles are dropped as degenerate.
        let s = t.sin();
        let s = if s.abs() < 1e-12 { 0.0 } else { s };
        DVec2::new(r * s, zc + r * t.cos())
    })
}

/// Smooth per-corner normals of a tessellated implicit surface: each corner gets the
/// area-weighted mean of the normals of the triangles around its point whose normal is within
/// `crease_deg` of its own triangle's, so curved surfaces shade smoothly while the edges of a
/// cube or of a cylinder's caps stay sharp. Unit vectors, corner order of `topo.triangles`.
pub fn crease_normals(topo: &Topology, crease_deg: f64) -> Vec<[DVec3; 3]> {
    let cos_crease = crease_deg.to_radians().cos();
    // Unnormalised (area-weighted) face normals and the triangles around each point.
    let face: Vec<DVec3> = topo
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|k| topo.points[k as usize]);
            (b - a).cross(c - a)
        })
        .collect();
    let mut around: Vec<Vec<u32>> = vec![Vec::new(); topo.points.len()];
    for (f, t) in topo.triangles.iter().enumerate() {
        for &k in t {
            around[k as usize].push(f as u32);
        }
    }
    topo.triangles
        .iter()
        .enumerate()
        .map(|(f, t)| {
            let nf = face[f].normalize_or_zero();
            t.map(|k| {
                let sum: DVec3 = around[k as usize]
                    .iter()
                    .map(|&g| face[g as usize])
                    .filter(|n| n.normalize_or_zero().dot(nf) >= cos_crease)
                    .sum();
                let n = sum.normalize_or_zero();
                if n == DVec3::ZERO { nf } else { n }
            })
        })
        .collect()
}

/// `UsdGeomSphere` of `radius` (default 1).
pub fn sphere(radius: f64) -> Topology {
    let p: Vec<DVec2> = arc(radius, 0.0, 0.0, std::f64::consts::PI, 2 * ARC_SEGMENTS).collect();
    revolve(&p, Axis::Z)
}

/// `UsdGeomCylinder` (`radius` 1, `height` 2, `axis` Z), closed with caps.
pub fn cylinder(radius: f64, height: f64, axis: Axis) -> Topology {
    let h = height / 2.0;
    let p = [
        DVec2::new(0.0, h),
        DVec2::new(radius, h),
        DVec2::new(radius, -h),
        DVec2::new(0.0, -h),
    ];
    revolve(&p, axis)
}

/// `UsdGeomCone` (`radius` 1, `height` 2, `axis` Z): apex at +height/2, capped base.
pub fn cone(radius: f64, height: f64, axis: Axis) -> Topology {
    let h = height / 2.0;
    let p = [
        DVec2::new(0.0, h),
        DVec2::new(radius, -h),
        DVec2::new(0.0, -h),
    ];
    revolve(&p, axis)
}

/// `UsdGeomCapsule` (`radius` 0.5, `height` 1 for the cylindrical part, `axis` Z).
pub fn capsule(radius: f64, height: f64, axis: Axis) -> Topology {
    let h = height / 2.0;
    let half = std::f64::consts::FRAC_PI_2;
    let mut p: Vec<DVec2> = arc(radius, h, 0.0, half, ARC_SEGMENTS).collect();
    p.extend(arc(radius, -h, half, std::f64::consts::PI, ARC_SEGMENTS));
    revolve(&p, axis)
}

/// `UsdGeomCube` of edge `size` (default 2), centred, faces outward.
pub fn cube(size: f64) -> Topology {
    let s = size / 2.0;
    let mut points = Vec::with_capacity(24);
    let mut triangles = Vec::with_capacity(12);
    for axis in [Axis::X, Axis::Y, Axis::Z] {
        for sign in [1.0, -1.0] {
            // A +Z face at z = s, corners CCW seen from +Z, mirrored for the −Z face.
            let base = points.len() as u32;
            let quad = [(-s, -s), (s, -s), (s, s), (-s, s)];
            for (x, y) in quad {
                let (x, y) = if sign > 0.0 { (x, y) } else { (y, x) };
                points.push(axis.map(DVec3::new(x, y, sign * s)));
            }
            triangles.push([base, base + 1, base + 2]);
            triangles.push([base, base + 2, base + 3]);
        }
    }
    finish(points, triangles)
}

/// `UsdGeomPlane` (`width` 2 along U, `length` 2 along V, `axis` Z = normal), front side towards
/// +axis. U/V are X/Y for axis Z, Z/Y for axis X, X/Z for axis Y.
pub fn plane(width: f64, length: f64, axis: Axis) -> Topology {
    let (w, l) = (width / 2.0, length / 2.0);
    let (u, v, n) = match axis {
        Axis::Z => (DVec3::X, DVec3::Y, DVec3::Z),
        Axis::X => (DVec3::Z, DVec3::Y, DVec3::X),
        Axis::Y => (DVec3::X, DVec3::Z, DVec3::Y),
    };
    let points = vec![-w * u - l * v, w * u - l * v, w * u + l * v, -w * u + l * v];
    let front = (points[1] - points[0]).cross(points[2] - points[0]).dot(n) > 0.0;
    let triangles = if front {
        vec![[0, 1, 2], [0, 2, 3]]
    } else {
        vec![[0, 2, 1], [0, 3, 2]]
    };
    finish(points, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_normals_are_radial_and_cube_edges_stay_sharp() {
        let t = sphere(2.0);
        let n = crease_normals(&t, 60.0);
        let mut worst: f64 = 1.0;
        for (tri, c) in t.triangles.iter().zip(&n) {
            for (k, v) in tri.iter().zip(c) {
                let radial = t.points[*k as usize].normalize();
                worst = worst.min(radial.dot(*v));
            }
        }
        // Averaged face normals of a 64 × 32 tessellation are within a few degrees of radial.
        assert!(worst > 0.995, "{worst}");
        let c = cube(2.0);
        for (tri, cn) in c.triangles.iter().zip(crease_normals(&c, 60.0)) {
            let [a, b, d] = tri.map(|k| c.points[k as usize]);
            let f = (b - a).cross(d - a).normalize();
            for v in cn {
                assert!((v - f).length() < 1e-12);
            }
        }
    }

    fn area_and_volume(t: &Topology) -> (f64, f64) {
        let mut a = 0.0;
        let mut v = 0.0;
        for tri in &t.triangles {
            let [p, q, r] = tri.map(|k| t.points[k as usize]);
            a += 0.5 * (q - p).cross(r - p).length();
            v += p.dot(q.cross(r)) / 6.0;
        }
        (a, v)
    }

    #[test]
    fn closed_shapes_face_outward_with_expected_size() {
        // Signed volume > 0 means every face winds outward.
        let (a, v) = area_and_volume(&cube(2.0));
        assert!((a - 24.0).abs() < 1e-12 && (v - 8.0).abs() < 1e-12);
        let (a, v) = area_and_volume(&sphere(1.0));
        assert!((a - 4.0 * std::f64::consts::PI).abs() / (4.0 * std::f64::consts::PI) < 0.01);
        assert!(v > 0.0 && (v - 4.0 / 3.0 * std::f64::consts::PI).abs() < 0.05);
        for axis in [Axis::X, Axis::Y, Axis::Z] {
            let (_, v) = area_and_volume(&cylinder(1.0, 2.0, axis));
            assert!(
                (v - 2.0 * std::f64::consts::PI).abs() < 0.02,
                "{axis:?} {v}"
            );
            let (_, v) = area_and_volume(&cone(1.0, 2.0, axis));
            assert!((v - 2.0 / 3.0 * std::f64::consts::PI).abs() < 0.01, "{v}");
            let (_, v) = area_and_volume(&capsule(0.5, 1.0, axis));
            let exact = std::f64::consts::PI * 0.25 + 4.0 / 3.0 * std::f64::consts::PI * 0.125;
            assert!((v - exact).abs() < 0.01, "{v} {exact}");
        }
        let p = plane(2.0, 4.0, Axis::Y);
        let (a, _) = area_and_volume(&p);
        assert!((a - 8.0).abs() < 1e-12);
        let [i, j, k] = p.triangles[0].map(|k| p.points[k as usize]);
        assert!((j - i).cross(k - i).y > 0.0);
    }
}
