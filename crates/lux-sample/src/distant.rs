//! DistantLight (UsdLux `DistantLight`: emits along local −Z; `inputs:angle` is the angular
//! diameter in degrees, clipped to \[0, 360)).

use crate::error::{SampleError, finite};
use crate::transform::LightTransform;
use crate::warp::sample_uniform_cone;
use crate::{LightSample, Reference, Strategy};
use core::f64::consts::TAU;
use glam::DVec3;
use lux_math::Frame;

/// A distant light: a cone of directions of half-angle θmax = clamp(angle/2, 0, π) around the
/// direction *towards* the light, which is the light's local +Z mapped to world (emission is
/// along −Z). Only the rotation of the transform matters; scale and shear merely change which
/// world direction the +Z axis maps to (L·ẑ normalised), as in USD.
#[derive(Clone, Copy, Debug)]
pub struct DistantLight {
    axis: DVec3,
    frame: Frame,
    one_minus_cos: f64,
}

impl DistantLight {
    /// From UsdLux `inputs:angle` (degrees; NaN/inf rejected, negatives give 0, ≥ 360 gives the
    /// whole sphere) and the light-to-world transform.
    pub fn new(angle_degrees: f64, xf: &LightTransform) -> Result<Self, SampleError> {
        let angle = finite("angle", angle_degrees)?;
        let theta_max = (0.5 * angle.to_radians()).clamp(0.0, core::f64::consts::PI);
        let axis = xf.vector(DVec3::Z).normalize();
        // 1 − cos θ = 2 sin²(θ/2): exact for the sun's 0.53°.
        let h = (0.5 * theta_max).sin();
        Ok(Self {
            axis,
            frame: Frame::from_normal(axis),
            one_minus_cos: 2.0 * h * h,
        })
    }

    /// True for `angle` = 0: a delta light.
    #[inline]
    pub fn is_delta(&self) -> bool {
        self.one_minus_cos == 0.0
    }

    /// Unit world direction towards the light (the cone axis): the light's local +Z mapped to
    /// world, `normalize(L ẑ)` (it emits along −Z).
    #[inline]
    pub fn direction(&self) -> DVec3 {
        self.axis
    }

    /// Solid angle of the cone, 2π(1 − cos θmax) (0 for a delta light). With `normalize` off the
    /// irradiance on a facing surface is L·π·sin²θmax; this is the sampling measure.
    #[inline]
    pub fn solid_angle(&self) -> f64 {
        TAU * self.one_minus_cos
    }

    /// Samples a direction; the reference position does not matter. Delta lights return the axis
    /// with `pdf = 1` and `delta = true`.
    #[inline]
    pub fn sample(&self, _r: &Reference, u: [f64; 2]) -> Option<LightSample> {
        let (wi, pdf, delta) = if self.is_delta() {
            (self.axis, 1.0, true)
        } else {
            let w = self
                .frame
                .to_world(sample_uniform_cone(u, self.one_minus_cos));
            (w, 1.0 / (TAU * self.one_minus_cos), false)
        };
        Some(LightSample {
            point: wi,
            normal: -wi,
            wi,
            distance: f64::INFINITY,
            pdf,
            delta,
        })
    }

    /// [`Self::sample`]: both strategies sample the cone uniformly.
    #[inline]
    pub fn sample_with(
        &self,
        r: &Reference,
        u: [f64; 2],
        _strategy: Strategy,
    ) -> Option<LightSample> {
        self.sample(r, u)
    }

    /// [`Self::pdf`]: both strategies sample the cone uniformly.
    #[inline]
    pub fn pdf_with(&self, r: &Reference, wi: DVec3, _strategy: Strategy) -> f64 {
        self.pdf(r, wi)
    }

    /// Density of direction `wi`: 1/(2π(1 − cos θmax)) inside the cone; 0 outside and for delta
    /// lights (a direction never hits a delta light by chance).
    #[inline]
    pub fn pdf(&self, _r: &Reference, wi: DVec3) -> f64 {
        if self.is_delta() {
            return 0.0;
        }
        let s = self.axis.cross(wi).length_squared();
        let c = self.axis.dot(wi);
        // 1 − cos θ computed without cancellation.
        let omc = if c > 0.0 { s / (1.0 + c) } else { 1.0 - c };
        if omc <= self.one_minus_cos {
            1.0 / (TAU * self.one_minus_cos)
        } else {
            0.0
        }
    }
}
