//! Spatial and directional emission bounds of a light, the input of the light BVH.
//!
//! This is a plain data struct the renderer fills (from the light's geometry and, for shaped
//! lights, from lux-shaping's cone/IES bounds) so that lux-sample does not depend on lux-shaping.

use crate::error::{SampleError, finite};
use glam::DVec3;

/// A cone bounding the emission of a light (Conty Estevez & Kulla 2018, §3; pbrt-v4 §12.6.3):
/// every emitting surface normal lies within θo of `axis`, and every emitted direction lies
/// within θe of some such normal. For a one-sided planar light θo = 0, θe = π/2; a sphere has
/// θo = π, θe = π/2; a ShapingAPI cone or IES profile narrows θe of a planar light to
/// min(θs, π/2), θs being the polar angle beyond which the shaping emits nothing
/// (`lux_shaping::Shaping::emission_half_angle`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmissionCone {
    /// Unit axis of the cone of normals.
    pub axis: DVec3,
    /// cos θo: spread of the normals around the axis.
    pub cos_theta_o: f64,
    /// cos θe: spread of emission around each normal.
    pub cos_theta_e: f64,
}

impl EmissionCone {
    /// Emits in every direction (θo = π, θe = π/2).
    pub const SPHERE: Self = Self {
        axis: DVec3::Z,
        cos_theta_o: -1.0,
        cos_theta_e: 0.0,
    };

    /// A cone from its axis and angles in radians (θo, θe clamped to \[0, π\]).
    pub fn new(axis: DVec3, theta_o: f64, theta_e: f64) -> Result<Self, SampleError> {
        finite("theta_o", theta_o)?;
        finite("theta_e", theta_e)?;
        let a = axis.normalize_or_zero();
        if !a.is_finite() || a == DVec3::ZERO {
            return Err(SampleError::BadTransform(
                "emission axis must be a non-zero finite vector",
            ));
        }
        Ok(Self {
            axis: a,
            cos_theta_o: theta_o.clamp(0.0, core::f64::consts::PI).cos(),
            cos_theta_e: theta_e.clamp(0.0, core::f64::consts::PI).cos(),
        })
    }

    /// Smallest cone containing both cones of normals; θe is the larger of the two.
    pub fn union(&self, other: &Self) -> Self {
        let cos_e = self.cos_theta_e.min(other.cos_theta_e);
        let ta = self.cos_theta_o.clamp(-1.0, 1.0).acos();
        let tb = other.cos_theta_o.clamp(-1.0, 1.0).acos();
        let td = self.axis.dot(other.axis).clamp(-1.0, 1.0).acos();
        let pi = core::f64::consts::PI;
        if (td + tb).min(pi) <= ta {
            return Self {
                cos_theta_e: cos_e,
                ..*self
            };
        }
        if (td + ta).min(pi) <= tb {
            return Self {
                cos_theta_e: cos_e,
                ..*other
            };
        }
        let to = 0.5 * (ta + td + tb);
        if to >= pi {
            return Self {
                axis: self.axis,
                cos_theta_o: -1.0,
                cos_theta_e: cos_e,
            };
        }
        // Rotate a's axis towards b's by (to − ta).
        let rot_axis = self.axis.cross(other.axis);
        if rot_axis.length_squared() < 1e-24 {
            return Self {
                axis: self.axis,
                cos_theta_o: -1.0,
                cos_theta_e: cos_e,
            };
        }
        let q = glam::DQuat::from_axis_angle(rot_axis.normalize(), to - ta);
        Self {
            axis: q * self.axis,
            cos_theta_o: to.cos(),
            cos_theta_e: cos_e,
        }
    }
}

/// World-space bounds of one light: box, power and emission cone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightBounds {
    /// Box minimum corner.
    pub min: DVec3,
    /// Box maximum corner.
    pub max: DVec3,
    /// Emitted power (any consistent unit, e.g. luminance × area × π); 0 excludes the light.
    pub phi: f64,
    /// Directional bounds.
    pub cone: EmissionCone,
    /// True if the light emits from both sides of its normals (the cone is mirrored).
    pub two_sided: bool,
}

impl LightBounds {
    /// Validates a finite box (min ≤ max) and a finite, non-negative power.
    pub fn new(
        min: DVec3,
        max: DVec3,
        phi: f64,
        cone: EmissionCone,
        two_sided: bool,
    ) -> Result<Self, SampleError> {
        if !(min.is_finite() && max.is_finite()) || min.cmpgt(max).any() {
            return Err(SampleError::BadSize {
                field: "bounds",
                expected: "finite box with min <= max".into(),
                got: 0,
            });
        }
        if !(phi.is_finite() && phi >= 0.0) {
            return Err(SampleError::BadWeight {
                field: "phi",
                index: 0,
                value: phi,
            });
        }
        Ok(Self {
            min,
            max,
            phi,
            cone,
            two_sided,
        })
    }

    /// Union of two bounds (box union, power sum, cone union).
    pub fn union(&self, o: &Self) -> Self {
        Self {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
            phi: self.phi + o.phi,
            cone: self.cone.union(&o.cone),
            two_sided: self.two_sided || o.two_sided,
        }
    }

    /// Box centre.
    #[inline]
    pub fn centroid(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    /// Conservative importance of this cluster for a receiver at `p` with normal `n` (zero for
    /// none): Φ·cos θ'/d² × cos θ'ᵢ, where θ' = max(0, θw − θo − θb) is the smallest angle
    /// between the cone of emitted directions and the direction to `p` (θw: axis to `p`,
    /// θb: half-angle of the bounding sphere seen from `p`), zero if θ' ≥ θe; θ'ᵢ likewise for
    /// the receiver's normal, θᵢ measured from `n` itself: a receiver with a normal takes light
    /// from its side of the surface only (as [`Reference`](crate::Reference)'s projected solid
    /// angle `∫ max(0, n·ω) dω` does), so a cluster wholly below its horizon
    /// (θᵢ − θb ≥ π/2) has importance 0 — pass a zero `n` for a receiver lit from both sides.
    /// d² is clamped below by the squared half-diagonal so that points inside a cluster keep
    /// finite importance (Conty Estevez & Kulla 2018, eq. 3; their `|cos θᵢ|` serves two-sided
    /// receivers).
    #[inline]
    pub fn importance(&self, p: DVec3, n: DVec3) -> f64 {
        let pc = self.centroid();
        let half_diag2 = 0.25 * (self.max - self.min).length_squared();
        let v = p - pc;
        let dist2 = v.length_squared();
        let d2 = dist2.max(half_diag2).max(1e-300);
        let wi = if dist2 > 0.0 {
            v / dist2.sqrt()
        } else {
            self.cone.axis
        };
        let mut cos_w = self.cone.axis.dot(wi);
        if self.two_sided {
            cos_w = cos_w.abs();
        }
        let sin_w = (1.0 - cos_w * cos_w).max(0.0).sqrt();
        let cos_b = if dist2 <= half_diag2 {
            -1.0
        } else {
            (1.0 - half_diag2 / dist2).max(0.0).sqrt()
        };
        let sin_b = (1.0 - cos_b * cos_b).max(0.0).sqrt();
        let cos_o = self.cone.cos_theta_o;
        let sin_o = (1.0 - cos_o * cos_o).max(0.0).sqrt();
        let (sin_x, cos_x) = sub_clamped(sin_w, cos_w, sin_o, cos_o);
        let (_, cos_p) = sub_clamped(sin_x, cos_x, sin_b, cos_b);
        if cos_p <= self.cone.cos_theta_e {
            return 0.0;
        }
        let mut imp = self.phi * cos_p / d2;
        if n != DVec3::ZERO {
            // (`wi` points from the cluster to `p`: the receiver looks along −wi)
            let cos_i = -wi.dot(n);
            let sin_i = (1.0 - cos_i * cos_i).max(0.0).sqrt();
            let (_, cos_pi) = sub_clamped(sin_i, cos_i, sin_b, cos_b);
            imp *= cos_pi;
        }
        imp.max(0.0)
    }
}

/// (sin, cos) of max(0, a − b) from the sines and cosines of a and b.
#[inline]
fn sub_clamped(sa: f64, ca: f64, sb: f64, cb: f64) -> (f64, f64) {
    if ca > cb {
        (0.0, 1.0)
    } else {
        (sa * cb - ca * sb, ca * cb + sa * sb)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cone_union_contains_both() {
        let a = EmissionCone::new(DVec3::Z, 0.2, 1.0).unwrap();
        let b = EmissionCone::new(DVec3::X, 0.1, 0.5).unwrap();
        let u = a.union(&b);
        // Both axes within θo of the union's axis (plus their own spread).
        let to = u.cos_theta_o.acos();
        assert!(u.axis.dot(DVec3::Z).acos() + 0.2 <= to + 1e-12);
        assert!(u.axis.dot(DVec3::X).acos() + 0.1 <= to + 1e-12);
        // (θa + θd + θb)/2 = (0.2 + π/2 + 0.1)/2.
        assert!((to - 0.5 * (0.3 + core::f64::consts::FRAC_PI_2)).abs() < 1e-12);
        assert_eq!(u.cos_theta_e, 1.0f64.cos());
    }

    #[test]
    fn importance_falls_off_and_respects_cone() {
        let cone = EmissionCone::new(DVec3::NEG_Z, 0.0, core::f64::consts::FRAC_PI_2).unwrap();
        let b = LightBounds::new(
            DVec3::new(-0.01, -0.01, 0.0),
            DVec3::new(0.01, 0.01, 0.0),
            1.0,
            cone,
            false,
        )
        .unwrap();
        let below1 = b.importance(DVec3::new(0.0, 0.0, -1.0), DVec3::ZERO);
        let below2 = b.importance(DVec3::new(0.0, 0.0, -2.0), DVec3::ZERO);
        // A point on the axis: cos θ' = 1, importance Φ/d².
        assert!((below1 - 1.0).abs() < 1e-12 && (below2 - 0.25).abs() < 1e-12);
        // Behind a one-sided light: nothing.
        assert_eq!(b.importance(DVec3::new(0.0, 0.0, 1.0), DVec3::ZERO), 0.0);
        assert!(LightBounds::new(DVec3::ONE, DVec3::ZERO, 1.0, cone, false).is_err());
        assert!(LightBounds::new(DVec3::ZERO, DVec3::ONE, f64::NAN, cone, false).is_err());
    }
}
