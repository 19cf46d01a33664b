//! Integrals of the shaping factor over the sphere and the cosine-weighted hemisphere (the
//! `G` of a light's flux), by adaptive quadrature split at the factor's kinks.

use super::*;
use lux_math::LightKind;

impl Shaping {
    /// `∫_{S²} factor(ω) dω` per channel (steradians; 4π for the identity).
    ///
    /// Computed in θ (polar angle from −Z) as `∫_0^π Φ(θ) sin θ dθ`, `Φ(θ)` being the integral
    /// over φ:
    /// - without IES, `Φ = 2π × focus colour × cone`;
    /// - type C, bilinear: `Φ` is exact, because the bilinear interpolant integrates exactly in
    ///   φ by the trapezoid rule on the profile's own horizontal angles; `Φ` is then the
    ///   φ-integrated profile, piecewise linear in θies;
    /// - type C, bicubic: φ by adaptive Gauss–Kronrod between the horizontal angles;
    /// - types A/B without angleScale: in their own coordinates (`dω = cos V dV dH`), split at
    ///   their grid lines and where the cone edges cross them (closed form);
    /// - types A/B with an angleScale: in (θ, φ), each θ-slice split where it crosses the
    ///   native grid lines (closed form). The slowest case: ~1–2 s for a 45 × 45 grid.
    ///
    /// The θ integral is adaptive Gauss–Kronrod (7/15) split at every kink: the cone edge and
    /// ramp start, π/2, the profile's vertical angles mapped back through angleScale (types A/B:
    /// where θ-circles touch the native grid lines), and, for a focus exponent above 4, at
    /// multiples of 1/√focus near the poles. Requested relative accuracy 10⁻¹⁰; the tests check
    /// 10⁻⁹ against closed forms and exact fluxes.
    pub fn integral_sphere(&self) -> DVec3 {
        DVec3::from_array(self.sphere_rgb())
    }

    fn sphere_rgb(&self) -> [f64; 3] {
        if let Some(p) = self.native_ab() {
            return self.integrate_native(p, &|_| 1.0);
        }
        self.integrate_theta(PI, |t| t.sin())
    }

    /// `∫ factor(ω) cos θ dω` over the emitting hemisphere θ < π/2 (θ off the light's −Z), per
    /// channel: what a flat emitter (rect, disk) radiates relative to an unshaped one, whose value
    /// is π. Same method as [`integral_sphere`](Self::integral_sphere).
    pub fn integral_cos_hemisphere(&self) -> DVec3 {
        DVec3::from_array(self.cos_hemisphere_rgb())
    }

    fn cos_hemisphere_rgb(&self) -> [f64; 3] {
        if let Some(p) = self.native_ab() {
            return self.integrate_native(p, &|d| (-d.z).max(0.0));
        }
        self.integrate_theta(FRAC_PI_2, |t| {
            let (s, c) = t.sin_cos();
            s * c
        })
    }

    /// `∫_{S²} factor(ω) · w(ω) dω` per channel, for any weight `w` of the unit light-space
    /// direction ω (e.g. the projected area of a sphere or cylinder emitter towards ω).
    ///
    /// Iterated adaptive Gauss–Kronrod: θ split as in
    /// [`integral_sphere`](Self::integral_sphere), φ split at multiples of π/8 and where the
    /// slice crosses the profile's grid lines (type C: its horizontal angles; types A/B: the
    /// crossings of the θies-circle with the native V and H lines, in closed form; types A/B
    /// without angleScale are integrated in (V, H) as for `integral_sphere`). `w` should be
    /// finite and piecewise smooth: its own kinks are found by bisection only, so their accuracy
    /// depends on the panel budget. Non-finite values of `w` count as 0.
    pub fn integral_weighted(&self, w: impl Fn(DVec3) -> f64) -> DVec3 {
        DVec3::from_array(self.weighted_rgb(w))
    }

    /// The integral of the factor over the emitting surface's directions that the shaping
    /// integral `G` of an area light of `kind` needs (lux-spectral's
    /// `ShapingIntegral::from_integrals`, for the luminance of a light given in lumens or
    /// watts; `Φ = L·A·G`):
    ///
    /// | kind | integral | `G` |
    /// |---|---|---|
    /// | RectLight, DiskLight | `∫_{θ<π/2} f cos θ dω` ([`integral_cos_hemisphere`](Self::integral_cos_hemisphere)) | the integral |
    /// | SphereLight | `∫_{S²} f dω` ([`integral_sphere`](Self::integral_sphere)) | ¼ of it |
    /// | CylinderLight (axis X) | `∫_{S²} f √(1 − ω_x²) dω` ([`integral_weighted`](Self::integral_weighted)) | 1/π of it |
    ///
    /// `None` for the identity (f ≡ 1, so `G = π` exactly, with no quadrature error) and for
    /// the kinds without an area emitter (distant, dome, portal, mesh).
    pub fn emitter_integral(&self, kind: LightKind) -> Option<DVec3> {
        if self.is_identity() {
            return None;
        }
        match kind {
            LightKind::Rect | LightKind::Disk => Some(self.integral_cos_hemisphere()),
            LightKind::Sphere => Some(self.integral_sphere()),
            LightKind::Cylinder => {
                Some(self.integral_weighted(|d| (1.0 - d.x * d.x).max(0.0).sqrt()))
            }
            LightKind::Distant | LightKind::Dome | LightKind::Portal | LightKind::Mesh => None,
        }
    }

    fn weighted_rgb(&self, w: impl Fn(DVec3) -> f64) -> [f64; 3] {
        if let Some(p) = self.native_ab() {
            return self.integrate_native(p, &w);
        }
        let breaks = self.theta_breaks(PI);
        quad::integrate(
            |theta| {
                let r = self.radial(theta);
                if r == [0.0; 3] {
                    return [0.0; 3];
                }
                let st = theta.sin();
                let phi_breaks = self.phi_breaks(theta);
                let inner = quad::integrate(
                    |phi| {
                        let d = lux_math::light_direction(theta, phi);
                        let i = self.ies.as_ref().map_or(1.0, |p| p.sample(theta, phi));
                        [i * w(d)]
                    },
                    &phi_breaks,
                    REL_INNER,
                    MAX_PANELS_INNER,
                )[0];
                r.map(|x| x * inner * st)
            },
            &breaks,
            REL_OUTER,
            MAX_PANELS_OUTER,
        )
    }

    /// The IES part when it is of type A/B with angleScale the identity: such profiles are
    /// integrated in their own (V, H) coordinates, where their grid is aligned.
    fn native_ab(&self) -> Option<&IesPart> {
        self.ies
            .as_ref()
            .filter(|p| !p.type_c && p.map == AngleMap::Identity)
    }

    /// Focus colour × cone for cos θ = `c`.
    fn radial_cos(&self, c: f64) -> [f64; 3] {
        let cone = self.cone.at_theta(c.acos());
        if cone == 0.0 {
            return [0.0; 3];
        }
        match &self.focus {
            None => [cone; 3],
            Some(f) => f.color(c).map(|x| x * cone),
        }
    }

    /// `∫ factor · w dω` for a type A/B profile without angle scale, in the profile's native
    /// coordinates: `dω = cos V dV dH` over its measured range (0 outside), V split at the
    /// grid's vertical angles and at ±κ for every cone kink κ < π/2 (where the curve
    /// `cos V cos H = cos κ` turns), H split at the grid's horizontal angles and at the
    /// crossings `H = ±acos(cos κ / cos V)`; near the axis also at the focus peak's scale.
    fn integrate_native(&self, p: &IesPart, w: &dyn Fn(DVec3) -> f64) -> [f64; 3] {
        let v = p.web.vertical_angles();
        let h = p.web.horizontal_angles();
        let type_b = p.web.photometric_type() == lux_ies::PhotometricType::B;
        let kinks: Vec<f64> = self
            .cone
            .kinks()
            .into_iter()
            .filter(|k| *k > 0.0 && *k < FRAC_PI_2)
            .collect();
        let mut peaks = Vec::new();
        if let Some(f) = &self.focus
            && f.exponent > 4.0
            && f.exponent.is_finite()
        {
            let mut x = 1.0 / f.exponent.sqrt();
            while x < FRAC_PI_2 {
                peaks.push(x);
                peaks.push(-x);
                x *= 4.0;
            }
        }
        let finish = |mut b: Vec<f64>, lo: f64, hi: f64| {
            b.retain(|x| x.is_finite() && *x >= lo && *x <= hi);
            b.sort_by(f64::total_cmp);
            b.dedup();
            b
        };
        let mut vb = v.to_vec();
        vb.push(0.0);
        vb.extend(kinks.iter().flat_map(|&k| [k, -k]));
        vb.extend_from_slice(&peaks);
        let vb = finish(vb, v[0], v[v.len() - 1]);
        let (h0, h1) = (h[0], h[h.len() - 1]);
        quad::integrate(
            |vv| {
                let (sv, cv) = vv.sin_cos();
                let mut hb = h.to_vec();
                hb.push(0.0);
                for &k in &kinks {
                    let a = k.cos() / cv;
                    if a.abs() <= 1.0 {
                        let x = a.acos();
                        hb.push(x);
                        hb.push(-x);
                    }
                }
                hb.extend_from_slice(&peaks);
                let hb = finish(hb, h0, h1);
                quad::integrate(
                    |hh| {
                        let (sh, ch) = hh.sin_cos();
                        let r = self.radial_cos((cv * ch).clamp(-1.0, 1.0));
                        if r == [0.0; 3] {
                            return [0.0; 3];
                        }
                        let d = if type_b {
                            DVec3::new(-cv * sh, sv, -cv * ch)
                        } else {
                            DVec3::new(sv, -cv * sh, -cv * ch)
                        };
                        let i = p.scale.apply(p.web.native(vv, hh, p.interp)) * w(d) * cv;
                        r.map(|x| x * i)
                    },
                    &hb,
                    REL_INNER,
                    MAX_PANELS_INNER,
                )
            },
            &vb,
            REL_OUTER,
            MAX_PANELS_OUTER,
        )
    }

    fn integrate_theta(&self, hi: f64, weight: impl Fn(f64) -> f64) -> [f64; 3] {
        if self.identity {
            // exact: 2π ∫ weight
            return quad::integrate(|t| [TAU * weight(t); 3], &[0.0, hi], REL_OUTER, 64);
        }
        let breaks = self.theta_breaks(hi);
        quad::integrate(
            |theta| {
                let r = self.radial(theta);
                if r == [0.0; 3] {
                    return [0.0; 3];
                }
                let p = self.phi_slice(theta) * weight(theta);
                r.map(|x| x * p)
            },
            &breaks,
            REL_OUTER,
            MAX_PANELS_OUTER,
        )
    }

    /// `∫_0^{2π} ies(θ, φ) dφ` (scaled); 2π without a profile.
    fn phi_slice(&self, theta: f64) -> f64 {
        let Some(p) = &self.ies else {
            return TAU;
        };
        if p.phi_integral.is_some() {
            return p.scale.apply(p.phi_integrated(p.map.apply(theta)));
        }
        if p.axial_c {
            return TAU * p.sample(theta, 0.0);
        }
        quad::integrate(
            |phi| [p.sample(theta, phi)],
            &self.phi_breaks(theta),
            REL_INNER,
            MAX_PANELS_INNER,
        )[0]
    }

    /// Break points in θ ∈ \[0, hi\]: the kinks and jumps of the factor.
    fn theta_breaks(&self, hi: f64) -> Vec<f64> {
        let mut b = vec![0.0, hi, FRAC_PI_2];
        b.extend(self.cone.kinks());
        b.extend((1..8).map(|k| PI * k as f64 / 8.0));
        if let Some(f) = &self.focus
            && f.exponent > 4.0
            && f.exponent.is_finite()
        {
            // |cos θ|^F ≈ exp(−F θ²/2): resolve the peak at the poles
            let w = 1.0 / f.exponent.sqrt();
            let mut x = w;
            while x < FRAC_PI_2 {
                b.push(x);
                b.push(PI - x);
                x *= 4.0;
            }
        }
        if let Some(p) = &self.ies {
            p.theta_kinks(&mut b);
        }
        b.retain(|x| x.is_finite() && *x >= 0.0 && *x <= hi);
        b.sort_by(f64::total_cmp);
        b.dedup();
        b
    }

    /// Break points in φ ∈ \[0, 2π\] for the slice at polar angle θ.
    fn phi_breaks(&self, theta: f64) -> Vec<f64> {
        let mut b: Vec<f64> = (0..=16).map(|k| PI * k as f64 / 8.0).collect();
        if let Some(p) = &self.ies {
            p.phi_kinks(theta, &mut b);
        }
        b.retain(|x| (0.0..=TAU).contains(x));
        b.sort_by(f64::total_cmp);
        b.dedup();
        b
    }
}
