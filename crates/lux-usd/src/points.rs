//! `UsdGeomPoints` drawn as spheres: one sphere of diameter `widths` (UsdGeomPoints: "Widths are
//! defined as the diameter of the points, in object space") around each of `points`, in the
//! prim's own space.
//!
//! What is read: `points`; `widths` / `primvars:widths` (`primvars:widths` wins; one value, or
//! one per point under `vertex` / `varying`; unauthored: Hydra's fallback width
//! [`crate::curves::FALLBACK_WIDTH`], 1); `primvars:displayColor` (one value, or one per point)
//! as per-corner colours. Authored `normals` (RenderMan draws such points as oriented disks)
//! are reported and not used. Non-finite points and zero widths are left out with a warning;
//! negative widths are taken as their absolute value.
//!
//! Tessellation: a latitude–longitude sphere of [`SPHERE_DETAIL`]`[0]` = 16 × 8 bands
//! (224 triangles; every vertex on the sphere, poles on ±Z and equator vertices on ±X and ±Y,
//! so the tessellated sphere has the true sphere's bounding box) with exact radial normals.
//! Past [`crate::curves::TRIANGLE_BUDGET`] triangles per prim the spheres get coarser
//! (8 × 4, then the 4 × 2 octahedron), with a warning.

use crate::curves::primvar::{self, CurvePrimvar, Interpolation, Sizes};
use crate::curves::sweep::Tessellation;
use crate::curves::{FALLBACK_WIDTH, TRIANGLE_BUDGET, authored_widths};
use crate::error::{LoadError, WarningKind};
use crate::reader::Reader;
use glam::DVec3;
use openusd::usd::Prim;

/// Sphere resolutions `(longitude bands, latitude bands)`, finest first; each has
/// `2·lon·(lat − 1)` triangles.
pub const SPHERE_DETAIL: [(usize, usize); 3] = [(16, 8), (8, 4), (4, 2)];

/// Triangles of one sphere of `(lon, lat)` bands.
pub fn sphere_triangles((lon, lat): (usize, usize)) -> usize {
    2 * lon * (lat - 1)
}

/// Adds a sphere of `radius` around `centre` with `(lon, lat)` bands (`lon` ≥ 3, `lat` ≥ 2) to
/// `out`, wound outward, with radial normals and one colour.
pub fn sphere(
    centre: DVec3,
    radius: f64,
    (lon, lat): (usize, usize),
    color: DVec3,
    out: &mut Tessellation,
) {
    let dir = |k: usize, j: usize| -> DVec3 {
        let theta = std::f64::consts::PI * k as f64 / lat as f64;
        let phi = std::f64::consts::TAU * j as f64 / lon as f64;
        // Exact zeros at the axes keep the bounding box exact (cos(π/2) is 6e-17).
        let snap = |x: f64| if x.abs() < 1e-15 { 0.0 } else { x };
        let (st, ct) = (snap(theta.sin()), snap(theta.cos()));
        DVec3::new(snap(st * snap(phi.cos())), snap(st * snap(phi.sin())), ct)
    };
    let north = out.vertex(centre + radius * DVec3::Z);
    let base = out.positions.len() as u32;
    for k in 1..lat {
        for j in 0..lon {
            out.vertex(centre + radius * dir(k, j));
        }
    }
    let south = out.vertex(centre - radius * DVec3::Z);
    let v = |k: usize, j: usize| base + ((k - 1) * lon + j % lon) as u32;
    let c = [color; 3];
    for j in 0..lon {
        out.triangle(
            [north, v(1, j), v(1, j + 1)],
            [DVec3::Z, dir(1, j), dir(1, j + 1)],
            c,
        );
        for k in 1..lat - 1 {
            let (a, b, cc, d) = (v(k, j), v(k + 1, j), v(k + 1, j + 1), v(k, j + 1));
            let (na, nb, nc, nd) = (dir(k, j), dir(k + 1, j), dir(k + 1, j + 1), dir(k, j + 1));
            out.triangle([a, b, cc], [na, nb, nc], c);
            out.triangle([a, cc, d], [na, nc, nd], c);
        }
        out.triangle(
            [v(lat - 1, j), south, v(lat - 1, j + 1)],
            [dir(lat - 1, j), -DVec3::Z, dir(lat - 1, j + 1)],
            c,
        );
    }
}

/// One value per point from a primvar read with [`primvar::read`].
fn per_point<T: Copy>(p: &CurvePrimvar<T>, i: usize) -> T {
    match p.interpolation {
        Interpolation::Constant | Interpolation::Uniform => p.values[0],
        Interpolation::Varying | Interpolation::Vertex => p.values[i],
    }
}

/// Reads a `Points` prim and tessellates it in its own space. `None` (with a warning) when no
/// point can be drawn.
pub fn read_points(
    r: &mut Reader<'_>,
    prim: &Prim,
    posed: Option<Vec<DVec3>>,
) -> Result<Option<Tessellation>, LoadError> {
    let points = match posed {
        Some(p) => p,
        None => r.vec3_array(prim, "points")?.unwrap_or_default(),
    };
    if points.is_empty() {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            "no points; nothing drawn",
        );
        return Ok(None);
    }
    // A Points prim is one element: `uniform` takes one value, like `constant`.
    let sizes = Sizes {
        curves: 1,
        varying: points.len(),
        vertex: points.len(),
    };
    let fallback = format!("drawn with the fallback width {FALLBACK_WIDTH}");
    let widths = match authored_widths(r, prim)? {
        Some(w) => primvar::read(r, prim, w.name, w.values, w.interpolation, sizes, &fallback)?,
        None => None,
    }
    .unwrap_or(CurvePrimvar::constant(FALLBACK_WIDTH));
    let colors = primvar::display_color(r, prim, sizes)?;
    for name in ["primvars:normals", "normals"] {
        if r.vec3_array(prim, name)?.is_some_and(|n| !n.is_empty()) {
            r.warn(
                prim,
                WarningKind::Unsupported,
                format!(
                    "{name}: points are drawn as spheres; the normals (oriented disks) are not used"
                ),
            );
            break;
        }
    }
    let drawn: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].is_finite() && per_point(&widths, i) > 0.0)
        .collect();
    let not_finite = points.iter().filter(|p| !p.is_finite()).count();
    if not_finite > 0 {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!(
                "{not_finite} of {} points are not finite; left out",
                points.len()
            ),
        );
    }
    let zero = points.len() - not_finite - drawn.len();
    if zero > 0 {
        r.warn(
            prim,
            WarningKind::InvalidGeometry,
            format!(
                "{zero} of {} points have zero width; left out",
                points.len()
            ),
        );
    }
    if drawn.is_empty() {
        return Ok(None);
    }
    let detail = SPHERE_DETAIL
        .iter()
        .copied()
        .find(|d| drawn.len().saturating_mul(sphere_triangles(*d)) <= TRIANGLE_BUDGET);
    let detail = match detail {
        Some(d) if d == SPHERE_DETAIL[0] => d,
        found => {
            let least = SPHERE_DETAIL[SPHERE_DETAIL.len() - 1];
            let d = found.unwrap_or(least);
            let total = drawn.len().saturating_mul(sphere_triangles(d));
            if total > r.limits.max_array_len {
                return Err(LoadError::TooLarge {
                    file: r.file.clone(),
                    prim: prim.path().to_string(),
                    what: "points tessellation",
                    count: total,
                    limit: r.limits.max_array_len,
                });
            }
            r.warn(
                prim,
                WarningKind::Unsupported,
                format!(
                    "{} points need {} triangles as {}×{} spheres, past the budget of \
                     {TRIANGLE_BUDGET} triangles per prim: drawn as {}×{} spheres ({total} \
                     triangles)",
                    drawn.len(),
                    drawn
                        .len()
                        .saturating_mul(sphere_triangles(SPHERE_DETAIL[0])),
                    SPHERE_DETAIL[0].0,
                    SPHERE_DETAIL[0].1,
                    d.0,
                    d.1
                ),
            );
            d
        }
    };
    let mut out = Tessellation::new(colors.is_some());
    for i in drawn {
        let color = colors.as_ref().map_or(DVec3::ZERO, |c| per_point(c, i));
        sphere(
            points[i],
            per_point(&widths, i) / 2.0,
            detail,
            color,
            &mut out,
        );
    }
    Ok(Some(out))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spheres_are_closed_outward_and_on_the_sphere() {
        for d in SPHERE_DETAIL {
            let mut t = Tessellation::new(false);
            let c = DVec3::new(1.0, -2.0, 3.0);
            sphere(c, 0.5, d, DVec3::ZERO, &mut t);
            assert_eq!(t.triangles.len(), sphere_triangles(d));
            let mut volume = 0.0;
            for (tri, n) in t.triangles.iter().zip(&t.normals) {
                let [a, b, e] = tri.map(|k| t.positions[k as usize] - c);
                volume += a.dot(b.cross(e)) / 6.0;
                let face = (b - a).cross(e - a);
                assert!(face.length() > 0.0);
                assert!(face.dot(a + b + e) > 0.0, "{d:?}: inward triangle");
                for (k, v) in tri.iter().zip(n) {
                    let radial = (t.positions[*k as usize] - c) / 0.5;
                    assert!((radial - *v).length() < 1e-12);
                }
            }
            assert!(volume > 0.0);
            let (lo, hi) = t.positions.iter().fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            );
            assert_eq!((lo, hi), (c - 0.5, c + 0.5), "{d:?}");
            for p in &t.positions {
                assert!(((*p - c).length() - 0.5).abs() < 1e-15);
            }
        }
    }
}
