//! `sizeFactor` of `inputs:normalize`: world-space surface areas and the distant-light factor.
//!
//! From the UsdLux 26.11 `inputs:normalize` doc: `L = L / sizeFactor`, where sizeFactor is 1 for
//! DomeLight/PortalLight, the world-space surface area (every scale of the transform stack
//! included) for area lights, and a function of the angle for DistantLight.
//!
//! Under an affine light-to-world map with linear part `A` (columns: images of local x, y, z):
//!
//! | light | [`Profile::Spec`] (exact) | [`Profile::HdEmbree`] (the reference's approximations) |
//! |---|---|---|
//! | rect | `w·h·‖A x̂ × A ŷ‖` | same |
//! | disk | `π r²·‖A x̂ × A ŷ‖` (exact under shear) | `π·‖r A x̂‖·‖r A ŷ‖` |
//! | sphere | ellipsoid with semi-axes `r·σᵢ(A)`: `4π R_G(b²c², c²a², a²b²)` | Thomsen p = 1.6 |
//! | cylinder | `‖L A x̂‖ ×` exact perimeter of the cross-section ellipse (images of the radial axes projected ⟂ the axis) | `‖L A x̂‖ ×` Ramanujan perimeter of `‖r A ŷ‖, ‖r A ẑ‖` |
//! | mesh | Σ ½‖(B−A)×(C−A)‖ of world triangles | same |
//!
//! Bad input: a non-finite transform or size, or a negative size, gives a size factor of 0 for
//! area lights ("a zero-area light"); [`crate::emission`] then emits 0. A singular transform
//! gives the area of the degenerate image, which is 0 only where the surface collapses: a rect
//! or disk flattened within its own plane has area 0, but a sphere squashed flat is a doubly
//! covered ellipse (2πr² for a unit squash of one axis) and a cylinder flattened across its
//! axis is a doubly covered strip (2·L·width), as the exact formulas give in the limit.

use crate::elliptic::{
    TraceForm, ellipse_perimeter_ramanujan, ellipse_perimeter_trace, ellipsoid_area_thomsen,
};
use crate::{LightShape, Profile};
use core::f64::consts::{FRAC_PI_2, PI};
use glam::{DMat3, DMat4, DVec3};

/// `sizeFactor` of `shape` under the light-to-world transform `xf` (glam column convention, see
/// [`crate::usd_matrix`]), regardless of whether `normalize` is on: the world-space area for area
/// lights, [`distant_size_factor`] for distant lights, 1 for dome and portal lights.
///
/// Always finite and ≥ 0. Invalid geometry (non-finite or negative sizes, non-finite transform)
/// gives 0 for area lights.
pub fn size_factor(shape: &LightShape, xf: &DMat4, profile: Profile) -> f64 {
    match shape {
        LightShape::Dome | LightShape::Portal { .. } => 1.0,
        LightShape::Distant { angle_deg } => distant_size_factor(*angle_deg, profile),
        _ => world_area(shape, xf, profile),
    }
}

/// World-space surface area of an area light (0 for dome, portal and distant lights).
///
/// See the module table for the formula per shape and profile. Always finite and ≥ 0.
pub fn world_area(shape: &LightShape, xf: &DMat4, profile: Profile) -> f64 {
    if !xf.is_finite() {
        return 0.0;
    }
    let a = DMat3::from_mat4(*xf);
    let area = match *shape {
        LightShape::Rect { width, height } => {
            if !valid(width) || !valid(height) {
                return 0.0;
            }
            rect_area(&a, width, height)
        }
        LightShape::Disk { radius } => {
            if !valid(radius) {
                return 0.0;
            }
            match profile {
                Profile::Spec => disk_area(&a, radius),
                Profile::HdEmbree => disk_area_reference(&a, radius),
            }
        }
        LightShape::Sphere { radius } => {
            if !valid(radius) {
                return 0.0;
            }
            match profile {
                Profile::Spec => sphere_area(&a, radius),
                Profile::HdEmbree => sphere_area_reference(&a, radius),
            }
        }
        LightShape::Cylinder { radius, length } => {
            if !valid(radius) || !valid(length) {
                return 0.0;
            }
            match profile {
                Profile::Spec => cylinder_area(&a, radius, length),
                Profile::HdEmbree => cylinder_area_reference(&a, radius, length),
            }
        }
        LightShape::Mesh { ref triangles } => mesh_area(xf, triangles),
        LightShape::Dome | LightShape::Portal { .. } | LightShape::Distant { .. } => 0.0,
    };
    if area.is_finite() && area > 0.0 {
        area
    } else {
        0.0
    }
}

#[inline]
fn valid(x: f64) -> bool {
    x.is_finite() && x >= 0.0
}

/// Rect: `w·h·‖A x̂ × A ŷ‖`, exact under any affine map (a parallelogram).
#[inline]
pub fn rect_area(a: &DMat3, width: f64, height: f64) -> f64 {
    width * height * a.x_axis.cross(a.y_axis).length()
}

/// Disk, exact: the image of a disk is an ellipse of area `π r²·‖A x̂ × A ŷ‖`, shear included.
#[inline]
pub fn disk_area(a: &DMat3, radius: f64) -> f64 {
    PI * radius * radius * a.x_axis.cross(a.y_axis).length()
}

/// Disk as the hdEmbree reference computes it: `π·‖r A x̂‖·‖r A ŷ‖` (ignores shear, so it
/// over-estimates a sheared disk).
#[inline]
pub fn disk_area_reference(a: &DMat3, radius: f64) -> f64 {
    PI * radius * radius * a.x_axis.length() * a.y_axis.length()
}

/// Sphere, exact: the image is an ellipsoid whose semi-axes are `r` times the singular values
/// of `A`; its area by Carlson's R_G ([`crate::ellipsoid_area`]). Rotation + uniform scale takes
/// the closed form `4π r² s²`.
pub fn sphere_area(a: &DMat3, radius: f64) -> f64 {
    let [l1, l2, l3] = gram_eigenvalues(a);
    let r2 = radius * radius;
    if l1 == l3 {
        return 4.0 * PI * r2 * l1;
    }
    // The semi-axes² are r²·λᵢ.
    crate::elliptic::ellipsoid_area_from_squares(r2 * l1, r2 * l2, r2 * l3)
}

/// Sphere as the hdEmbree reference computes it: Thomsen's p = 1.6 formula on the same
/// semi-axes (exact for uniform scale; within 1.1 % of exact while the semi-axis ratio is
/// ≥ 1/30, at most 1.18 % below it for needles, see [`crate::ellipsoid_area_thomsen`]).
pub fn sphere_area_reference(a: &DMat3, radius: f64) -> f64 {
    let [l1, l2, l3] = gram_eigenvalues(a);
    let r2 = radius * radius;
    ellipsoid_area_thomsen((r2 * l1).sqrt(), (r2 * l2).sqrt(), (r2 * l3).sqrt())
}

/// Cylinder lateral area, exact: `‖L·A x̂‖ × perimeter(E)`, where `E` is the ellipse spanned by
/// the images `r A ŷ`, `r A ẑ` of the radial axes projected onto the plane perpendicular to the
/// axis image `u = A x̂` (the right cross-section of the possibly oblique cylinder); its
/// perimeter is the complete elliptic integral of the second kind ([`crate::ellipse_perimeter`]).
///
/// Evaluated without projecting: with `p = u × A ŷ`, `q = u × A ẑ` the Gram matrix of the
/// projected pair is `G = G'/|u|²` where `G' = [p·p, p·q; p·q, q·q]` (Lagrange's identity,
/// free of cancellation). The perimeter is homogeneous of degree 1, so `|u|·P(G) = P(G')` and
/// the area is `L·r·P(G')`. The perimeter comes from the trace form
/// `P = √T·F_E(m)`, `T = tr G'`, `m = ((g11 − g22)² + 4g12²)/T²` (one division with the square
/// root beside it, then a table polynomial; see `elliptic::ellipse_perimeter_trace`); cross
/// sections flatter than b/a ≈ 0.23 take the Gauss–Kummer / AGM route through the semi-axes.
pub fn cylinder_area(a: &DMat3, radius: f64, length: f64) -> f64 {
    let u = a.x_axis;
    let p = u.cross(a.y_axis);
    let q = u.cross(a.z_axis);
    let (g11, g22, g12) = (p.length_squared(), q.length_squared(), p.dot(q));
    let d = g11 - g22;
    let per = ellipse_perimeter_trace(g11 + g22, d * d + 4.0 * (g12 * g12), TraceForm::Exact);
    match per {
        Some(per) => length * radius * per,
        None => cylinder_area_slow(a, radius, length, g11, g22, g12),
    }
}

/// [`cylinder_area`] for the inputs the trace form does not take: flat cross-sections, zero
/// or extreme scales, non-finite entries.
#[cold]
fn cylinder_area_slow(a: &DMat3, radius: f64, length: f64, g11: f64, g22: f64, g12: f64) -> f64 {
    let u = a.x_axis;
    let l2 = u.length_squared();
    if l2 == 0.0 || radius == 0.0 || length == 0.0 {
        return 0.0;
    }
    // the projected parallelogram: ab' = |u|²·|w₁ × w₂| = |det A|·|u|
    let ab = u.dot(a.y_axis.cross(a.z_axis)).abs() * l2.sqrt();
    length * radius * cross_section_perimeter(g11, g22, g12, ab)
}

/// Perimeter of the ellipse `{w1·cos t + w2·sin t}` from its Gram entries `g11 = |w1|²`,
/// `g22 = |w2|²`, `g12 = w1·w2` and `ab = |w1 × w2|` (the product of its semi-axes a ≥ b,
/// given separately to avoid cancellation): `(a + b)² = g11 + g22 + 2ab` and
/// `(a² − b²)² = (g11 − g22)² + 4g12²`, hence `h = ((a − b)/(a + b))² = (a² − b²)²/(a + b)⁴`
/// and `P = π(a + b)·GK(h)` by the piecewise polynomial of [`crate::elliptic`] (one square
/// root and one division). Cross-sections flatter than b/a = 0.0406 go through the eigenvalues
/// and the AGM.
fn cross_section_perimeter(g11: f64, g22: f64, g12: f64, ab: f64) -> f64 {
    let s = g11 + g22 + 2.0 * ab;
    if s.is_nan() || s <= 0.0 {
        return 0.0;
    }
    let inv_s = 1.0 / s;
    let d = g11 - g22;
    let h = ((d * d + 4.0 * g12 * g12) * inv_s) * inv_s;
    if let Some(gk) = crate::elliptic::gauss_kummer(h) {
        return PI * s.sqrt() * gk;
    }
    let (big, small) = sym2_eigenvalues(g11, g22, g12);
    crate::elliptic::ellipse_perimeter_agm(big.sqrt(), small.sqrt())
}

/// Cylinder as the hdEmbree reference computes it: `‖L·A x̂‖ ×` Ramanujan's perimeter of the
/// ellipse with semi-axes `‖r A ŷ‖`, `‖r A ẑ‖` (no projection).
///
/// Evaluated in the trace form of Ramanujan's formula, `P = √T·F_R(m)` with `T = a² + b²`,
/// `m = ((a² − b²)/T)²` from the squared lengths (same value to within an ulp or two; the
/// square roots of `‖A x̂‖²` and T and the division run side by side). Semi-axis ratios below
/// 0.233 and extreme scales use [`ellipse_perimeter_ramanujan`] on the lengths.
pub fn cylinder_area_reference(a: &DMat3, radius: f64, length: f64) -> f64 {
    let (y2, z2) = (a.y_axis.length_squared(), a.z_axis.length_squared());
    let d = y2 - z2;
    match ellipse_perimeter_trace(y2 + z2, d * d, TraceForm::Ramanujan) {
        Some(per) => length * radius * a.x_axis.length() * per,
        None => cylinder_area_reference_slow(a, radius, length),
    }
}

#[cold]
fn cylinder_area_reference_slow(a: &DMat3, radius: f64, length: f64) -> f64 {
    length
        * a.x_axis.length()
        * ellipse_perimeter_ramanujan(radius * a.y_axis.length(), radius * a.z_axis.length())
}

/// Mesh light: Σ ½‖(B−A)×(C−A)‖ over the world-space images of the local triangles.
/// Non-finite triangles are skipped.
///
/// Evaluated without transforming any point: for the linear part `A` (columns c₀, c₁, c₂),
/// `(A u) × (A v) = cof(A)·(u × v)` with the cofactor matrix `cof(A) = [c₁×c₂, c₂×c₀, c₀×c₁]`
/// (= det A · A⁻ᵀ), so each triangle costs one local cross product, one matrix–vector product
/// and one square root; the translation cancels in the edge vectors.
pub fn mesh_area(xf: &DMat4, triangles: &[[DVec3; 3]]) -> f64 {
    let a = DMat3::from_mat4(*xf);
    let cof = DMat3::from_cols(
        a.y_axis.cross(a.z_axis),
        a.z_axis.cross(a.x_axis),
        a.x_axis.cross(a.y_axis),
    );
    let mut sum = 0.0;
    for t in triangles {
        let n = (t[1] - t[0]).cross(t[2] - t[0]);
        let area = 0.5 * (cof * n).length();
        if area.is_finite() {
            sum += area;
        }
    }
    sum
}

/// DistantLight `sizeFactor` from `inputs:angle` (degrees, the angular diameter).
///
/// `θmax = clamp(radians(angle)/2, 0, π)` (this clips `angle` to \[0, 360\]); then
/// - θmax = 0: 1 (a delta light whose intensity is the illuminance in lux);
/// - 0 < θmax ≤ π/2: `π·sin²θmax`;
/// - π/2 < θmax ≤ π: [`Profile::Spec`] `π·(2 − sin²θmax)`; [`Profile::HdEmbree`] keeps
///   `π·sin²θmax` (the reference has no second branch; at θmax = π that is 0, and a light with a
///   zero size factor emits nothing).
///
/// A NaN angle is treated as 0 (delta light).
pub fn distant_size_factor(angle_deg: f64, profile: Profile) -> f64 {
    let theta_max = if angle_deg.is_nan() {
        0.0
    } else {
        (angle_deg.to_radians() * 0.5).clamp(0.0, PI)
    };
    if theta_max == 0.0 {
        return 1.0;
    }
    let s = theta_max.sin();
    let s2 = s * s;
    if theta_max <= FRAC_PI_2 || profile == Profile::HdEmbree {
        PI * s2
    } else {
        PI * (2.0 - s2)
    }
}

/// Eigenvalues of `AᵀA` (the squared singular values of `A`), largest first.
///
/// The largest comes from the trigonometric closed form for symmetric 3×3 matrices; the other
/// two from `λ₂ + λ₃ = tr − λ₁` and `λ₂λ₃ = det(A)²/λ₁`, which keeps the smallest accurate
/// for nearly flat maps.
pub fn gram_eigenvalues(a: &DMat3) -> [f64; 3] {
    let g = a.transpose() * *a;
    let (g00, g11, g22) = (g.x_axis.x, g.y_axis.y, g.z_axis.z);
    let (g01, g02, g12) = (g.y_axis.x, g.z_axis.x, g.z_axis.y);
    let p1 = g01 * g01 + g02 * g02 + g12 * g12;
    let tr = g00 + g11 + g22;
    let q = tr * (1.0 / 3.0);
    let p2 = (g00 - q).powi(2) + (g11 - q).powi(2) + (g22 - q).powi(2) + 2.0 * p1;
    if p2 <= 1e-30 * q * q {
        return [q, q, q];
    }
    let p = (p2 * (1.0 / 6.0)).sqrt();
    // B = (G − qI)/p; r = det(B)/2.
    // (one division: B's entries stay O(1), so det(B) cannot overflow)
    let inv_p = 1.0 / p;
    let (b00, b11, b22) = ((g00 - q) * inv_p, (g11 - q) * inv_p, (g22 - q) * inv_p);
    let (b01, b02, b12) = (g01 * inv_p, g02 * inv_p, g12 * inv_p);
    let det_b = b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02)
        + b02 * (b01 * b12 - b11 * b02);
    let r = (0.5 * det_b).clamp(-1.0, 1.0);
    let phi = r.acos() * (1.0 / 3.0);
    let l1 = (q + 2.0 * p * phi.cos()).max(0.0);
    if l1 == 0.0 {
        return [0.0, 0.0, 0.0];
    }
    let det_a = a.determinant();
    let prod23 = det_a * det_a / l1;
    let sum23 = (tr - l1).max(0.0);
    let disc = (sum23 * sum23 - 4.0 * prod23).max(0.0).sqrt();
    let l2 = 0.5 * (sum23 + disc);
    let l3 = if l2 > 0.0 { prod23 / l2 } else { 0.0 };
    [l1, l2.min(l1), l3.min(l2)]
}

/// Eigenvalues `(big, small)` of the symmetric 2×2 matrix `[[a, c], [c, b]]` (both ≥ 0 for a
/// Gram matrix); the small one via the determinant for accuracy.
#[inline]
fn sym2_eigenvalues(a: f64, b: f64, c: f64) -> (f64, f64) {
    let half_tr = 0.5 * (a + b);
    let d = (0.25 * (a - b) * (a - b) + c * c).sqrt();
    let big = half_tr + d;
    if big <= 0.0 {
        return (0.0, 0.0);
    }
    let small = ((a * b - c * c) / big).max(0.0);
    (big, small)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    #[test]
    fn identity_areas() {
        let i = DMat4::IDENTITY;
        let p = Profile::Spec;
        assert_eq!(
            size_factor(
                &LightShape::Rect {
                    width: 2.0,
                    height: 3.0
                },
                &i,
                p
            ),
            6.0
        );
        assert!(
            rel(
                size_factor(&LightShape::Disk { radius: 0.5 }, &i, p),
                PI * 0.25
            ) < 1e-15
        );
        assert!(rel(size_factor(&LightShape::Sphere { radius: 0.5 }, &i, p), PI) < 1e-15);
        assert!(
            rel(
                size_factor(
                    &LightShape::Cylinder {
                        radius: 0.5,
                        length: 2.0
                    },
                    &i,
                    p
                ),
                2.0 * PI
            ) < 1e-15
        );
        assert_eq!(size_factor(&LightShape::Dome, &i, p), 1.0);
        assert_eq!(
            size_factor(
                &LightShape::Portal {
                    width: 5.0,
                    height: 5.0
                },
                &i,
                p
            ),
            1.0
        );
        let tri = LightShape::Mesh {
            triangles: vec![[DVec3::ZERO, DVec3::X * 2.0, DVec3::Y * 3.0]],
        };
        assert_eq!(size_factor(&tri, &i, p), 3.0);
    }

    #[test]
    fn mesh_area_equals_transformed_triangles() {
        // A sheared, non-uniformly scaled, rotated, translated map; triangles of every
        // orientation, one degenerate. Compare with transforming the points themselves.
        let m = DMat4::from_rotation_translation(
            DQuat::from_euler(glam::EulerRot::XYZ, 0.4, -1.2, 2.0),
            DVec3::new(-3.0, 7.0, 0.5),
        ) * DMat4::from_scale(DVec3::new(0.3, 2.5, 1.7))
            * crate::usd_matrix([
                [1.0, 0.2, 0.0, 0.0],
                [0.7, 1.0, -0.4, 0.0],
                [0.0, 0.3, 1.0, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            ]);
        let tris = vec![
            [DVec3::ZERO, DVec3::X, DVec3::Y],
            [
                DVec3::new(1.0, 2.0, 3.0),
                DVec3::new(-2.0, 0.5, 1.0),
                DVec3::new(0.0, -1.0, 4.0),
            ],
            [
                DVec3::new(0.1, 0.1, 0.1),
                DVec3::new(0.2, 0.2, 0.2),
                DVec3::new(0.3, 0.3, 0.3),
            ],
            [DVec3::Z, DVec3::ZERO, DVec3::new(5.0, 0.0, 1.0)],
        ];
        let want: f64 = tris
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|p| m.transform_point3(p));
                0.5 * (b - a).cross(c - a).length()
            })
            .sum();
        let got = mesh_area(&m, &tris);
        assert!(rel(got, want) < 1e-14, "{got} vs {want}");
        let tri = LightShape::Mesh { triangles: tris };
        assert_eq!(size_factor(&tri, &m, Profile::Spec), got);
    }

    #[test]
    fn sheared_disk_exact_vs_reference() {
        // USD rows: x ↦ (1,0,0), y ↦ (1,1,0) (shear of y along x by 1).
        let m = crate::usd_matrix([
            [1.0, 0.0, 0.0, 0.0],
            [1.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ]);
        let d = LightShape::Disk { radius: 1.0 };
        // Shear preserves area: π exactly.
        assert!(rel(size_factor(&d, &m, Profile::Spec), PI) < 1e-15);
        // Reference: π·1·√2.
        assert!(rel(size_factor(&d, &m, Profile::HdEmbree), PI * 2f64.sqrt()) < 1e-15);
    }

    #[test]
    fn scaled_sphere_is_spheroid() {
        let m = DMat4::from_scale(DVec3::new(2.0, 2.0, 0.5));
        let a = DMat3::from_mat4(m);
        let e = (1.0f64 - 0.0625).sqrt();
        let expect = 2.0 * PI * 4.0 * (1.0 + (1.0 - e * e) / e * e.atanh());
        assert!(rel(sphere_area(&a, 1.0), expect) < 1e-13);
        // Rotated: the same.
        let r = DMat4::from_quat(DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 2.0));
        assert!(rel(sphere_area(&DMat3::from_mat4(r * m), 1.0), expect) < 1e-12);
        assert!(rel(sphere_area_reference(&a, 1.0), expect) < 0.011);
    }

    #[test]
    fn sheared_cylinder() {
        // Shear the radial axis y along the cylinder axis x: the right cross-section is unchanged
        // (a circle of radius r), only the slant grows: area is still 2πrL.
        let m = crate::usd_matrix([
            [1.0, 0.0, 0.0, 0.0],
            [0.7, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ]);
        let c = LightShape::Cylinder {
            radius: 0.5,
            length: 3.0,
        };
        assert!(rel(size_factor(&c, &m, Profile::Spec), 2.0 * PI * 0.5 * 3.0) < 1e-14);
        // Non-uniform radial scale: ellipse 2r × 0.5r, exact perimeter.
        let s = DMat4::from_scale(DVec3::new(1.0, 2.0, 0.5));
        let expect = 3.0 * crate::ellipse_perimeter(1.0, 0.25);
        assert!(rel(size_factor(&c, &s, Profile::Spec), expect) < 1e-14);
        let approx = 3.0 * ellipse_perimeter_ramanujan(1.0, 0.25);
        assert!(rel(size_factor(&c, &s, Profile::HdEmbree), approx) < 1e-14);
    }

    #[test]
    fn cylinder_cross_section_matches_eigenvalues_and_agm() {
        // The Gram-entry evaluations (trace form, and Gauss–Kummer for flatter cross-sections)
        // against the textbook route: semi-axes from the
        // eigenvalues of the projected radial axes' Gram matrix, perimeter by the AGM. Oblique,
        // sheared and rotated maps, cross-sections from circular to needle-flat (AGM fallback).
        let mut worst = 0.0f64;
        for i in 0..400 {
            let f = i as f64;
            let m = DMat4::from_quat(DQuat::from_euler(
                glam::EulerRot::XYZ,
                0.37 * f,
                -0.21 * f,
                0.13 * f,
            )) * DMat4::from_scale(DVec3::new(
                0.5 + (f * 0.7).sin().abs(),
                0.01 + 3.0 * (f * 1.3).cos().abs(),
                0.01 + 2.0 * (f * 0.9).sin().abs(),
            )) * crate::usd_matrix([
                [1.0, 0.3 * (f * 0.5).sin(), 0.0, 0.0],
                [0.6 * (f * 0.4).cos(), 1.0, 0.0, 0.0],
                [0.2, -0.5 * (f * 0.3).sin(), 1.0, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            ]);
            let a = DMat3::from_mat4(m);
            let (r, len) = (0.7, 2.5);
            let axis = a.x_axis;
            let u = axis / axis.length();
            let w1 = (a.y_axis - u * a.y_axis.dot(u)) * r;
            let w2 = (a.z_axis - u * a.z_axis.dot(u)) * r;
            let (big, small) =
                sym2_eigenvalues(w1.length_squared(), w2.length_squared(), w1.dot(w2));
            let want = len
                * axis.length()
                * crate::elliptic::ellipse_perimeter_agm(big.sqrt(), small.sqrt());
            worst = worst.max(rel(cylinder_area(&a, r, len), want));
        }
        // measured worst 1.15e-15 (the AGM's and the eigenvalues' own rounding)
        assert!(worst < 2e-15, "{worst}");
    }

    #[test]
    fn distant_branches() {
        let p = Profile::Spec;
        assert_eq!(distant_size_factor(0.0, p), 1.0);
        assert_eq!(distant_size_factor(-5.0, p), 1.0);
        assert_eq!(distant_size_factor(f64::NAN, p), 1.0);
        // angle 80 deg: π sin²(40°)
        let s = 40f64.to_radians().sin();
        assert!(rel(distant_size_factor(80.0, p), PI * s * s) < 1e-15);
        assert!(rel(distant_size_factor(180.0, p), PI) < 1e-15);
        // 270 deg: θmax = 135°, sin² = 1/2: spec 1.5π, reference 0.5π.
        assert!(rel(distant_size_factor(270.0, p), 1.5 * PI) < 1e-14);
        assert!(rel(distant_size_factor(270.0, Profile::HdEmbree), 0.5 * PI) < 1e-14);
        // clipped at 360: 2π, and beyond
        assert!(rel(distant_size_factor(360.0, p), 2.0 * PI) < 1e-15);
        assert!(rel(distant_size_factor(1000.0, p), 2.0 * PI) < 1e-15);
    }

    #[test]
    fn bad_input_is_zero_area() {
        let i = DMat4::IDENTITY;
        let p = Profile::Spec;
        for s in [
            LightShape::Rect {
                width: f64::NAN,
                height: 1.0,
            },
            LightShape::Rect {
                width: -1.0,
                height: 1.0,
            },
            LightShape::Disk {
                radius: f64::INFINITY,
            },
            LightShape::Sphere { radius: -0.5 },
            LightShape::Cylinder {
                radius: 0.5,
                length: f64::NAN,
            },
        ] {
            assert_eq!(size_factor(&s, &i, p), 0.0, "{s:?}");
        }
        let singular = DMat4::from_scale(DVec3::new(1.0, 0.0, 1.0));
        assert_eq!(
            size_factor(
                &LightShape::Rect {
                    width: 1.0,
                    height: 1.0
                },
                &singular,
                p
            ),
            0.0
        );
        // A sphere squashed flat is a doubly covered disk: 2πr².
        assert!(
            rel(
                size_factor(&LightShape::Sphere { radius: 1.0 }, &singular, p),
                2.0 * PI
            ) < 1e-12
        );
        let nan = DMat4::from_scale(DVec3::new(f64::NAN, 1.0, 1.0));
        assert_eq!(
            size_factor(&LightShape::Sphere { radius: 1.0 }, &nan, p),
            0.0
        );
        assert_eq!(
            size_factor(&LightShape::Sphere { radius: 1.0 }, &DMat4::ZERO, p),
            0.0
        );
    }

    #[test]
    fn gram_eigen_matches_scale() {
        let m = DMat4::from_quat(DQuat::from_rotation_y(0.7))
            * DMat4::from_scale(DVec3::new(3.0, 0.2, 1.5));
        let [a, b, c] = gram_eigenvalues(&DMat3::from_mat4(m));
        assert!(rel(a, 9.0) < 1e-13 && rel(b, 2.25) < 1e-13 && rel(c, 0.04) < 1e-12);
    }
}
