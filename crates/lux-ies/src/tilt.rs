//! Lamp tilt data (`TILT=` block): how lamp output changes with the lamp's inclination.

/// Lamp-to-luminaire geometry code of a TILT block (LM-63-2002 §5.6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LampGeometry {
    /// 1: lamp base-up or base-down, vertical.
    Vertical,
    /// 2: lamp horizontal, its axis stays horizontal as the luminaire tilts (0° plane parallel).
    HorizontalParallel,
    /// 3: lamp horizontal, tilting about its own axis (0° plane perpendicular).
    HorizontalPerpendicular,
}

impl LampGeometry {
    /// The code as written in the file (1, 2, 3).
    pub const fn code(self) -> i64 {
        match self {
            LampGeometry::Vertical => 1,
            LampGeometry::HorizontalParallel => 2,
            LampGeometry::HorizontalPerpendicular => 3,
        }
    }

    /// From the file code; `None` for anything but 1, 2, 3.
    pub const fn from_code(c: i64) -> Option<LampGeometry> {
        match c {
            1 => Some(LampGeometry::Vertical),
            2 => Some(LampGeometry::HorizontalParallel),
            3 => Some(LampGeometry::HorizontalPerpendicular),
            _ => None,
        }
    }
}

/// The data of a `TILT=INCLUDE` block or a TILT file: geometry, angles (degrees, increasing) and
/// the multiplying factor at each angle.
#[derive(Clone, Debug, PartialEq)]
pub struct TiltData {
    /// Lamp-to-luminaire geometry.
    pub geometry: LampGeometry,
    /// Tilt angles in degrees, strictly increasing.
    pub angles_deg: Vec<f64>,
    /// Candela multiplying factors, one per angle.
    pub factors: Vec<f64>,
}

impl TiltData {
    /// The multiplying factor at tilt `angle_deg` (degrees): linear interpolation between the tabulated
    /// angles, held constant beyond the first and last. A NaN angle or empty table gives 1.
    pub fn tilt_factor(&self, angle_deg: f64) -> f64 {
        let angle = angle_deg;
        let (a, f) = (&self.angles_deg, &self.factors);
        let n = a.len().min(f.len());
        if n == 0 || angle.is_nan() {
            return 1.0;
        }
        if angle <= a[0] {
            return f[0];
        }
        if angle >= a[n - 1] {
            return f[n - 1];
        }
        let i = a[..n].partition_point(|&x| x <= angle) - 1;
        let t = (angle - a[i]) / (a[i + 1] - a[i]);
        lux_math::lerp(t, f[i], f[i + 1])
    }
}

/// The `TILT=` line and what it refers to.
#[derive(Clone, Debug, PartialEq)]
pub enum Tilt {
    /// `TILT=NONE`: output does not depend on lamp inclination.
    None,
    /// `TILT=INCLUDE`: the tilt block follows in this file.
    Include(TiltData),
    /// `TILT=<file>`: the tilt block lives in another file; `data` is `Some` when the caller's
    /// resolver supplied it.
    File {
        /// The file name as written.
        name: String,
        /// The resolved data, if any.
        data: Option<TiltData>,
    },
}

impl Tilt {
    /// The tilt data, if present (included or resolved).
    pub fn data(&self) -> Option<&TiltData> {
        match self {
            Tilt::None => None,
            Tilt::Include(d) => Some(d),
            Tilt::File { data, .. } => data.as_ref(),
        }
    }

    /// The multiplying factor at lamp tilt `angle_deg` (degrees); 1 without tilt data.
    pub fn tilt_factor(&self, angle_deg: f64) -> f64 {
        self.data().map_or(1.0, |d| d.tilt_factor(angle_deg))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factor_interpolates_and_clamps() {
        let d = TiltData {
            geometry: LampGeometry::Vertical,
            angles_deg: vec![0.0, 15.0, 30.0],
            factors: vec![1.0, 0.95, 0.94],
        };
        assert_eq!(d.tilt_factor(-5.0), 1.0);
        assert_eq!(d.tilt_factor(15.0), 0.95);
        assert!((d.tilt_factor(7.5) - 0.975).abs() < 1e-15);
        assert_eq!(d.tilt_factor(90.0), 0.94);
        assert_eq!(d.tilt_factor(f64::NAN), 1.0);
        assert_eq!(Tilt::None.tilt_factor(10.0), 1.0);
    }
}
