//! What several blockers hide of a light together, where their projections overlap.
//!
//! Seen from a point `p`, each blocker of an exact penumbra (a triangle, a card's outline, a
//! convex solid's silhouette: lux-render's `visibility/penumbra.rs`) is a convex spherical
//! polygon, and what they hide
//! together is the part of the light in their union. Its measure (`H`: the projected solid
//! angle of the light's directions in a set) is additive, so by inclusion–exclusion
//!
//! `H(P₁ ∪ … ∪ Pₖ) = Σ H(Pᵢ) − Σ H(Pᵢ ∩ Pⱼ) + Σ H(Pᵢ ∩ Pⱼ ∩ Pₗ) − …`
//!
//! where each intersection of convex polygons is again one, found by clipping one by the
//! planes through `p` and the other's edges (Sutherland–Hodgman). Most terms vanish: an
//! intersection hiding nothing (empty, or beside the light) ends its branch, since every
//! intersection below it lies inside it.
//!
//! Polygons are kept relative to `p` (corner `rᵢ = xᵢ − p`, `x` a world point): only their
//! directions matter.

use glam::DVec3;

/// Most corners of a [`Poly`]: a blocker clipped to a light's pyramid (a faceted ball's
/// whole silhouette within a large light's), or an intersection.
pub const POLY: usize = 64;

/// Most intersections evaluated for one point ([`union_hidden`]); past that the caller
/// samples the light.
pub const MOST_TERMS: usize = 48;

/// Most levels of intersections ([`union_hidden`]: pairs, triples, …): where more blockers
/// overlap at once the light is sampled.
pub const MOST_DEEP: usize = 4;

/// A convex spherical polygon seen from a point: its corners relative to the point, in order
/// around it (either way).
#[derive(Clone, Copy, Debug)]
pub struct Poly {
    len: u8,
    r: [DVec3; POLY],
}

impl Default for Poly {
    fn default() -> Poly {
        Poly::EMPTY
    }
}

impl Poly {
    /// No corners.
    pub const EMPTY: Poly = Poly {
        len: 0,
        r: [DVec3::ZERO; POLY],
    };

    /// The polygon of the corners `r` (relative to the point); `None` for more than
    /// [`POLY`].
    pub fn new(r: &[DVec3]) -> Option<Poly> {
        let mut poly = Poly::EMPTY;
        poly.r.get_mut(..r.len())?.copy_from_slice(r);
        poly.len = r.len() as u8;
        Some(poly)
    }

    /// Its corners, relative to the point.
    pub fn corners(&self) -> &[DVec3] {
        &self.r[..self.len as usize]
    }

    /// Whether it has no area (fewer than three corners).
    pub fn is_empty(&self) -> bool {
        self.len < 3
    }

    /// Its part where `ω·k ≥ 0` for each of `planes`, in place (`spare` a buffer); `None`
    /// when a part would have more than [`POLY`] corners.
    pub fn clip_all(
        &mut self,
        planes: impl IntoIterator<Item = DVec3>,
        spare: &mut Poly,
    ) -> Option<()> {
        let mut in_self = true;
        for k in planes {
            let (from, to) = if in_self {
                (&*self, &mut *spare)
            } else {
                (&*spare, &mut *self)
            };
            if from.is_empty() {
                break;
            }
            clip_into(from.corners(), k, to)?;
            in_self = !in_self;
        }
        if !in_self {
            let n = spare.len as usize;
            self.r[..n].copy_from_slice(&spare.r[..n]);
            self.len = spare.len;
        }
        Some(())
    }

    /// Drops corners in the previous one's direction (within 10⁻¹² rad; the last against the
    /// first too): an edge of no length hides nothing, and has no great circle.
    pub fn tidy(&mut self) {
        let distinct = |x: DVec3, y: DVec3| {
            x.cross(y).length_squared() > 1e-24 * x.length_squared() * y.length_squared()
        };
        let mut n = 0;
        for a in 0..self.len as usize {
            let x = self.r[a];
            if n == 0 || distinct(x, self.r[n - 1]) {
                self.r[n] = x;
                n += 1;
            }
        }
        while n >= 3 && !distinct(self.r[n - 1], self.r[0]) {
            n -= 1;
        }
        self.len = if n < 3 { 0 } else { n as u8 };
    }

    /// Its part inside the convex polygon `other`, into `out` (`spare` a buffer; empty when
    /// they do not overlap or `other` has no area), tidied; `None` when a part would have more
    /// than [`POLY`] corners.
    pub fn intersect_into(&self, other: &Poly, out: &mut Poly, spare: &mut Poly) -> Option<()> {
        let r = other.corners();
        let n = r.len();
        out.len = 0;
        if n < 3 || self.is_empty() {
            return Some(());
        }
        // (the orientation: Σ r₀·(rᵢ × rᵢ₊₁), the fan's volumes, one sign for a convex
        // polygon; each edge's plane normal turned towards the inside)
        let det: f64 = (1..n - 1).map(|i| r[0].dot(r[i].cross(r[i + 1]))).sum();
        if det == 0.0 || det.is_nan() {
            return Some(());
        }
        let keep = |i: usize| r[i].cross(r[(i + 1) % n]) * det.signum();
        clip_into(self.corners(), keep(0), out)?;
        out.clip_all((1..n).map(keep), spare)?;
        out.tidy();
        Some(())
    }
}

/// The part of the convex polygon of corners `r` (relative to the point, any number) where
/// `keep·ω ≥ 0` (a half-space through the point), into `out`; `None` when it would have more
/// than [`POLY`] corners.
pub fn clip_into(r: &[DVec3], keep: DVec3, out: &mut Poly) -> Option<()> {
    let n = r.len();
    let mut j = 0;
    for a in 0..n {
        let (x, y) = (r[a], r[(a + 1) % n]);
        let (hx, hy) = (keep.dot(x), keep.dot(y));
        if hx >= 0.0 {
            *out.r.get_mut(j)? = x;
            j += 1;
        }
        // (not where x lies on the plane: the crossing would be x again)
        if (hx > 0.0 && hy < 0.0) || (hx < 0.0 && hy >= 0.0) {
            *out.r.get_mut(j)? = x + (y - x) * (hx / (hx - hy));
            j += 1;
        }
    }
    out.len = if j < 3 { 0 } else { j as u8 };
    Some(())
}

/// `H(P₁ ∪ … ∪ Pₖ)` for the convex polygons `polys` of hidden parts `h[i] = H(Pᵢ)` (module
/// docs), `hidden` giving H of an intersection, `bufs` room for the intersections
/// (2·[`MOST_DEEP`] polygons); `None` when `hidden` has no answer, an intersection has too
/// many corners, more than [`MOST_DEEP`] polygons overlap at once or more than [`MOST_TERMS`]
/// intersections hide something. Branches whose intersection hides at most `negligible` end
/// there (what they leave out is at most that each).
pub fn union_hidden(
    polys: &[Poly],
    h: &[f64],
    negligible: f64,
    hidden: &impl Fn(&Poly) -> Option<f64>,
    bufs: &mut [Poly],
) -> Option<f64> {
    let mut sum: f64 = h.iter().sum();
    let mut terms = 0;
    for i in 0..polys.len() {
        if h[i] > negligible {
            let cur = &polys[i];
            sum -= deeper(polys, cur, i, negligible, hidden, &mut terms, bufs)?;
        }
    }
    Some(sum)
}

/// `Σ_{j > last} [H(cur ∩ Pⱼ) − Σ_{l > j} [H(cur ∩ Pⱼ ∩ Pₗ) − …]]`: the inclusion–exclusion
/// terms below the intersection `cur` of polygons up to index `last`, `bufs` the room left.
fn deeper(
    polys: &[Poly],
    cur: &Poly,
    last: usize,
    negligible: f64,
    hidden: &impl Fn(&Poly) -> Option<f64>,
    terms: &mut usize,
    bufs: &mut [Poly],
) -> Option<f64> {
    let mut sum = 0.0;
    for j in last + 1..polys.len() {
        let [both, spare, rest @ ..] = &mut *bufs else {
            return None;
        };
        cur.intersect_into(&polys[j], both, spare)?;
        if both.is_empty() {
            continue;
        }
        let h = hidden(both)?;
        if h <= negligible {
            continue;
        }
        *terms += 1;
        if *terms > MOST_TERMS {
            return None;
        }
        sum += h - deeper(polys, both, j, negligible, hidden, terms, rest)?;
    }
    Some(sum)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The solid angle of a convex spherical polygon (corners relative to the origin):
    /// Σ of its fan triangles' (Van Oosterom & Strackee).
    fn solid_angle(p: &Poly) -> f64 {
        let r: Vec<DVec3> = p.corners().iter().map(|v| v.normalize()).collect();
        (1..r.len() - 1)
            .map(|i| {
                let (a, b, c) = (r[0], r[i], r[i + 1]);
                let num = a.dot(b.cross(c));
                let den = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
                2.0 * num.atan2(den).abs()
            })
            .sum()
    }

    /// An axis-aligned square in the plane z = 1: [x0, x1] × [y0, y1].
    fn square(x0: f64, x1: f64, y0: f64, y1: f64) -> Poly {
        Poly::new(&[
            DVec3::new(x0, y0, 1.0),
            DVec3::new(x1, y0, 1.0),
            DVec3::new(x1, y1, 1.0),
            DVec3::new(x0, y1, 1.0),
        ])
        .unwrap()
    }

    #[test]
    fn intersections_of_squares_are_their_overlaps() {
        let a = square(-0.2, 0.3, -0.1, 0.4);
        let b = square(0.1, 0.6, 0.0, 0.2);
        let meet = |a: &Poly, b: &Poly| {
            let (mut out, mut spare) = (Poly::EMPTY, Poly::EMPTY);
            a.intersect_into(b, &mut out, &mut spare).unwrap();
            out
        };
        let ab = meet(&a, &b);
        let want = square(0.1, 0.3, 0.0, 0.2);
        assert!((solid_angle(&ab) - solid_angle(&want)).abs() < 1e-14);
        // Either order, the same part.
        assert!((solid_angle(&meet(&b, &a)) - solid_angle(&want)).abs() < 1e-14);
        // Apart: nothing; sharing an edge: nothing.
        assert!(meet(&a, &square(0.5, 0.7, 0.0, 0.1)).is_empty());
        let touching = meet(&a, &square(0.3, 0.7, 0.0, 0.1));
        assert!(touching.is_empty() || solid_angle(&touching) < 1e-15);
        // Reversed winding of either: the same.
        let mut rev = b;
        rev.r[..4].reverse();
        assert!((solid_angle(&meet(&a, &rev)) - solid_angle(&want)).abs() < 1e-14);
    }

    #[test]
    fn the_union_of_overlapping_squares_is_counted_once() {
        // Three squares overlapping pairwise and all three; the union's solid angle against
        // a fine grid count over the plane z = 1 (weighted by the solid angle per cell).
        let polys = [
            square(-0.3, 0.2, -0.3, 0.2),
            square(0.0, 0.5, -0.1, 0.4),
            square(-0.1, 0.3, 0.1, 0.6),
        ];
        let h: Vec<f64> = polys.iter().map(solid_angle).collect();
        let mut bufs = [Poly::EMPTY; 2 * MOST_DEEP];
        let union = union_hidden(&polys, &h, 0.0, &|p| Some(solid_angle(p)), &mut bufs).unwrap();
        // (cells of 0.001 from −0.35: every edge on a cell boundary)
        let n = 1200;
        let cell = 1.2 / n as f64;
        let mut grid = 0.0;
        for i in 0..n {
            for j in 0..n {
                let (x, y) = (
                    -0.35 + (i as f64 + 0.5) * cell,
                    -0.35 + (j as f64 + 0.5) * cell,
                );
                let inside = |p: &Poly| {
                    let r = p.corners();
                    (0..4).all(|k| {
                        let (a, b) = (r[k], r[(k + 1) % 4]);
                        (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x) >= 0.0
                    })
                };
                if polys.iter().any(inside) {
                    // dω = dA cos θ / d² = dA / (1 + x² + y²)^{3/2}
                    grid += cell * cell / (1.0 + x * x + y * y).powf(1.5);
                }
            }
        }
        assert!((union - grid).abs() < 1e-5 * grid, "{union} vs {grid}");
        // Less than the plain sum, by the overlaps.
        assert!(union < h.iter().sum::<f64>() - 0.01);
    }
}
