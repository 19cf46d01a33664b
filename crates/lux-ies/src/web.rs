//! The expanded photometric web: every symmetry unfolded, angles in radians, values in candela,
//! evaluated in the light-space convention of the spec (θ from the light's −Z, φ the IES
//! horizontal angle: 0 towards −X, 90° towards −Y).

use crate::error::IesError;
use crate::file::{IesFile, PhotometricType};
use crate::interp::Axis;
use core::f64::consts::{FRAC_PI_2, PI, TAU};
use lux_math::Profile;
use std::borrow::Cow;

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
    vaxis: Axis,
    haxis: Axis,
    constant_h: bool,
    max_cd: f64,
    max_at: (f64, f64),
    flux_exact: f64,
    flux_midpoint: f64,
}

/// The horizontal angles and candela columns to expand. A type C 90..270 file is mirrored about
/// its 180° plane (h → 180° − h), so that plane must be tabulated for the mirrored web to cover
/// the full circle. When the file has no 180° plane, one is inserted by linear interpolation
/// between its two neighbours: the bilinear interpolant over 90..270 is unchanged (the inserted
/// knot lies on it), and its mirror image then closes the circle at 0° and 360°.
fn with_mirror_plane(file: &IesFile) -> (Cow<'_, [f64]>, Cow<'_, [f64]>) {
    let ha = &file.horizontal_angles_deg;
    let nv = file.num_vertical();
    let needs_plane = file.photometric_type == PhotometricType::C
        && ha.len() > 1
        && ha[0] == 90.0
        && !ha.contains(&180.0);
    if !needs_plane {
        return (Cow::Borrowed(ha), Cow::Borrowed(&file.candela));
    }
    // validated: strictly increasing from 90 to 270, so 180 has a neighbour on each side
    let j = ha.partition_point(|&a| a < 180.0);
    let t = (180.0 - ha[j - 1]) / (ha[j] - ha[j - 1]);
    let mut angles = Vec::with_capacity(ha.len() + 1);
    angles.extend_from_slice(&ha[..j]);
    angles.push(180.0);
    angles.extend_from_slice(&ha[j..]);
    let mut cd = Vec::with_capacity(file.candela.len() + nv);
    cd.extend_from_slice(&file.candela[..j * nv]);
    let (lo, hi) = (
        &file.candela[(j - 1) * nv..j * nv],
        &file.candela[j * nv..(j + 1) * nv],
    );
    cd.extend(lo.iter().zip(hi).map(|(a, b)| lux_math::lerp(t, *a, *b)));
    cd.extend_from_slice(&file.candela[j * nv..]);
    (Cow::Owned(angles), Cow::Owned(cd))
}

impl PhotometricWeb {
    /// The profile of UsdLux `inputs:shaping:ies:file` (spec §3) as a web over the whole sphere:
    /// `file` validated, its symmetry expanded (types A, B, C), raw values scaled by
    /// `file.candela_scale(profile)` (lamps × multiplier × ballast factor, and under
    /// [`Profile::HdEmbree`] the LM-63-2019 third factor). The web keeps `profile`, which also
    /// chooses the flux rule of [`flux`](Self::flux) and
    /// [`mean_intensity`](Self::mean_intensity) (exact under `Spec`, midpoint under `HdEmbree`).
    pub fn new(file: &IesFile, profile: Profile) -> Result<PhotometricWeb, IesError> {
        file.validate()?;
        let scale = file.candela_scale(profile);
        let nv = file.num_vertical();
        let (ha, candela) = with_mirror_plane(file);
        let (ha, candela) = (&ha[..], &candela[..]);
        let col = |i: usize| &candela[i * nv..(i + 1) * nv];
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
            .vertical_angles_deg
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
        let vaxis = Axis::new(&v, None);
        let haxis = Axis::new(&h, (ptype == PhotometricType::C).then_some(TAU));
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
            v,
            h,
            values,
            vaxis,
            haxis,
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

    /// The spacing of the vertical angles (LM-63 vertical angle list, radians) when they are
    /// evenly spaced — every angle within 10⁻¹² of a step of `first + k·step`, which angles
    /// converted from degrees meet — else `None`. Evenly spaced axes are located by arithmetic
    /// (`k = ⌊(x − first)/step⌋`) rather than by a bin table.
    pub fn vertical_step(&self) -> Option<f64> {
        self.vaxis.step()
    }

    /// [`vertical_step`](Self::vertical_step) for the expanded horizontal angles.
    pub fn horizontal_step(&self) -> Option<f64> {
        self.haxis.step()
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

    /// Flux (lm) by the method the web's [`profile`](Self::profile) prescribes: `Spec`
    /// [`flux_exact`](Self::flux_exact), `HdEmbree` [`flux_midpoint`](Self::flux_midpoint).
    pub fn flux(&self) -> f64 {
        match self.profile {
            Profile::Spec => self.flux_exact,
            Profile::HdEmbree => self.flux_midpoint,
        }
    }

    /// The `inputs:shaping:ies:normalize` divisor (mean intensity, cd):
    /// `Φ / 4π`, or `Φ / 2π` when the vertical range spans ≤ 95.73° (see
    /// [`covers_sphere`](Self::covers_sphere)), with Φ the [`flux`](Self::flux) of the web's
    /// own [`profile`](Self::profile) (exact under `Spec`, the midpoint rule under
    /// `HdEmbree`). The candela scale is the one chosen at construction; for `ies:normalize`
    /// the LM-63-2019 generation-type factor cancels anyway.
    pub fn mean_intensity(&self) -> f64 {
        let solid = if self.covers_sphere() { 2.0 * TAU } else { TAU };
        self.flux() / solid
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
    /// the identity with φ wrapped into [0, 2π)): V = asin(y), H = atan2(x, z) of the direction
    /// in the type's frame.
    #[inline]
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
    ///
    /// Constant time and allocation-free: on evenly spaced angles the interval is found by
    /// arithmetic, otherwise with a bin table (one load and one comparison); the fraction is a
    /// multiplication by the interval's precomputed reciprocal width, and the bicubic weights'
    /// tangent coefficients are precomputed per interval. The values equal those of the direct
    /// evaluation (bisection, division, the Hermite formula) up to rounding.
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
                return self.eval_at(self.v.len() - 2, 1.0, phi, interp);
            }
            self.native(theta, phi, interp)
        } else {
            let (v, h) = self.light_to_native(theta, phi);
            self.native(v, h, interp)
        }
    }

    /// Intensity at native (vertical, horizontal) radians; 0 outside the measured range.
    #[inline(always)]
    pub fn native(&self, v: f64, h: f64, interp: Interpolation) -> f64 {
        if !(v >= self.vaxis.lo && v <= self.vaxis.hi) {
            return 0.0;
        }
        let (vi, vt) = self.vaxis.locate(&self.v, v);
        self.eval_at(vi, vt, h, interp)
    }

    /// The interpolant in vertical interval `vi` at fraction `vt`, horizontal angle `h`.
    #[inline(always)]
    fn eval_at(&self, vi: usize, vt: f64, h: f64, interp: Interpolation) -> f64 {
        if interp == Interpolation::Bicubic {
            return self.bicubic(vi, vt, h);
        }
        let nv = self.v.len();
        if self.constant_h {
            let r = &self.values[vi..vi + 2];
            return r[0] + vt * (r[1] - r[0]);
        }
        if !(h >= self.haxis.lo && h <= self.haxis.hi) {
            return 0.0;
        }
        let (hi, ht) = self.haxis.locate(&self.h, h);
        // the four corners: rows hi and hi + 1, columns vi and vi + 1
        let k = hi * nv + vi;
        let r = &self.values[k..k + nv + 2];
        let a = r[0] + vt * (r[1] - r[0]);
        let b = r[nv] + vt * (r[nv + 1] - r[nv]);
        a + ht * (b - a)
    }

    /// Bicubic: the Hermite weights of the vertical segment (shared by the four rows), each row
    /// clamped at 0, then the horizontal segment's weights, clamped at 0.
    #[inline(never)]
    fn bicubic(&self, vi: usize, vt: f64, h: f64) -> f64 {
        // the neighbours of `hermite`, computed (not loaded) from `vi`
        let c = self.vaxis.neighbours(vi);
        let wv = self.vaxis.segment(vi).weights(vt);
        // away from the ends the four columns are consecutive: one slice per row
        let inner = c[0] + 3 == c[3];
        if self.constant_h {
            return self.cubic_row(0, c, inner, &wv);
        }
        if !(h >= self.haxis.lo && h <= self.haxis.hi) {
            return 0.0;
        }
        let (hi, ht) = self.haxis.locate(&self.h, h);
        let wh = self.haxis.segment(hi).weights(ht);
        let [k0, k1, k2, k3] = self.haxis.neighbours(hi);
        let r0 = self.cubic_row(k0, c, inner, &wv);
        let r1 = self.cubic_row(k1, c, inner, &wv);
        let r2 = self.cubic_row(k2, c, inner, &wv);
        let r3 = self.cubic_row(k3, c, inner, &wv);
        ((wh[0] * r0 + wh[1] * r1) + (wh[2] * r2 + wh[3] * r3)).max(0.0)
    }

    /// Row `hk` interpolated in the vertical with weights `w` on columns `c` (each < nv;
    /// consecutive when `inner`), clamped at 0.
    #[inline(always)]
    fn cubic_row(&self, hk: usize, c: [usize; 4], inner: bool, w: &[f64; 4]) -> f64 {
        let nv = self.v.len();
        let p = if inner {
            let k = hk * nv + c[0];
            let r: &[f64; 4] = self.values[k..k + 4].try_into().unwrap();
            *r
        } else {
            let r = &self.values[hk * nv..hk * nv + nv];
            c.map(|k| r[k])
        };
        ((w[0] * p[0] + w[1] * p[1]) + (w[2] * p[2] + w[3] * p[3])).max(0.0)
    }
}
