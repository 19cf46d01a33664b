//! Solid-angle sampling of spherical polygons: the spherical rectangle (Ureña, Fajardo, King
//! 2013, "An area-preserving parametrization for spherical rectangles") and the spherical
//! triangle (Arvo 1995, "Stratified sampling of spherical triangles").

use glam::DVec3;

/// A rectangle seen from a point, prepared for uniform solid-angle sampling (Ureña et al. 2013,
/// §3–4). The rectangle is `corner + s·ex + t·ey`, s, t ∈ \[0,1\], with `ex ⟂ ey`.
///
/// The set-up follows the paper in its own local frame, with the trigonometry replaced by
/// algebra (same quantities up to rounding, see `new`): the solid angle from one arctangent,
/// and the paper's angle k = 2π − γ₂ − γ₃ kept as the unit complex number e^{ik}.
#[derive(Clone, Copy, Debug)]
pub struct SphericalRectangle {
    o: DVec3,
    x: DVec3,
    y: DVec3,
    z: DVec3,
    z0: f64,
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
    /// n₀·ẑ and n₂·ẑ of the paper (its b0 and b1).
    b0: f64,
    b1: f64,
    /// 1 − b0² = z0²/(z0² + y0²), without the cancellation.
    nb: f64,
    /// cos k and sin k.
    cos_k: f64,
    sin_k: f64,
    solid_angle: f64,
}

/// 2^−e for the binary exponent e of `m` (`m·2^−e` ∈ \[½, 1)), clamped so that the result is a
/// normal number: multiplying by it is exact, and it brings lengths near 1 so that sixth
/// powers of them can neither overflow nor underflow.
#[inline(always)]
fn pow2_scale(m: f64) -> f64 {
    let e = ((m.to_bits() >> 52) & 0x7ff).clamp(1, 2044);
    f64::from_bits((2045 - e) << 52)
}

/// Solid angle of the rectangle \[x0, x1\] × \[y0, y1\] in the plane z = z0 ≤ 0 seen from the
/// origin, and the four corner distances `[r00, r10, r11, r01]` (`rij` at (xi, yj)).
///
/// The rectangle is split along its diagonal (x0, y0)–(x1, y1) into two triangles, each by
/// Van Oosterom & Strackee (1983) with unnormalised vertices:
/// `tan(Ω/2) = |A·(B×C)| / (abc + (A·B)c + (A·C)b + (B·C)a)`; both triple products are
/// |z0|·(x1 − x0)·(y1 − y0). The two half-angles are added as the argument of the product of
/// the two complex numbers `denominator + i·numerator`, so that S = 2·atan2(…) needs one
/// arctangent. S/2 ∈ \[0, π\]: a negative imaginary part can only be round-off (at S ≈ 0 or
/// S ≈ 2π) and is taken as 0. Inputs must be pre-scaled to magnitudes near 1 (sixth powers).
#[inline(always)]
fn rect_solid_angle(x0: f64, x1: f64, y0: f64, y1: f64, z0: f64) -> (f64, [f64; 4]) {
    let z02 = z0 * z0;
    let (xx0, xx1, yy0, yy1) = (x0 * x0, x1 * x1, y0 * y0, y1 * y1);
    let (lx0, lx1) = (z02 + xx0, z02 + xx1);
    let r00 = (lx0 + yy0).sqrt();
    let r10 = (lx1 + yy0).sqrt();
    let r11 = (lx1 + yy1).sqrt();
    let r01 = (lx0 + yy1).sqrt();
    // dot products of the corner vectors
    let (x01, y01) = (x0 * x1 + z02, y0 * y1);
    let d00_10 = x01 + yy0;
    let d00_11 = x01 + y01;
    let d10_11 = xx1 + z02 + y01;
    let d00_01 = xx0 + z02 + y01;
    let d11_01 = x01 + yy1;
    let n = -z0 * ((x1 - x0) * (y1 - y0));
    let den1 = r00 * r10 * r11 + d00_10 * r11 + d00_11 * r10 + d10_11 * r00;
    let den2 = r00 * r11 * r01 + d00_11 * r01 + d00_01 * r11 + d11_01 * r00;
    let re = den1 * den2 - n * n;
    let im = n * (den1 + den2);
    (2.0 * im.max(0.0).atan2(re), [r00, r10, r11, r01])
}

impl SphericalRectangle {
    /// Sets up the spherical rectangle of `corner + s·ex + t·ey` seen from `o`.
    ///
    /// Local frame (paper §3): x̂ = ex/|ex|, ŷ = ey/|ey|, ẑ = x̂ × ŷ flipped so that the
    /// rectangle lies at z0 < 0. The four great-circle planes through `o` and the edges have
    /// normals n0..n3; the interior angles are γᵢ = acos(−nᵢ·nᵢ₊₁) and the solid angle is
    /// S = Σγᵢ − 2π.
    ///
    /// Evaluated without trigonometry: S from the two triangles of the diagonal by Van Oosterom
    /// & Strackee with one arctangent (`rect_solid_angle` in the source), and
    /// e^{ik} = e^{−i(γ₂+γ₃)} from the corners of the x = x0 edge, where
    /// `e^{iγ}·|…| = (±x·y, |z0|·r)` at the corner (x, y) at distance r, of modulus
    /// √(z0² + x²)·√(z0² + y²).
    #[inline]
    pub fn new(o: DVec3, corner: DVec3, ex: DVec3, ey: DVec3) -> Self {
        let exl = ex.length();
        let eyl = ey.length();
        let x = ex / exl;
        let y = ey / eyl;
        let mut z = x.cross(y);
        let d = corner - o;
        let mut z0 = d.dot(z);
        if z0 > 0.0 {
            z = -z;
            z0 = -z0;
        }
        let x0 = d.dot(x);
        let y0 = d.dot(y);
        Self::from_local(o, x, y, z, [x0, y0, x0 + exl, y0 + eyl], z0)
    }

    /// The axis-aligned rectangle \[−a, a\] × \[−b, b\] in the plane z = 0 seen from `o`
    /// (the local frame of a RectLight): the same as [`Self::new`] without the frame set-up.
    #[inline]
    pub fn centred(o: DVec3, a: f64, b: f64) -> Self {
        let (z, z0) = if o.z < 0.0 {
            (DVec3::NEG_Z, o.z)
        } else {
            (DVec3::Z, -o.z)
        };
        let c = [-a - o.x, -b - o.y, a - o.x, b - o.y];
        Self::from_local(o, DVec3::X, DVec3::Y, z, c, z0)
    }

    /// The axis-aligned rectangle \[x0, x1\] × \[y0, y1\] in the plane z = 0 seen from `o`:
    /// [`Self::centred`] for a window of a RectLight (x0 < x1, y0 < y1).
    #[inline]
    pub fn window(o: DVec3, [x0, y0, x1, y1]: [f64; 4]) -> Self {
        let (z, z0) = if o.z < 0.0 {
            (DVec3::NEG_Z, o.z)
        } else {
            (DVec3::Z, -o.z)
        };
        let c = [x0 - o.x, y0 - o.y, x1 - o.x, y1 - o.y];
        Self::from_local(o, DVec3::X, DVec3::Y, z, c, z0)
    }

    /// The set-up from the rectangle's coordinates `[x0, y0, x1, y1]` and z0 ≤ 0 in the frame
    /// (x̂, ŷ, ẑ) centred at `o`.
    #[inline(always)]
    fn from_local(o: DVec3, x: DVec3, y: DVec3, z: DVec3, c: [f64; 4], z0: f64) -> Self {
        let [x0, y0, x1, y1] = c;
        // Everything below is a ratio of equal powers of lengths: compute it on lengths scaled
        // by a power of two (exact) to keep the sixth powers in range.
        let m = x0
            .abs()
            .max(x1.abs())
            .max(y0.abs())
            .max(y1.abs())
            .max(z0.abs());
        let k = pow2_scale(m);
        let (sx0, sy0, sx1, sy1, sz0) = (x0 * k, y0 * k, x1 * k, y1 * k, z0 * k);
        let (solid_angle, [r00, _, _, r01]) = rect_solid_angle(sx0, sx1, sy0, sy1, sz0);
        let z02 = sz0 * sz0;
        let (ly0, ly1) = (z02 + sy0 * sy0, z02 + sy1 * sy1);
        let (sly0, sly1) = (ly0.sqrt(), ly1.sqrt());
        // e^{iγ₂}·|…| = (x0·y1, |z0|·r01), e^{iγ₃}·|…| = (−x0·y0, |z0|·r00);
        // e^{ik} = conj(product) / (√(z0²+x0²)²·√(z0²+y0²)·√(z0²+y1²))
        let (a2, c2) = (sx0 * sy1, -sz0 * r01);
        let (a3, c3) = (-sx0 * sy0, -sz0 * r00);
        let lx0 = z02 + sx0 * sx0;
        let inv = 1.0 / (lx0 * (sly0 * sly1));
        let cos_k = (a2 * a3 - c2 * c3) * inv;
        let sin_k = -(a2 * c3 + c2 * a3) * inv;
        // the same reciprocal gives 1/√ly0 = √ly1·lx0·inv and 1/√ly1 = √ly0·lx0·inv
        let w = lx0 * inv;
        let (inv_sly0, inv_sly1) = (sly1 * w, sly0 * w);
        Self {
            o,
            x,
            y,
            z,
            z0,
            x0,
            y0,
            x1,
            y1,
            b0: -sy0 * inv_sly0,
            b1: sy1 * inv_sly1,
            nb: z02 * (inv_sly0 * inv_sly0),
            cos_k,
            sin_k,
            solid_angle,
        }
    }

    /// Solid angle S subtended by the rectangle (steradians).
    #[inline]
    pub fn solid_angle(&self) -> f64 {
        self.solid_angle
    }

    /// The point of the rectangle for `u ∈ [0,1]²`; directions from `o` to it are uniform in
    /// solid angle (density 1/S). `u[0]` sweeps the sub-rectangle area along x̂ (paper eq. 11–13),
    /// `u[1]` is uniform in h = y/√(d² + y²) along the chosen vertical line (eq. 15–17).
    ///
    /// The paper's angle au = u₀·S + k enters only through cos au and sin au, obtained by
    /// rotating e^{ik} by u₀·S; and its
    /// `xu = −cu·z0/√(1 − cu²)`, `cu = sign(fu)/√(fu² + b0²)`, `fu = (cos au·b0 − b1)/sin au`
    /// is `xu = N/√D` with `N = −sign(n)·sin au·z0`, `D = n² − (1 − b0²)·sin² au`,
    /// `n = cos au·b0 − b1` (`fu = n/sin au`; 1 − b0² without cancellation).
    ///
    /// The vertical step then needs no `xu`: with `d² = xu² + z0² = E/D`, `E = N² + z0²·D`,
    /// and `Aᵢ = E + yᵢ²·D` (so that √(d² + yᵢ²) = √Aᵢ/√D), the paper's
    /// `yv = hv·d/√(1 − hv²)`, `hv = h0 + u₁(h1 − h0)`, `hᵢ = yᵢ/√(d² + yᵢ²)`, is
    /// `yv = M·√(E/((P − M√D)(P + M√D)))` with `M = y0√A1 + u₁(y1√A0 − y0√A1)` and
    /// `P = √A0·√A1`. The square roots √D, √A0, √A1 run side by side, leaving one square root,
    /// one division and one square root in a row after the sine and cosine (the direct form
    /// has two more of each). Samples whose `xu` leaves \[x0, x1\] by rounding (or with
    /// D ≤ 0) take the direct form with `xu` clamped.
    #[inline]
    pub fn sample(&self, u: [f64; 2]) -> DVec3 {
        let (num, den2) = self.horizontal_terms(u[0]);
        let rd = den2.sqrt();
        let xu = num / rd;
        if !(den2 > 0.0 && xu >= self.x0 && xu <= self.x1) {
            return self.sample_clamped(num, den2, u[1]);
        }
        let e = num * num + (self.z0 * self.z0) * den2;
        let a0 = e + (self.y0 * self.y0) * den2;
        let a1 = e + (self.y1 * self.y1) * den2;
        let (r0, r1) = (a0.sqrt(), a1.sqrt());
        let (a, b) = (self.y0 * r1, self.y1 * r0);
        let m = a + u[1] * (b - a);
        let p = r0 * r1;
        let mr = m * rd;
        let gap = (p - mr) * (p + mr);
        self.point_at(xu, m, e, gap, p)
    }

    /// The rectangle's point at `xu` and `yv = m·√(e/gap)` (both forms of [`Self::sample`]
    /// end so), clamped to \[y0, y1\]; the far edge y1 when `gap ≤ 10⁻¹²·p²` (|hv| → 1, only
    /// at the far edge at grazing angles).
    #[inline(always)]
    fn point_at(&self, xu: f64, m: f64, e: f64, gap: f64, p: f64) -> DVec3 {
        let yv = if gap > 1e-12 * (p * p) {
            m * (e / gap).sqrt()
        } else {
            self.y1
        };
        let yv = yv.clamp(self.y0, self.y1);
        self.o + xu * self.x + yv * self.y + self.z0 * self.z
    }

    /// [`Self::sample`] in the paper's direct form for `xu = N/√D` clamped to \[x0, x1\]
    /// (D ≤ 0: the edge on N's side). `hv = N'/D'` with `D' = s0·s1`,
    /// `N' = y0·s1 + u₁(y1·s0 − y0·s1)`, `sᵢ = √(d² + yᵢ²)`, so
    /// `yv = hv·√(d²/(1 − hv²)) = N'·√(d²/(D'² − N'²))`.
    #[cold]
    fn sample_clamped(&self, num: f64, den2: f64, u1: f64) -> DVec3 {
        let xu = if den2 > 0.0 {
            num / den2.sqrt()
        } else {
            f64::INFINITY.copysign(num)
        };
        let xu = xu.clamp(self.x0, self.x1);
        let d2 = xu * xu + self.z0 * self.z0;
        let s0 = (d2 + self.y0 * self.y0).sqrt();
        let s1 = (d2 + self.y1 * self.y1).sqrt();
        let (a, b) = (self.y0 * s1, self.y1 * s0);
        let nn = a + u1 * (b - a);
        let dd = s0 * s1;
        let gap = (dd - nn) * (dd + nn);
        self.point_at(xu, nn, d2, gap, dd)
    }

    /// `(N, D)` of [`Self::sample`] for `u₀`: `xu = N/√D`.
    #[inline(always)]
    fn horizontal_terms(&self, u0: f64) -> (f64, f64) {
        let (s, c) = (u0 * self.solid_angle).sin_cos();
        let cau = c * self.cos_k - s * self.sin_k;
        let sau = s * self.cos_k + c * self.sin_k;
        let n = cau * self.b0 - self.b1;
        let num = -(n.signum() * sau) * self.z0;
        (num, n * n - self.nb * (sau * sau))
    }

    /// The direct form of [`Self::sample`] for every sample (tests).
    #[cfg(test)]
    fn sample_direct(&self, u: [f64; 2]) -> DVec3 {
        let (num, den2) = self.horizontal_terms(u[0]);
        self.sample_clamped(num, den2, u[1])
    }

    /// Inverse of [`Self::sample`] for a point `q` on the rectangle: u₀ = S(x0..x)/S with the
    /// solid angle of the sub-rectangle, u₁ = (h(y) − h0)/(h1 − h0).
    #[inline]
    pub fn invert(&self, q: DVec3) -> [f64; 2] {
        let d = q - self.o;
        let xu = d.dot(self.x).clamp(self.x0, self.x1);
        let yv = d.dot(self.y).clamp(self.y0, self.y1);
        let z0 = self.z0;
        let m = self
            .x0
            .abs()
            .max(self.x1.abs())
            .max(self.y0.abs())
            .max(self.y1.abs())
            .max(z0.abs());
        let k = pow2_scale(m);
        let (sub, _) = rect_solid_angle(self.x0 * k, xu * k, self.y0 * k, self.y1 * k, z0 * k);
        let u0 = (sub / self.solid_angle).clamp(0.0, 1.0);
        let d2 = xu * xu + z0 * z0;
        let h0 = self.y0 / (d2 + self.y0 * self.y0).sqrt();
        let h1 = self.y1 / (d2 + self.y1 * self.y1).sqrt();
        let h = yv / (d2 + yv * yv).sqrt();
        let u1 = if h1 > h0 {
            ((h - h0) / (h1 - h0)).clamp(0.0, 1.0)
        } else {
            0.5
        };
        [u0, u1]
    }

    /// Unit directions from `o` to the four corners, ordered `[(x0,y0), (x1,y0), (x0,y1), (x1,y1)]`
    /// (the order of [`crate::warp::sample_bilinear`]'s weights).
    #[inline]
    pub fn corner_directions(&self) -> [DVec3; 4] {
        let c = |xx: f64, yy: f64| (xx * self.x + yy * self.y + self.z0 * self.z).normalize();
        [
            c(self.x0, self.y0),
            c(self.x1, self.y0),
            c(self.x0, self.y1),
            c(self.x1, self.y1),
        ]
    }
}

/// Solid angle of the spherical triangle with unit vertices a, b, c (Van Oosterom & Strackee
/// 1983): Ω = 2·atan2(|a·(b×c)|, 1 + a·b + b·c + c·a).
#[inline]
pub fn spherical_triangle_area(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let num = a.dot(b.cross(c)).abs();
    let den = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
    2.0 * num.atan2(den)
}

/// Uniform direction inside the spherical triangle with unit vertices a, b, c (Arvo 1995):
/// u₀ picks the sub-triangle area Â = u₀·Ω, which fixes a point ĉ on arc ac; u₁ then picks
/// cos θ uniformly on the arc from b to ĉ. Returns `(direction, 1/Ω)`, or `None` for a
/// degenerate triangle.
#[inline]
pub fn sample_spherical_triangle(
    a: DVec3,
    b: DVec3,
    c: DVec3,
    u: [f64; 2],
) -> Option<(DVec3, f64)> {
    let area = spherical_triangle_area(a, b, c);
    if crate::not_positive(area) {
        return None;
    }
    // Interior angles from the great-circle plane normals.
    let nab = a.cross(b).normalize_or_zero();
    let nbc = b.cross(c).normalize_or_zero();
    let nca = c.cross(a).normalize_or_zero();
    if nab == DVec3::ZERO || nbc == DVec3::ZERO || nca == DVec3::ZERO {
        return None;
    }
    let alpha = angle_between(nab, -nca);
    let beta = angle_between(nbc, -nab);
    let gamma = angle_between(nca, -nbc);
    let area_angles = alpha + beta + gamma - core::f64::consts::PI;
    let ap = u[0] * area_angles;
    let (s, t) = (ap - alpha).sin_cos();
    let cos_alpha = alpha.cos();
    let sin_alpha = alpha.sin();
    let cos_c = a.dot(b);
    let uu = t - cos_alpha;
    let vv = s + sin_alpha * cos_c;
    let den = (vv * s + uu * t) * sin_alpha;
    let q = if den != 0.0 {
        (((vv * t - uu * s) * cos_alpha - vv) / den).clamp(-1.0, 1.0)
    } else {
        1.0
    };
    let c_perp = (c - c.dot(a) * a).normalize_or_zero();
    let c_hat = q * a + (1.0 - q * q).max(0.0).sqrt() * c_perp;
    let z = 1.0 - u[1] * (1.0 - c_hat.dot(b));
    let ch_perp = (c_hat - c_hat.dot(b) * b).normalize_or_zero();
    let w = z * b + (1.0 - z * z).max(0.0).sqrt() * ch_perp;
    Some((w.normalize(), 1.0 / area))
}

/// Angle between unit vectors, accurate near 0 and π (2·asin of half the chord).
#[inline]
fn angle_between(a: DVec3, b: DVec3) -> f64 {
    if a.dot(b) < 0.0 {
        core::f64::consts::PI - 2.0 * ((a + b).length() * 0.5).min(1.0).asin()
    } else {
        2.0 * ((b - a).length() * 0.5).min(1.0).asin()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A unit square at distance 1 on the axis subtends 4·asin(1/3)... exactly
    /// Ω = 4·atan(ab / (2d·√(4d² + a² + b²))) with a = b = 1, d = 1: 4·atan(1/6).
    #[test]
    fn rectangle_solid_angle_closed_form() {
        let r =
            SphericalRectangle::new(DVec3::ZERO, DVec3::new(-0.5, -0.5, 1.0), DVec3::X, DVec3::Y);
        let exact = 4.0 * (1.0 / (2.0 * 6.0f64.sqrt())).atan();
        assert!(
            (r.solid_angle() - exact).abs() < 1e-13,
            "{} {}",
            r.solid_angle(),
            exact
        );
        // Split into two triangles, the solid angle is additive.
        let v = [
            DVec3::new(-0.5, -0.5, 1.0).normalize(),
            DVec3::new(0.5, -0.5, 1.0).normalize(),
            DVec3::new(0.5, 0.5, 1.0).normalize(),
            DVec3::new(-0.5, 0.5, 1.0).normalize(),
        ];
        let t =
            spherical_triangle_area(v[0], v[1], v[2]) + spherical_triangle_area(v[0], v[2], v[3]);
        assert!((t - exact).abs() < 1e-13);
    }

    /// A grazing, far-off placement (height 0.035, the rectangle 1.8–2.6 away along y), where
    /// the vertical step is ill-conditioned (|hv| ≈ 0.9997): the paper's formulas at 50 digits
    /// (mpmath, `ox, oy, height` below) give x = 0.270525645440996176, y = 0.161972816429450438.
    /// Measured errors: x 1.5e-14 (the set-up), y 5.0e-13; the direct form's y is 1.6e-12 off.
    #[test]
    #[allow(clippy::excessive_precision)]
    fn sample_at_grazing_placement_against_high_precision() {
        let o = DVec3::new(
            0.24208607043173794,
            -2.15555871508759,
            -(10f64.powf(-1.4546670387717373)),
        );
        let r = SphericalRectangle::new(
            o,
            DVec3::new(-0.6, -0.4, 0.0),
            DVec3::X * 1.2,
            DVec3::Y * 0.8,
        );
        let q = r.sample([0.7135585114883902, 0.8069710416355673]);
        assert!((q.x - 0.270525645440996176).abs() < 5e-14, "{}", q.x);
        assert!((q.y - 0.161972816429450438).abs() < 1e-12, "{}", q.y);
    }

    proptest! {
        #[test]
        fn centred_matches_general(ox in -2.0..2.0f64, oy in -2.0..2.0f64, oz in 0.05..2.0f64, u0 in 0.0..1.0f64, u1 in 0.0..1.0f64) {
            let o = DVec3::new(ox, oy, -oz);
            let a = SphericalRectangle::new(o, DVec3::new(-0.6, -0.4, 0.0), DVec3::X * 1.2, DVec3::Y * 0.8);
            let b = SphericalRectangle::centred(o, 0.6, 0.4);
            prop_assert!((a.solid_angle() - b.solid_angle()).abs() < 1e-12);
            prop_assert!((a.sample([u0, u1]) - b.sample([u0, u1])).length() < 1e-9);
        }

        #[test]
        fn sample_equals_the_direct_form(
            u0 in 0.0..1.0f64, u1 in 0.0..1.0f64,
            ox in -3.0..3.0f64, oy in -3.0..3.0f64, lz in -1.3..0.5f64,
        ) {
            // heights from 0.05 to 3 (grazing placements: `sample_at_grazing_placement`)
            let o = DVec3::new(ox, oy, -(10f64.powf(lz)));
            let r = SphericalRectangle::new(o, DVec3::new(-0.6, -0.4, 0.0), DVec3::X * 1.2, DVec3::Y * 0.8);
            let (a, b) = (r.sample([u0, u1]), r.sample_direct([u0, u1]));
            // Compared in the sample domain: near grazing the map u ↦ q stretches (its Jacobian
            // reached ~600 in a saved case, oy = 2.97, height 0.07), so two forms that agree to
            // 1e-12 in u differ by ~1e-9 in position; a wrong form differs by O(1) in u.
            let (ia, ib) = (r.invert(a), r.invert(b));
            prop_assert!(
                (ia[0] - ib[0]).abs() < 1e-10 && (ia[1] - ib[1]).abs() < 1e-10,
                "{:?} {:?} invert to {:?} {:?}", a, b, ia, ib
            );
        }

        #[test]
        fn rectangle_sample_lies_on_rectangle_and_inverts(
            u0 in 0.001..0.999f64, u1 in 0.001..0.999f64,
            ox in -2.0..2.0f64, oy in -2.0..2.0f64, oz in 0.05..2.0f64,
        ) {
            let corner = DVec3::new(-0.6, -0.4, 0.0);
            let r = SphericalRectangle::new(DVec3::new(ox, oy, -oz), corner, DVec3::X * 1.2, DVec3::Y * 0.8);
            let q = r.sample([u0, u1]);
            prop_assert!(q.z.abs() < 1e-9);
            prop_assert!(q.x >= -0.6 - 1e-9 && q.x <= 0.6 + 1e-9 && q.y >= -0.4 - 1e-9 && q.y <= 0.4 + 1e-9);
            let back = r.invert(q);
            prop_assert!((back[0] - u0).abs() < 1e-6 && (back[1] - u1).abs() < 1e-6, "{:?} vs {} {}", back, u0, u1);
        }

        #[test]
        fn triangle_sample_is_inside(u0 in 0.0..1.0f64, u1 in 0.0..1.0f64) {
            let a = DVec3::new(0.2, 0.1, 1.0).normalize();
            let b = DVec3::new(1.0, 0.3, 0.8).normalize();
            let c = DVec3::new(-0.4, 1.2, 0.6).normalize();
            let (w, pdf) = sample_spherical_triangle(a, b, c, [u0, u1]).unwrap();
            prop_assert!((pdf * spherical_triangle_area(a, b, c) - 1.0).abs() < 1e-12);
            // Inside: same side of all three great circles as the opposite vertex.
            let n = a.cross(b);
            prop_assert!(w.dot(n) * c.dot(n) >= -1e-9);
            let n = b.cross(c);
            prop_assert!(w.dot(n) * a.dot(n) >= -1e-9);
            let n = c.cross(a);
            prop_assert!(w.dot(n) * b.dot(n) >= -1e-9);
        }
    }
}
