//! Fresnel curves against closed forms: normal incidence, total internal reflection, the
//! complex-index Fresnel equations, Hoffman's 82° tint.

use glam::DVec3;
use lux_bsdf::fresnel;

/// Complex numbers, just enough for the Fresnel equations.
#[derive(Clone, Copy)]
struct C(f64, f64);
impl C {
    fn add(self, o: C) -> C {
        C(self.0 + o.0, self.1 + o.1)
    }
    fn sub(self, o: C) -> C {
        C(self.0 - o.0, self.1 - o.1)
    }
    fn mul(self, o: C) -> C {
        C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
    fn div(self, o: C) -> C {
        let d = o.0 * o.0 + o.1 * o.1;
        C(
            (self.0 * o.0 + self.1 * o.1) / d,
            (self.1 * o.0 - self.0 * o.1) / d,
        )
    }
    fn sqrt(self) -> C {
        let r = (self.0 * self.0 + self.1 * self.1).sqrt();
        let re = ((r + self.0) / 2.0).sqrt();
        let im = ((r - self.0) / 2.0).sqrt().copysign(self.1);
        C(re, im)
    }
    fn norm2(self) -> f64 {
        self.0 * self.0 + self.1 * self.1
    }
}

/// Unpolarized reflectance from a medium of index 1 onto `n = eta + i k`, from the
/// amplitude coefficients `rs = (cosθ − n cosθt)/(cosθ + n cosθt)`,
/// `rp = (n cosθ − cosθt)/(n cosθ + cosθt)`, `n cosθt = √(n² − sin²θ)`.
fn complex_fresnel(cos: f64, eta: f64, k: f64) -> f64 {
    let n = C(eta, k);
    let c = C(cos, 0.0);
    let s2 = C(1.0 - cos * cos, 0.0);
    let n_ct = n.mul(n).sub(s2).sqrt(); // n cosθt
    let ct = n_ct.div(n);
    let rs = c.sub(n_ct).div(c.add(n_ct));
    let rp = n.mul(c).sub(ct).div(n.mul(c).add(ct));
    0.5 * (rs.norm2() + rp.norm2())
}

#[test]
fn dielectric_normal_incidence_is_f0() {
    for eta in [1.1, 1.33, 1.5, 2.0, 2.42] {
        let f0 = ((eta - 1.0) / (eta + 1.0)) * ((eta - 1.0) / (eta + 1.0));
        assert!((fresnel::dielectric(1.0, eta) - f0).abs() < 1e-15);
        // Leaving the denser medium: the same at normal incidence.
        assert!((fresnel::dielectric(1.0, 1.0 / eta) - f0).abs() < 1e-15);
        assert!((fresnel::f0_from_ior(eta) - f0).abs() < 1e-15);
        assert!((fresnel::ior_from_f0(f0) - eta).abs() < 1e-12);
    }
}

#[test]
fn dielectric_matches_complex_fresnel_with_zero_extinction() {
    for eta in [1.33, 1.5, 2.0] {
        for deg in [0.0f64, 20.0, 45.0, 70.0, 85.0, 89.0] {
            let c = deg.to_radians().cos();
            let a = fresnel::dielectric(c, eta);
            let b = complex_fresnel(c, eta, 0.0);
            assert!((a - b).abs() < 1e-12, "η={eta} θ={deg}: {a} vs {b}");
        }
    }
}

#[test]
fn total_internal_reflection_beyond_the_critical_angle() {
    let eta = 1.0 / 1.5;
    let critical = (1.0f64 / 1.5).asin().to_degrees(); // 41.81°
    for deg in [critical + 0.01, 50.0, 70.0, 89.9] {
        assert_eq!(
            fresnel::dielectric(deg.to_radians().cos(), eta),
            1.0,
            "θ={deg}"
        );
    }
    for deg in [0.0, 20.0, critical - 0.5] {
        let f = fresnel::dielectric(deg.to_radians().cos(), eta);
        assert!(f < 1.0, "θ={deg}: {f}");
    }
}

#[test]
fn conductor_matches_complex_fresnel_for_gold() {
    let eta = DVec3::new(0.183, 0.421, 1.373);
    let k = DVec3::new(3.424, 2.346, 1.770);
    for deg in [0.0f64, 30.0, 60.0, 80.0, 89.0] {
        let c = deg.to_radians().cos();
        let f = fresnel::conductor(c, eta, k);
        for ch in 0..3 {
            let r = complex_fresnel(c, eta[ch], k[ch]);
            assert!(
                (f[ch] - r).abs() < 1e-12,
                "θ={deg} channel {ch}: {} vs {r}",
                f[ch]
            );
        }
    }
}

#[test]
fn generalized_schlick_at_normal_incidence_and_82_degrees() {
    let eta = 1.5;
    let f0 = DVec3::splat(fresnel::f0_from_ior(eta));
    let f = fresnel::schlick(1.0, f0, DVec3::ONE, DVec3::ONE, 5.0);
    assert!((f - DVec3::splat(0.04)).abs().max_element() < 1e-15);
    // Hoffman's tint: F(θmax) = t · (r0 + (r90 − r0)(1 − 1/7)^q).
    let r0 = DVec3::new(0.9, 0.6, 0.3);
    let t = DVec3::new(0.7, 0.85, 1.0);
    let f82 = fresnel::schlick(1.0 / 7.0, r0, t, DVec3::ONE, 5.0);
    let base = r0 + (DVec3::ONE - r0) * (6.0f64 / 7.0).powi(5);
    assert!((f82 - t * base).abs().max_element() < 1e-12);
    // Grazing: r90.
    let g = fresnel::schlick(0.0, r0, t, DVec3::splat(0.8), 5.0);
    assert!((g - DVec3::splat(0.8)).abs().max_element() < 1e-15);
    // The closed-form hemispherical average against quadrature.
    let avg = fresnel::schlick_average(r0, t, DVec3::ONE, 5.0);
    let n = 200_000;
    let mut q = DVec3::ZERO;
    for i in 0..n {
        let mu = (i as f64 + 0.5) / n as f64;
        q += fresnel::schlick(mu, r0, t, DVec3::ONE, 5.0) * (2.0 * mu / n as f64);
    }
    assert!((avg - q).abs().max_element() < 1e-8, "{avg} vs {q}");
}

#[test]
fn slab_conserves_energy() {
    for f in [0.0, 0.04, 0.3, 1.0] {
        let r = fresnel::slab(DVec3::splat(f)).x;
        let t = (1.0 - f) / (1.0 + f);
        assert!((r + t - 1.0).abs() < 1e-15);
    }
}
