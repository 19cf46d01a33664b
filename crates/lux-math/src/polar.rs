//! Light-space polar coordinates and orthonormal frames, with the conventions of the spec.
//!
//! A light's primary axis is its local **−Z**. The polar angle θ is measured from −Z (θ = 0 is
//! emission straight along the axis, "nadir" in IES terms). The azimuth φ is the IES horizontal
//! angle: φ = 0 points towards local −X and φ = 90° towards local −Y, i.e. φ is the ordinary
//! azimuth `atan2(y, x)` plus 180°.

use glam::DVec3;

/// Light-space direction → `(θ, φ)` in radians: θ ∈ \[0, π\] the angle from −Z
/// (`acos(−z/|d|)`), φ ∈ \[0, 2π).
///
/// θ is evaluated as `atan2(√(x² + y²), −z)`, which unlike `acos` of the rounded cosine keeps
/// full relative accuracy near the axis (acos loses up to √(2⁻⁵²) ≈ 1.5·10⁻⁸ rad there).
/// φ = atan2(y, x) + π wrapped to \[0, 2π): 0 towards −X, π/2 towards −Y (the IES horizontal angle).
/// On the axis (x = y = 0) φ is 0. A zero or non-finite direction gives `None`.
#[inline]
pub fn light_polar(dir: DVec3) -> Option<(f64, f64)> {
    let len2 = dir.length_squared();
    if !(len2 > 0.0 && len2.is_finite()) {
        return None;
    }
    Some(polar_angles(dir))
}

/// The `(θ, φ)` of [`light_polar`] without its check of the direction, for callers that have
/// checked it already: θ by [`polar_angle`], φ by [`azimuth_from_xy`].
#[inline]
pub fn polar_angles(dir: DVec3) -> (f64, f64) {
    (polar_angle(dir), azimuth_from_xy(dir.x, dir.y))
}

/// The θ of [`light_polar`] alone: `atan2(√(x² + y²), −z)`, the angle from the light's −Z axis
/// (no check of the direction: a zero one gives atan2(0, −0) = π, a NaN one NaN).
#[inline]
pub fn polar_angle(dir: DVec3) -> f64 {
    (dir.x * dir.x + dir.y * dir.y).sqrt().atan2(-dir.z)
}

/// The IES azimuth of a light-space direction's XY components: atan2(y, x) + π wrapped to \[0, 2π).
#[inline]
pub fn azimuth_from_xy(x: f64, y: f64) -> f64 {
    if x == 0.0 && y == 0.0 {
        return 0.0;
    }
    let mut phi = y.atan2(x) + core::f64::consts::PI;
    if phi >= core::f64::consts::TAU {
        phi -= core::f64::consts::TAU;
    }
    if phi < 0.0 {
        phi = 0.0;
    }
    phi
}

/// Inverse of [`light_polar`]: the unit light-space direction with polar angle θ (from −Z) and
/// IES azimuth φ: `(−sinθ·cosφ, −sinθ·sinφ, −cosθ)`.
#[inline]
pub fn light_direction(theta: f64, phi: f64) -> DVec3 {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    DVec3::new(-st * cp, -st * sp, -ct)
}

/// An orthonormal frame `(t, b, n)` around the unit vector `n`, right-handed (t × b = n).
///
/// Uses the branchless construction of Duff et al. 2017 ("Building an orthonormal basis,
/// revisited"); continuous everywhere except across n.z = 0⁻/0⁺ where it flips sign.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// First tangent.
    pub t: DVec3,
    /// Second tangent (bitangent).
    pub b: DVec3,
    /// The normal the frame is built around.
    pub n: DVec3,
}

impl Frame {
    /// Builds the frame around `n`, which must be unit length (not checked; a non-unit input
    /// gives a non-orthonormal frame).
    #[inline]
    pub fn from_normal(n: DVec3) -> Frame {
        let sign = 1.0f64.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let t = DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let bt = DVec3::new(b, sign + n.y * n.y * a, -n.y);
        Frame { t, b: bt, n }
    }

    /// World → local: components of `v` along (t, b, n).
    #[inline]
    pub fn to_local(&self, v: DVec3) -> DVec3 {
        DVec3::new(v.dot(self.t), v.dot(self.b), v.dot(self.n))
    }

    /// Local → world: `x·t + y·b + z·n`.
    #[inline]
    pub fn to_world(&self, v: DVec3) -> DVec3 {
        self.t * v.x + self.b * v.y + self.n * v.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::{FRAC_PI_2, PI};
    use proptest::prelude::*;

    #[test]
    fn ies_azimuth_convention() {
        // towards -X is h = 0, towards -Y is h = 90 deg, towards +X is 180 deg, +Y is 270 deg.
        let (t, p) = light_polar(DVec3::new(-1.0, 0.0, 0.0)).unwrap();
        assert!((t - FRAC_PI_2).abs() < 1e-15 && p.abs() < 1e-15);
        let (_, p) = light_polar(DVec3::new(0.0, -1.0, 0.0)).unwrap();
        assert!((p - FRAC_PI_2).abs() < 1e-15);
        let (_, p) = light_polar(DVec3::new(1.0, 0.0, 0.0)).unwrap();
        assert!((p - PI).abs() < 1e-15);
        let (_, p) = light_polar(DVec3::new(0.0, 1.0, 0.0)).unwrap();
        assert!((p - 1.5 * PI).abs() < 1e-15);
        let (t, _) = light_polar(DVec3::new(0.0, 0.0, -2.0)).unwrap();
        assert_eq!(t, 0.0);
        let (t, _) = light_polar(DVec3::new(0.0, 0.0, 3.0)).unwrap();
        assert!((t - PI).abs() < 1e-15);
        assert!(light_polar(DVec3::ZERO).is_none());
        assert!(light_polar(DVec3::new(f64::NAN, 0.0, 1.0)).is_none());
    }

    #[test]
    fn azimuth_wrap_rules_and_unchecked_angles() {
        // φ = atan2(y, x) + π folded into [0, 2π): 0 towards −X (either sign of a zero y, and a
        // tiny positive y whose sum rounds up to 2π), π towards +X, π/2 towards −Y
        let tiny = 1e-300;
        for (x, y, want) in [
            (-1.0, 0.0, 0.0),
            (-1.0, -0.0, 0.0),
            (-1.0, tiny, 0.0),
            (1.0, 0.0, PI),
            (1.0, -0.0, PI),
            (0.0, -1.0, FRAC_PI_2),
            (0.0, 0.0, 0.0),
        ] {
            assert_eq!(azimuth_from_xy(x, y), want, "({x}, {y})");
        }
        // just below −X: φ in [0, 2π) next to 0 (libm's atan2 rounds −π + 10⁻³⁰⁰ to −π)
        let p = azimuth_from_xy(-1.0, -tiny);
        assert!((0.0..1e-15).contains(&p), "{p}");
        // the unchecked angles are light_polar's wherever it is defined
        for d in [
            DVec3::new(1e-9, -1e-9, -1.0),
            DVec3::new(-1e-200, 1e-200, 1.0),
            DVec3::new(0.3, -0.4, 0.5),
            DVec3::new(0.0, 0.0, 3.0),
        ] {
            assert_eq!(light_polar(d), Some(polar_angles(d)), "{d}");
            assert_eq!(polar_angles(d).0, polar_angle(d));
        }
        assert!(polar_angle(DVec3::NAN).is_nan());
    }

    proptest! {
        #[test]
        fn polar_round_trip(theta in 0.001f64..3.1, phi in 0.0f64..6.2) {
            let d = light_direction(theta, phi);
            let (t, p) = light_polar(d * 3.0).unwrap();
            prop_assert!((t - theta).abs() < 1e-9);
            prop_assert!((p - phi).abs() < 1e-9);
        }

        #[test]
        fn frame_is_orthonormal(x in -1.0f64..1.0, y in -1.0f64..1.0, z in -1.0f64..1.0) {
            let v = DVec3::new(x, y, z);
            prop_assume!(v.length() > 1e-3);
            let n = v.normalize();
            let f = Frame::from_normal(n);
            prop_assert!((f.t.length() - 1.0).abs() < 1e-12);
            prop_assert!((f.b.length() - 1.0).abs() < 1e-12);
            prop_assert!(f.t.dot(f.b).abs() < 1e-12);
            prop_assert!(f.t.dot(n).abs() < 1e-12);
            prop_assert!((f.t.cross(f.b) - n).length() < 1e-12);
            let w = DVec3::new(0.3, -0.2, 0.7);
            prop_assert!((f.to_world(f.to_local(w)) - w).length() < 1e-12);
        }
    }
}
