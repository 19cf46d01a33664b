//! The expanded photometric web: every symmetry unfolded, angles in radians, values in candela,
//! evaluated in the light-space convention of the spec (θ from the light's −Z, φ the IES
//! horizontal angle: 0 towards −X, 90° towards −Y).

use crate::error::IesError;
use crate::file::{IesFile, PhotometricType};
use crate::interp::{IntervalTable, hermite};
use core::f64::consts::{FRAC_PI_2, PI, TAU};
use lux_math::Profile;

/// The horizontal symmetry a file's angle set declares (LM-63-2002 §5.12 and LM-63-1995).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Symmetry {
    /// A single horizontal angle: the same in every plane (type C), or in every H (types A/B).
    Axial,
    /// Type C 0..90: symmetric about the 0–180 and 90–270 planes.
    Quadrant,
    /// Type C 0..180: symmetric about the 0–180 plane.
    Bilateral0To180,
    /// Type C 90..270 (LM-63-1995): symmetric about the 90–270 plane.
    Bilateral90To270,
    /// Type C 0..360 (or 0..h with 180 < h < 360, closed periodically): no symmetry.
    Full,
    /// Types A/B 0..90: symmetric about H = 0.
    LateralMirror,
    /// Types A/B −90..90: no symmetry.
    Lateral,
}

/// Interpolation between the tabulated angles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Interpolation {
    /// Linear in the vertical, then in the horizontal angle (the reference's interpolant).
    #[default]
    Bilinear,
    /// Cubic Hermite with Catmull-Rom tangents (generalised to uneven spacing) in both angles,
    /// clamped at 0 candela.
    Bicubic,
}

/// An LM-63 distribution ready for evaluation: symmetry expanded, angles in radians in the file's
/// native system (type C: vertical = θ from nadir, horizontal = φ over the full 0..2π; types A/B:
/// vertical = elevation V, horizontal = H over −π/2..π/2), values in candela
/// (raw × [`IesFile::candela_scale`]).
///
/// Type B directions: `d = (−cos V sin H, sin V, −cos V cos H)` in light space, polar axis +Y
/// (H = 0, V = 0 is the light's −Z). Type A: `d = (sin V, −cos V sin H, −cos V cos H)`, polar axis
/// +X (type B turned 90° about the light axis). Directions outside the measured range give 0.
#[derive(Clone, Debug, PartialEq)]
pub struct PhotometricWeb {
    ptype: PhotometricType,
    symmetry: Symmetry,
    profile: Profile,
    v: Vec<f64>,
    h: Vec<f64>,
    /// `h.len()` rows of `v.len()` values.
    values: Vec<f64>,
    vtab: IntervalTable,
    htab: IntervalTable,
    constant_h: bool,
    periodic: bool,
    max_cd: f64,
    max_at: (f64, f64),
    flux_exact: f64,
    flux_midpoint: f64,
}

impl PhotometricWeb {
    /// Expands `file` (validated first), scaling raw values by `file.candela_scale(profile)`.
    pub fn new(file: &IesFile, profile: Profile) -> Result<PhotometricWeb, IesError> {
        file.validate()?;
        let scale = file.candela_scale(profile);
        let nv = file.num_vertical();
        let ha = &file.horizontal_angles;
        let col = |i: usize| &file.candela[i * nv..(i + 1) * nv];
        // (angle in degrees, source column) in increasing angle order
        let mut planes: Vec<(f64, usize)> = Vec::with_capacity(4 * ha.len() + 2);
        let n = ha.len();
        let last = ha[n - 1];
        let symmetry = match file.photometric_type {
            PhotometricType::C => {
                if n == 1 {
                    planes.push((0.0, 0));
                    planes.push((360.0, 0));
                    Symmetry::Axial
                } else if ha[0] == 90.0 {
                    // 90..270, mirrored about the 90-270 plane: h -> 180 - h (mod 360)
                    planes.extend(
                        ha.iter()
                            .enumerate()
                            .rev()
                            .filter(|(_, a)| **a >= 90.0 && **a <= 180.0)
                            .map(|(i, a)| (180.0 - a, i)),
                    );
                    planes.extend(
                        ha.iter()
                            .enumerate()
                            .filter(|(_, a)| **a > 90.0)
                            .map(|(i, a)| (*a, i)),
                    );
                    planes.extend(
                        ha.iter()
                            .enumerate()
                            .rev()
                            .filter(|(_, a)| **a >= 180.0 && **a < 270.0)
                            .map(|(i, a)| (540.0 - a, i)),
                    );
                    Symmetry::Bilateral90To270
                } else if last == 90.0 {
                    planes.extend(ha.iter().enumerate().map(|(i, a)| (*a, i)));
                    planes.extend(
                        ha.iter()
                            .enumerate()
                            .rev()
                            .skip(1)
                            .map(|(i, a)| (180.0 - a, i)),
                    );
                    planes.extend(ha.iter().enumerate().skip(1).map(|(i, a)| (180.0 + a, i)));
                    planes.extend(
                        ha.iter()
                            .enumerate()
                            .rev()
                            .skip(1)
                            .map(|(i, a)| (360.0 - a, i)),
                    );
                    Symmetry::Quadrant
                } else if last == 180.0 {
                    planes.extend(ha.iter().enumerate().map(|(i, a)| (*a, i)));
                    planes.extend(
                        ha.iter()
                            .enumerate()
                            .rev()
                            .skip(1)
                            .map(|(i, a)| (360.0 - a, i)),
                    );
                    Symmetry::Bilateral0To180
                } else {
                    planes.extend(ha.iter().enumerate().map(|(i, a)| (*a, i)));
                    if last < 360.0 {
                        planes.push((360.0, 0));
                    }
                    Symmetry::Full
                }
            }
            PhotometricType::A | PhotometricType::B => {
                if n == 1 {
                    planes.push((-90.0, 0));
                    planes.push((90.0, 0));
                    Symmetry::Axial
                } else if ha[0] == 0.0 {
                    planes.extend(
                        ha.iter()
                            .enumerate()
                            .rev()
                            .filter(|(_, a)| **a > 0.0)
                            .map(|(i, a)| (-a, i)),
                    );
                    planes.extend(ha.iter().enumerate().map(|(i, a)| (*a, i)));
                    Symmetry::LateralMirror
                } else {
                    planes.extend(ha.iter().enumerate().map(|(i, a)| (*a, i)));
                    Symmetry::Lateral
                }
            }
        };
        let v: Vec<f64> = file
            .vertical_angles
            .iter()
            .map(|a| a.to_radians())
            .collect();
        let h: Vec<f64> = planes.iter().map(|p| p.0.to_radians()).collect();
        let mut values = Vec::with_capacity(planes.len() * nv);
        for &(_, src) in &planes {
            values.extend(col(src).iter().map(|c| c * scale));
        }
        Ok(Self::from_parts(
            file.photometric_type,
            symmetry,
            profile,
            v,
            h,
            values,
        ))
    }

    fn from_parts(
        ptype: PhotometricType,
        symmetry: Symmetry,
        profile: Profile,
        v: Vec<f64>,
        h: Vec<f64>,
        values: Vec<f64>,
    ) -> PhotometricWeb {
        let vtab = IntervalTable::new(&v);
        let htab = IntervalTable::new(&h);
        let nv = v.len();
        let mut max_cd = 0.0;
        let mut max_idx = (0, 0);
        for (k, &c) in values.iter().enumerate() {
            if c > max_cd {
                max_cd = c;
                max_idx = (k / nv, k % nv);
            }
        }
        let mut web = PhotometricWeb {
            ptype,
            symmetry,
            profile,
            constant_h: symmetry == Symmetry::Axial,
            periodic: ptype == PhotometricType::C,
            v,
            h,
            values,
            vtab,
            htab,
            max_cd,
            max_at: (0.0, 0.0),
            flux_exact: 0.0,
            flux_midpoint: 0.0,
        };
        web.max_at = web.native_to_light(web.v[max_idx.1], web.h[max_idx.0]);
        web.flux_exact = crate::flux::exact(&web);
        web.flux_midpoint = crate::flux::midpoint(&web);
        web
    }

    /// Photometric type of the source file.
    pub fn photometric_type(&self) -> PhotometricType {
        self.ptype
    }

    /// The horizontal symmetry that was expanded.
    pub fn symmetry(&self) -> Symmetry {
        self.symmetry
    }

    /// The profile whose candela scale was applied (see [`IesFile::candela_scale`]).
    pub fn profile(&self) -> Profile {
        self.profile
    }

    /// Vertical angles in radians (type C: θ from nadir; A/B: elevation V).
    pub fn vertical_angles(&self) -> &[f64] {
        &self.v
    }

    /// Expanded horizontal angles in radians (type C: 0..2π inclusive; A/B: −π/2..π/2).
    pub fn horizontal_angles(&self) -> &[f64] {
        &self.h
    }

    /// Candela values, one row of `vertical_angles().len()` per expanded horizontal angle.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Candela at expanded horizontal index `h`, vertical index `v`.
    pub fn value(&self, h: usize, v: usize) -> f64 {
        self.values[h * self.v.len() + v]
    }

    /// `(first, last)` vertical angle in radians.
    pub fn vertical_range(&self) -> (f64, f64) {
        (self.v[0], self.v[self.v.len() - 1])
    }

    /// `true` when the vertical range spans more than π/2 + 0.1 rad (95.73°): the profile is taken
    /// to cover the sphere and its mean intensity is flux / 4π; otherwise flux / 2π (spec §3).
    pub fn covers_sphere(&self) -> bool {
        let (a, b) = self.vertical_range();
        b - a > FRAC_PI_2 + 0.1
    }

    /// Largest candela value of the web.
    pub fn max_candela(&self) -> f64 {
        self.max_cd
    }

    /// Light-space `(θ, φ)` in radians of the (first) largest candela value.
    pub fn max_direction(&self) -> (f64, f64) {
        self.max_at
    }

    /// Luminous flux (lm) = ∫ I dω of the bilinear interpolant, integrated exactly
    /// (closed form per cell; see [`crate::flux`]).
    pub fn flux_exact(&self) -> f64 {
        self.flux_exact
    }

    /// Luminous flux (lm) by the midpoint rule of the reference renderer: per cell
    /// Δh·Δv·sin(v + Δv/2)·(mean of the four corners) (cos for types A/B).
    pub fn flux_midpoint(&self) -> f64 {
        self.flux_midpoint
    }

    /// Flux by the method `profile` prescribes: `Spec` exact, `HdEmbree` midpoint.
    pub fn flux(&self, profile: Profile) -> f64 {
        match profile {
            Profile::Spec => self.flux_exact,
            Profile::HdEmbree => self.flux_midpoint,
        }
    }

    /// The `shaping:ies:normalize` divisor (mean intensity, cd): [`flux`](Self::flux)`(profile)`
    /// divided by 4π, or by 2π when the vertical range spans ≤ 95.73° (see
    /// [`covers_sphere`](Self::covers_sphere)). The candela scale is the one chosen at
    /// construction; for `ies:normalize` the LM-63-2019 generation-type factor cancels anyway.
    pub fn mean_intensity(&self, profile: Profile) -> f64 {
        let solid = if self.covers_sphere() { 2.0 * TAU } else { TAU };
        self.flux(profile) / solid
    }

    /// Converts native (vertical, horizontal) radians to light-space (θ, φ).
    pub fn native_to_light(&self, v: f64, h: f64) -> (f64, f64) {
        match self.ptype {
            PhotometricType::C => (v, h.rem_euclid(TAU)),
            _ => {
                let (sv, cv) = v.sin_cos();
                let (sh, ch) = h.sin_cos();
                let d = if self.ptype == PhotometricType::B {
                    glam::DVec3::new(-cv * sh, sv, -cv * ch)
                } else {
                    glam::DVec3::new(sv, -cv * sh, -cv * ch)
                };
                lux_math::light_polar(d).unwrap_or((0.0, 0.0))
            }
        }
    }

    /// Converts light-space (θ, φ) to native (vertical, horizontal) radians (types A/B; type C is
    /// the identity with φ wrapped into [0, 2π)).
    pub fn light_to_native(&self, theta: f64, phi: f64) -> (f64, f64) {
        match self.ptype {
            PhotometricType::C => (theta, phi.rem_euclid(TAU)),
            _ => {
                let d = lux_math::light_direction(theta, phi);
                let (x, y, z) = if self.ptype == PhotometricType::B {
                    (-d.x, d.y, -d.z)
                } else {
                    (-d.y, d.x, -d.z)
                };
                // x = cos V sin H, y = sin V, z = cos V cos H
                (y.clamp(-1.0, 1.0).asin(), x.atan2(z))
            }
        }
    }

    /// Intensity in candela towards light-space (θ, φ) (radians), bilinear.
    ///
    /// Edge rules (spec §3, type C): θ < 0 (or NaN) gives 0; θ ≥ π gives the value at the last
    /// vertical angle (interpolated in φ); otherwise θ outside the vertical range gives 0. φ is
    /// taken modulo 2π. Types A/B: the direction is converted to (V, H); outside the measured
    /// range gives 0.
    #[inline]
    pub fn intensity(&self, theta: f64, phi: f64) -> f64 {
        self.intensity_with(theta, phi, Interpolation::Bilinear)
    }

    /// [`intensity`](Self::intensity) with a choice of interpolation.
    #[inline]
    pub fn intensity_with(&self, theta: f64, phi: f64, interp: Interpolation) -> f64 {
        if self.ptype == PhotometricType::C {
            if !(theta >= 0.0) {
                return 0.0;
            }
            let phi = if (0.0..TAU).contains(&phi) {
                phi
            } else if phi.is_finite() {
                phi.rem_euclid(TAU)
            } else {
                return 0.0;
            };
            if theta >= PI {
                let nv = self.v.len();
                return self.eval_at(nv - 2, 1.0, self.v[nv - 1], phi, interp);
            }
            self.native(theta, phi, interp)
        } else {
            let (v, h) = self.light_to_native(theta, phi);
            self.native(v, h, interp)
        }
    }

    /// Intensity at native (vertical, horizontal) radians; 0 outside the measured range.
    #[inline]
    pub fn native(&self, v: f64, h: f64, interp: Interpolation) -> f64 {
        let nv = self.v.len();
        if !(v >= self.v[0] && v <= self.v[nv - 1]) {
            return 0.0;
        }
        let vi = self.vtab.find(&self.v, v);
        let vt = (v - self.v[vi]) / (self.v[vi + 1] - self.v[vi]);
        self.eval_at(vi, vt, v, h, interp)
    }

    #[inline(always)]
    fn eval_at(&self, vi: usize, vt: f64, v: f64, h: f64, interp: Interpolation) -> f64 {
        let nv = self.v.len();
        let nh = self.h.len();
        if interp == Interpolation::Bicubic {
            return self.bicubic(vi, v, h);
        }
        if self.constant_h {
            let r = &self.values[..nv];
            return r[vi] + vt * (r[vi + 1] - r[vi]);
        }
        if !(h >= self.h[0] && h <= self.h[nh - 1]) {
            return 0.0;
        }
        let hi = self.htab.find(&self.h, h);
        let ht = (h - self.h[hi]) / (self.h[hi + 1] - self.h[hi]);
        let r0 = &self.values[hi * nv..hi * nv + nv];
        let r1 = &self.values[(hi + 1) * nv..(hi + 1) * nv + nv];
        let a = r0[vi] + vt * (r0[vi + 1] - r0[vi]);
        let b = r1[vi] + vt * (r1[vi + 1] - r1[vi]);
        a + ht * (b - a)
    }

    fn bicubic(&self, vi: usize, v: f64, h: f64) -> f64 {
        let nv = self.v.len();
        let nh = self.h.len();
        let vidx = [vi.saturating_sub(1), vi, vi + 1, (vi + 2).min(nv - 1)];
        let vx = vidx.map(|k| self.v[k]);
        let row = |hk: usize| {
            let r = &self.values[hk * nv..hk * nv + nv];
            hermite(v, vx, vidx.map(|k| r[k])).max(0.0)
        };
        if self.constant_h {
            return row(0);
        }
        if !(h >= self.h[0] && h <= self.h[nh - 1]) {
            return 0.0;
        }
        let hi = self.htab.find(&self.h, h);
        // neighbours in h: periodic for type C (h[0] = 0 and h[nh-1] = 2π are the same plane)
        let (i0, x0) = if hi > 0 {
            (hi - 1, self.h[hi - 1])
        } else if self.periodic && nh > 2 {
            (nh - 2, self.h[nh - 2] - TAU)
        } else {
            (hi, self.h[hi])
        };
        let (i3, x3) = if hi + 2 < nh {
            (hi + 2, self.h[hi + 2])
        } else if self.periodic && nh > 2 {
            (1, self.h[1] + TAU)
        } else {
            (hi + 1, self.h[hi + 1])
        };
        let hx = [x0, self.h[hi], self.h[hi + 1], x3];
        let p = [row(i0), row(hi), row(hi + 1), row(i3)];
        hermite(h, hx, p).max(0.0)
    }
}
