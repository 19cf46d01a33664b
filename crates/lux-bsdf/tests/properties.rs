//! Exact properties: Lambertian limits, reciprocity, the combinators' albedos and the layer
//! furnace, delta lobes, and robustness against bad numbers.

mod common;
use common::*;
use glam::{DVec2, DVec3};
use lux_bsdf::*;
use proptest::prelude::*;
use std::f64::consts::FRAC_1_PI;

fn random_dirs(seed: u64, n: usize, upper: bool) -> Vec<DVec3> {
    let mut r = Rng(seed);
    (0..n)
        .map(|_| {
            let z = r.next();
            let p = 2.0 * std::f64::consts::PI * r.next();
            let s = (1.0 - z * z).sqrt();
            DVec3::new(
                s * p.cos(),
                s * p.sin(),
                if upper { z.max(1e-3) } else { -z.max(1e-3) },
            )
        })
        .collect()
}

#[test]
fn oren_nayar_roughness_zero_is_lambert_exactly() {
    let rho = DVec3::new(0.8, 0.4, 0.1);
    for eon in [false, true] {
        for wo in random_dirs(1, 20, true) {
            let c = Closure::OrenNayar {
                weight: 1.0,
                color: rho,
                roughness: 0.0,
                energy_compensation: eon,
                frame: frame(),
            };
            let b = single(c, wo.normalize());
            for wi in random_dirs(2, 20, true) {
                let wi = wi.normalize();
                let e = b.eval(wi);
                let want = rho * FRAC_1_PI * wi.z;
                assert!(
                    (e.diffuse - want).abs().max_element() <= 1e-15 * want.max_element(),
                    "{e:?} vs {want}"
                );
                assert_eq!(e.specular, DVec3::ZERO);
            }
            assert!((b.albedo() - rho).abs().max_element() < 1e-15);
        }
    }
}

/// `f(a, b) = f(b, a)` for the reciprocal reflection closures: Oren–Nayar (both forms),
/// Burley, sheen, Lambertian subsurface. (Not `layer`, nor the energy-compensated microfacet
/// lobes, whose Turquin factor depends on `ωo` only; their single-scattering part is checked
/// below.)
#[test]
fn reciprocity_of_reflection_closures() {
    let f = frame();
    let closures = [
        Closure::OrenNayar {
            weight: 1.0,
            color: DVec3::ONE,
            roughness: 0.8,
            energy_compensation: false,
            frame: f,
        },
        Closure::OrenNayar {
            weight: 1.0,
            color: DVec3::splat(0.7),
            roughness: 0.8,
            energy_compensation: true,
            frame: f,
        },
        Closure::Burley {
            weight: 1.0,
            color: DVec3::ONE,
            roughness: 0.6,
            frame: f,
        },
        Closure::Sheen {
            weight: 1.0,
            color: DVec3::ONE,
            roughness: 0.3,
            mode: SheenMode::ContyKulla,
            frame: f,
        },
        Closure::Subsurface {
            weight: 1.0,
            color: DVec3::ONE,
            radius: DVec3::ONE,
            anisotropy: 0.0,
            frame: f,
        },
    ];
    let dirs = random_dirs(3, 30, true);
    for c in closures {
        for a in &dirs {
            for b in &dirs {
                let (a, b) = (a.normalize(), b.normalize());
                let fab = single(c, a).eval(b).diffuse / b.z;
                let fba = single(c, b).eval(a).diffuse / a.z;
                assert!(
                    (fab - fba).abs().max_element() <= 1e-12 * fab.max_element().max(1e-3),
                    "{c:?}: {fab} vs {fba}"
                );
            }
        }
    }
}

/// The single-scattering GGX BRDF is reciprocal: for a white conductor, whose Turquin factor
/// is `1/E_ss(μo)`, `f(a, b)·E_ss(a) = f(b, a)·E_ss(b)` (isotropic and anisotropic).
#[test]
fn reciprocity_of_single_scattering_microfacet_brdf() {
    let dirs = random_dirs(4, 25, true);
    for alpha in [DVec2::splat(0.3), DVec2::new(0.1, 0.5)] {
        let c = conductor(DVec3::ZERO, DVec3::ZERO, alpha);
        let ar = (0.5 * (alpha.x * alpha.x + alpha.y * alpha.y)).sqrt();
        for a in &dirs {
            for b in &dirs {
                let (a, b) = (a.normalize(), b.normalize());
                let fab = single(c, a).eval(b).specular.x / b.z * lux_bsdf::albedo::ggx(a.z, ar);
                let fba = single(c, b).eval(a).specular.x / a.z * lux_bsdf::albedo::ggx(b.z, ar);
                assert!((fab - fba).abs() <= 1e-10 * fab.max(1e-6), "{fab} vs {fba}");
            }
        }
    }
}

/// `layer(dielectric 1.5, white Lambert)`: the tree's albedo is `E_top + (1 − E_top)·1` exactly,
/// its furnace equals it (within 4 standard errors and the tables' accuracy), and it is ≤ 1.
#[test]
fn dielectric_over_white_lambert_conserves_energy() {
    for alpha in [0.0, 0.1, 0.4, 0.9] {
        for th in [0.0, 45.0, 80.0] {
            let wo = dir(th, 0.0);
            let top_c = dielectric(1.5, DVec2::splat(alpha), ScatterMode::R);
            let e_top = single(top_c, wo).albedo();
            let mut b = Bsdf::new(wo, DVec3::Z, true, false);
            let base = b.push(Node::Closure(lambert(DVec3::ONE))).unwrap();
            let top = b.push(Node::Closure(top_c)).unwrap();
            b.push(Node::Layer {
                top,
                base: Some(base),
            })
            .unwrap();
            let want = e_top + (DVec3::ONE - e_top);
            assert!((b.albedo() - want).abs().max_element() < 1e-15);
            let (m, se) = furnace_with_delta(&b, 1 << 16, 11);
            println!(
                "layer α={alpha} θ={th}: furnace {:.4} ± {:.4}, E_top {:.4}",
                m.x, se.x, e_top.x
            );
            assert!(
                (m.x - want.x).abs() < 4.0 * se.x + 2.5e-3,
                "furnace {} vs {}",
                m.x,
                want.x
            );
            assert!(m.x <= 1.0 + 4.0 * se.x + 2.5e-3);
        }
    }
}

#[test]
fn combinator_albedos() {
    let wo = dir(30.0, 0.0);
    let a_c = lambert(DVec3::new(0.9, 0.5, 0.1));
    let b_c = conductor(
        DVec3::new(0.2, 0.4, 1.4),
        DVec3::new(3.4, 2.3, 1.8),
        DVec2::splat(0.3),
    );
    let ea = single(a_c, wo).albedo();
    let eb = single(b_c, wo).albedo();
    let mut t = Bsdf::new(wo, DVec3::Z, true, false);
    let a = t.push(Node::Closure(a_c)).unwrap();
    let b = t.push(Node::Closure(b_c)).unwrap();
    let m = t
        .push(Node::Mix {
            fg: Some(a),
            bg: Some(b),
            mix: 0.25,
        })
        .unwrap();
    let s = t
        .push(Node::Multiply {
            a: m,
            weight: DVec3::new(0.5, 1.0, 2.0),
        })
        .unwrap();
    t.push(Node::Add {
        a: Some(s),
        b: Some(a),
    })
    .unwrap();
    let want = (ea * 0.25 + eb * 0.75) * DVec3::new(0.5, 1.0, 2.0) + ea;
    assert!((t.albedo() - want).abs().max_element() < 1e-14);
    // eval is the same linear combination.
    for wi in random_dirs(9, 10, true) {
        let wi = wi.normalize();
        let fa = single(a_c, wo).eval(wi);
        let fb = single(b_c, wo).eval(wi);
        let e = t.eval(wi);
        let want = (fa.diffuse * 0.25) * DVec3::new(0.5, 1.0, 2.0) + fa.diffuse;
        assert!((e.diffuse - want).abs().max_element() < 1e-14);
        let want = (fb.specular * 0.75) * DVec3::new(0.5, 1.0, 2.0);
        assert!((e.specular - want).abs().max_element() < 1e-14);
    }
}

#[test]
fn delta_lobes_only_through_sample() {
    let wo = dir(40.0, 0.0);
    let b = single(
        conductor(
            DVec3::new(0.2, 0.4, 1.4),
            DVec3::new(3.4, 2.3, 1.8),
            DVec2::ZERO,
        ),
        wo,
    );
    let mirror = DVec3::new(-wo.x, -wo.y, wo.z);
    assert_eq!(b.pdf(mirror), 0.0);
    assert_eq!(b.eval(mirror), Eval::default());
    let s = b.sample(0.5, [0.3, 0.7]).unwrap();
    assert_eq!(s.kind, LobeKind::Specular);
    assert!((s.wi - mirror).length() < 1e-12);
    assert_eq!(s.pdf, 1.0);
    let f =
        lux_bsdf::fresnel::conductor(wo.z, DVec3::new(0.2, 0.4, 1.4), DVec3::new(3.4, 2.3, 1.8));
    assert!((s.weight - f).abs().max_element() < 1e-14);
    // A smooth dielectric at normal incidence reflects 4 % and refracts straight down.
    let b = single(dielectric(1.5, DVec2::ZERO, ScatterMode::Rt), DVec3::Z);
    let r = b.sample(0.01, [0.5, 0.5]).unwrap();
    assert!((r.pdf - 0.04).abs() < 1e-15 && (r.weight - DVec3::ONE).abs().max_element() < 1e-14);
    assert!(!r.transmitted);
    let t = b.sample(0.5, [0.5, 0.5]).unwrap();
    assert!((t.pdf - 0.96).abs() < 1e-15 && (t.wi + DVec3::Z).length() < 1e-12 && t.transmitted);
    // Thin-walled: straight through at any angle.
    let mut b = Bsdf::new(wo, DVec3::Z, true, true);
    b.push(Node::Closure(dielectric(1.5, DVec2::ZERO, ScatterMode::Rt)))
        .unwrap();
    let t = b.sample(0.99, [0.5, 0.5]).unwrap();
    assert!((t.wi + wo).length() < 1e-12);
}

#[test]
fn black_trees() {
    let wo = dir(20.0, 0.0);
    assert!(Bsdf::new(wo, DVec3::Z, true, false).is_black());
    let mut b = Bsdf::new(wo, DVec3::Z, true, false);
    b.push(Node::Closure(Closure::OrenNayar {
        weight: 0.0,
        color: DVec3::ONE,
        roughness: 0.0,
        energy_compensation: false,
        frame: frame(),
    }));
    assert!(b.is_black());
    assert!(b.sample(0.5, [0.5, 0.5]).is_none());
    assert!(!single(lambert(DVec3::ONE), wo).is_black());
    fn copy<T: Copy>() {}
    copy::<Bsdf>();
}

fn any_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        -2.0..3.0f64,
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(-f64::INFINITY),
        Just(0.0),
        Just(1e-300),
    ]
}
fn any_v3() -> impl Strategy<Value = DVec3> {
    (any_f64(), any_f64(), any_f64()).prop_map(|(a, b, c)| DVec3::new(a, b, c))
}

fn any_closure() -> impl Strategy<Value = Closure> {
    (
        0usize..8,
        any_f64(),
        any_v3(),
        any_v3(),
        any_f64(),
        any_f64(),
        0usize..3,
        any::<bool>(),
    )
        .prop_map(|(k, w, c, d, r, q, m, flag)| {
            let f = Frame::new(DVec3::new(0.1, 0.2, 1.0), DVec3::X);
            let mode = [ScatterMode::R, ScatterMode::T, ScatterMode::Rt][m];
            let alpha = DVec2::new(r, q);
            match k {
                0 => Closure::OrenNayar {
                    weight: w,
                    color: c,
                    roughness: r,
                    energy_compensation: flag,
                    frame: f,
                },
                1 => Closure::Burley {
                    weight: w,
                    color: c,
                    roughness: r,
                    frame: f,
                },
                2 => Closure::Translucent {
                    weight: w,
                    color: c,
                    frame: f,
                },
                3 => Closure::Dielectric {
                    weight: w,
                    tint: c,
                    ior: q,
                    alpha,
                    retroreflective: flag,
                    thinfilm: ThinFilm::default(),
                    mode,
                    frame: f,
                },
                4 => Closure::Conductor {
                    weight: w,
                    ior: c,
                    extinction: d,
                    alpha,
                    retroreflective: flag,
                    thinfilm: ThinFilm::default(),
                    frame: f,
                },
                5 => Closure::GeneralizedSchlick {
                    weight: w,
                    color0: c,
                    color82: d,
                    color90: c,
                    exponent: q,
                    alpha,
                    retroreflective: flag,
                    thinfilm: ThinFilm::default(),
                    mode,
                    frame: f,
                },
                6 => Closure::Sheen {
                    weight: w,
                    color: c,
                    roughness: r,
                    mode: SheenMode::ContyKulla,
                    frame: f,
                },
                _ => Closure::Subsurface {
                    weight: w,
                    color: c,
                    radius: d,
                    anisotropy: q,
                    frame: f,
                },
            }
        })
}

fn ok(v: DVec3) -> bool {
    v.is_finite() && v.min_element() >= 0.0
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]
    /// Bad inputs (NaN, infinities, negative colours and weights, out-of-range roughness and
    /// mix) never panic and never give NaN or negative results.
    #[test]
    fn bad_numbers_are_harmless(
        a in any_closure(), b in any_closure(), mix in any_f64(), mul in any_v3(),
        wo in any_v3(), wi in any_v3(), u in (any_f64(), any_f64(), any_f64()),
        entering in any::<bool>(), thin in any::<bool>(),
    ) {
        let wo = if wo.is_finite() && wo.length() > 0.0 { wo.normalize() } else { wo };
        let mut t = Bsdf::new(wo, DVec3::Z, entering, thin);
        let na = t.push(Node::Closure(a)).unwrap();
        let nb = t.push(Node::Closure(b)).unwrap();
        let l = t.push(Node::Layer { top: na, base: Some(nb) }).unwrap();
        let m = t.push(Node::Multiply { a: l, weight: mul }).unwrap();
        t.push(Node::Mix { fg: Some(m), bg: Some(nb), mix }).unwrap();
        let e = t.eval(wi);
        prop_assert!(ok(e.diffuse) && ok(e.specular));
        let p = t.pdf(wi);
        prop_assert!(p.is_finite() && p >= 0.0);
        prop_assert!(ok(t.albedo()));
        let _ = t.is_black();
        if let Some(s) = t.sample(u.0, [u.1, u.2]) {
            prop_assert!(ok(s.weight) && s.pdf.is_finite() && s.pdf > 0.0 && s.wi.is_finite());
        }
    }
}
