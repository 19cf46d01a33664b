//! `inputs:shaping:ies:normalize` conserves energy.
//!
//! The normalizer is the profile's mean intensity: flux/4π when its vertical range spans more
//! than 95.73° (it "covers the sphere"), flux/2π otherwise. Under `Profile::Spec` the flux is the
//! exact integral of the bilinear interpolant, which is what `factor` evaluates, so:
//!
//! - covering profiles: `∫_{S²} factor dω = 4π` exactly — the sphere mean of the factor is 1;
//! - other profiles: `∫_{S²} factor dω = 2π` — the sphere mean is 1/2, and when the profile lies
//!   in one hemisphere (vertical range within 0..90° or 90..180°) the mean over that emitting
//!   hemisphere is 1 and over the other 0.
//!
//! Under `Profile::HdEmbree` the divisor is the midpoint-rule flux, so the sphere integral is
//! `4π · flux_exact / flux_midpoint` (or 2π ·): off by the midpoint rule's error (0.01 % to 7 %
//! on the corpus; 36 % for the 2-sample linear profile).

mod common;

use common::{arb_file, corpus, web, web_of};
use core::f64::consts::{PI, TAU};
use glam::DVec3;
use lux_ies::Interpolation;
use lux_math::Profile;
use lux_shaping::{Shaping, ShapingOptions, ShapingParams};
use proptest::prelude::*;

const NORMALIZED: ShapingParams = ShapingParams {
    ies_normalize: true,
    ..ShapingParams::NO_SHAPING
};

fn expected_sphere_integral(w: &lux_ies::PhotometricWeb) -> f64 {
    if w.covers_sphere() { 4.0 * PI } else { TAU }
}

#[test]
fn every_corpus_profile_keeps_its_energy_under_spec() {
    let files = corpus();
    assert_eq!(files.len(), 21);
    let mut covering = 0;
    for rel in &files {
        let w = web(rel, Profile::Spec);
        let want = expected_sphere_integral(&w);
        covering += w.covers_sphere() as usize;
        let (v0, v1) = w.vertical_range();
        let type_c = w.photometric_type() == lux_ies::PhotometricType::C;
        let s = Shaping::new(&NORMALIZED, Some(w), ShapingOptions::default()).unwrap();
        let got = s.integral_sphere();
        for c in got.to_array() {
            assert!((c / want - 1.0).abs() < 1e-9, "{rel}: {c} vs {want}");
        }
        if type_c && (v1 <= PI / 2.0 || v0 >= PI / 2.0) {
            // one-hemisphere type C profile: mean 1 over its emitting hemisphere, 0 over the other
            let lower = s.integral_weighted(|d| if d.z < 0.0 { 1.0 } else { 0.0 })[0];
            let upper = s.integral_weighted(|d| if d.z > 0.0 { 1.0 } else { 0.0 })[0];
            let (lit, dark) = if v1 <= PI / 2.0 {
                (lower, upper)
            } else {
                (upper, lower)
            };
            assert!(
                (lit / TAU - 1.0).abs() < 1e-9,
                "{rel}: hemisphere mean {}",
                lit / TAU
            );
            assert!(dark.abs() < 1e-9, "{rel}: {dark}");
        }
    }
    // 12 files cover the sphere (0..180 type C and the two type B files), 9 are 0..90,
    // 0..50 or 130..180 profiles
    assert_eq!(covering, 12);
}

#[test]
fn hdembree_divides_by_the_midpoint_flux() {
    for rel in corpus() {
        let w = web(&rel, Profile::HdEmbree);
        let want = expected_sphere_integral(&w) * w.flux_exact() / w.flux_midpoint();
        let o = ShapingOptions {
            profile: Profile::HdEmbree,
            ..Default::default()
        };
        let s = Shaping::new(&NORMALIZED, Some(w), o).unwrap();
        let got = s.integral_sphere()[0];
        assert!((got / want - 1.0).abs() < 1e-9, "{rel}: {got} vs {want}");
    }
}

#[test]
fn the_luxtest_omni_profile_mean_is_one_and_its_divisor_is_flux_over_4pi() {
    // bega_omni002_4777lm.ies (rect frames 56–60): flux 4779.19 lm (lux-ies EXPECTED.md §3)
    let w = web("luxtest/bega_omni002_4777lm.ies", Profile::Spec);
    let s = Shaping::new(&NORMALIZED, Some(w), ShapingOptions::default()).unwrap();
    let n = s.ies_normalizer().unwrap();
    assert!((n * 4.0 * PI - 4779.19).abs() < 0.01, "{}", n * 4.0 * PI);
    let mean = s.integral_sphere()[0] / (4.0 * PI);
    assert!((mean - 1.0).abs() < 1e-9);
}

#[test]
fn angle_scale_moves_energy_but_the_divisor_stays() {
    // The normalizer is a property of the file: an angleScale changes the emitted total.
    // test_linear_vertical (I = 1 − θ/π, mean 1/2) at angleScale 0.5: 2π(1 − 2/π) / (1/2).
    let w = web("luxtest/test_linear_vertical.ies", Profile::Spec);
    let p = ShapingParams {
        ies_angle_scale: 0.5,
        ..NORMALIZED
    };
    let s = Shaping::new(&p, Some(w), ShapingOptions::default()).unwrap();
    let want = TAU * (1.0 - 2.0 / PI) / 0.5;
    assert!((s.integral_sphere()[0] / want - 1.0).abs() < 1e-9);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn generated_profiles_keep_their_energy(file in arb_file()) {
        let w = web_of(&file);
        prop_assume!(w.flux_exact() > 1e-6 * w.max_candela());
        let want = expected_sphere_integral(&w);
        let s = Shaping::new(&NORMALIZED, Some(w), ShapingOptions::default()).unwrap();
        let got = s.integral_sphere()[0];
        prop_assert!((got / want - 1.0).abs() < 1e-7, "{} vs {}", got, want);
    }

    #[test]
    fn all_zero_profiles_give_zero_not_nan(file in arb_file(), bicubic in any::<bool>()) {
        let mut file = file;
        file.candela.iter_mut().for_each(|c| *c = 0.0);
        let o = ShapingOptions {
            interpolation: if bicubic { Interpolation::Bicubic } else { Interpolation::Bilinear },
            ..Default::default()
        };
        let s = Shaping::new(&NORMALIZED, Some(web_of(&file)), o).unwrap();
        prop_assert_eq!(s.ies_normalizer(), Some(0.0));
        prop_assert_eq!(s.factor(glam::DVec3::NEG_Z), DVec3::ZERO);
        prop_assert_eq!(s.max_factor(), 0.0);
        prop_assert_eq!(s.integral_sphere(), DVec3::ZERO);
    }
}
