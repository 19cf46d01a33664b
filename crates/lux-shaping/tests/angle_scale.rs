//! The `inputs:shaping:ies:angleScale` examples of the schema text, on synthetic spot profiles,
//! and the lookup edge rules (θies < 0 → 0; θies ≥ 180° → the last vertical angle's value).

mod common;

use common::{dir_deg, file, web, web_of};
use glam::DVec3;
use lux_ies::{PhotometricType, PhotometricWeb};
use lux_math::Profile;
use lux_shaping::{AngleScaleFormula, Shaping, ShapingOptions, ShapingParams};

/// A downward spot with a total cone of 60°: 1000 cd up to 30° off the nadir, a 0.01° linear
/// edge, 0 beyond.
fn down_spot() -> PhotometricWeb {
    web_of(&file(
        PhotometricType::C,
        vec![0.0, 30.0, 30.01, 180.0],
        vec![0.0],
        vec![1000.0, 1000.0, 0.0, 0.0],
    ))
}

/// The same aimed up: 1000 cd from 150° to 180°.
fn up_spot() -> PhotometricWeb {
    web_of(&file(
        PhotometricType::C,
        vec![0.0, 149.99, 150.0, 180.0],
        vec![0.0],
        vec![0.0, 0.0, 1000.0, 1000.0],
    ))
}

fn shaping(web: PhotometricWeb, scale: f64, formula: AngleScaleFormula) -> Shaping {
    let p = ShapingParams {
        ies_angle_scale: scale,
        ..ShapingParams::NO_SHAPING
    };
    let o = ShapingOptions {
        angle_scale: formula,
        ..Default::default()
    };
    Shaping::new(&p, Some(web), o).unwrap()
}

/// The lit range [θ_first, θ_last] (degrees, 0.001° steps) of a profile's light.
fn lit_range(s: &Shaping) -> (f64, f64) {
    let lit: Vec<f64> = (0..=180_000)
        .map(|k| k as f64 * 0.001)
        .filter(|&t| s.factor(dir_deg(t, 0.0))[0] > 500.0)
        .collect();
    (lit[0], *lit.last().unwrap())
}

#[track_caller]
fn near(a: f64, b: f64) {
    assert!((a - b).abs() < 0.0011, "{a} vs {b}");
}

/// Half-maximum of the 0.01° edge of the synthetic spots: 30.005° off the axis (down) or
/// 149.995° (up), i.e. a "total cone angle" of 60.01°.
const EDGE: f64 = 30.005;

#[test]
fn downward_spot_narrows_with_half_and_widens_with_one_and_a_half() {
    let tb = AngleScaleFormula::TwoBranch;
    // unscaled: 60° total (30° half-angle)
    let (a, b) = lit_range(&shaping(down_spot(), 0.0, tb));
    near(a, 0.0);
    near(b, EDGE);
    // "angleScale = .5 will narrow it to have a cone angle of 30°"
    let (a, b) = lit_range(&shaping(down_spot(), 0.5, tb));
    near(a, 0.0);
    near(2.0 * b, 2.0 * 0.5 * EDGE);
    assert!((2.0 * b - 30.0).abs() < 0.01);
    // "an angleScale of 1.5 will broaden it to have a cone angle of 90°"
    let (a, b) = lit_range(&shaping(down_spot(), 1.5, tb));
    near(a, 0.0);
    near(2.0 * b, 2.0 * 1.5 * EDGE);
    assert!((2.0 * b - 90.0).abs() < 0.02);
    // exactly at the mapped edge: θ = 0.5·30° maps to 30° (1000 cd), just past it to the
    // interpolated edge
    let s = shaping(down_spot(), 0.5, tb);
    assert_eq!(s.factor(dir_deg(14.9, 0.0))[0], 1000.0);
    assert_eq!(s.factor(dir_deg(15.01, 0.0))[0], 0.0);
}

#[test]
fn upward_spot_with_negative_scales() {
    let tb = AngleScaleFormula::TwoBranch;
    let (a, b) = lit_range(&shaping(up_spot(), 0.0, tb));
    near(a, 180.0 - EDGE);
    near(b, 180.0);
    // −0.5: total cone 30° (lit from 165°)
    let (a, b) = lit_range(&shaping(up_spot(), -0.5, tb));
    near(180.0 - a, 0.5 * EDGE);
    assert!((2.0 * (180.0 - a) - 30.0).abs() < 0.01);
    near(b, 180.0);
    // −1.5: total cone 90° (lit from 135°)
    let (a, b) = lit_range(&shaping(up_spot(), -1.5, tb));
    near(180.0 - a, 1.5 * EDGE);
    assert!((2.0 * (180.0 - a) - 90.0).abs() < 0.02);
    near(b, 180.0);
    // −1 is the identity of the negative branch: (θ − π)/1 + π
    let s = shaping(up_spot(), -1.0, tb);
    let plain = shaping(up_spot(), 0.0, tb);
    for t in [100.0, 149.0, 150.5, 170.0, 180.0] {
        let (x, y) = (
            s.factor(dir_deg(t, 0.0))[0],
            plain.factor(dir_deg(t, 0.0))[0],
        );
        assert!((x - y).abs() <= 1e-3 * y.max(1.0), "{t}: {x} vs {y}");
    }
}

#[test]
fn the_wrong_sign_translates_the_profile() {
    // "If you violate the above rules (i.e., use a negative angleScale for a spotlight aimed
    // down) ... the IES profile may seem to translate": −0.5 maps θ to 2θ − π, so the downward
    // spot's 0..30° appears at 90..105° and everything below 90° samples θies < 0 → 0.
    let s = shaping(down_spot(), -0.5, AngleScaleFormula::TwoBranch);
    let (a, b) = lit_range(&s);
    near(a, 90.0);
    near(b, 90.0 + 0.5 * EDGE);
    assert_eq!(s.factor(dir_deg(0.0, 0.0))[0], 0.0);
}

#[test]
fn legacy_formula() {
    let legacy = AngleScaleFormula::Legacy;
    // (θ − π)/(1 + s) + π with s = 1: the upward 150° edge moves to θ = 120°
    let (a, b) = lit_range(&shaping(up_spot(), 1.0, legacy));
    near(a, 180.0 - 2.0 * EDGE);
    near(b, 180.0);
    // s = −0.5 coincides with the two-branch formula (1 + s = −s)
    let (a, _) = lit_range(&shaping(up_spot(), -0.5, legacy));
    near(a, 180.0 - 0.5 * EDGE);
    // the downward spot under legacy s = 1: θies = θ/2 + 90° ≥ 90° → dark everywhere
    let s = shaping(down_spot(), 1.0, legacy);
    assert_eq!(s.max_factor(), 0.0);
    assert_eq!(s.factor(dir_deg(0.0, 0.0)), DVec3::ZERO);
    // −1 is rejected with the legacy formula only
    let p = ShapingParams {
        ies_angle_scale: -1.0,
        ..ShapingParams::NO_SHAPING
    };
    let o = ShapingOptions {
        angle_scale: legacy,
        ..Default::default()
    };
    let e = Shaping::new(&p, Some(down_spot()), o).unwrap_err();
    assert!(
        e.to_string().contains("inputs:shaping:ies:angleScale"),
        "{e}"
    );
}

#[test]
fn lookups_beyond_180_degrees_use_the_last_vertical_angle() {
    // luxtest iesDown frame 1: the 0..50° aimDown profile at angleScale 1/6. θies = 6θ:
    // lit for θ ≤ 50/6°, 0 between, and from θ = 30° on θies ≥ 180°, which the edge rule maps
    // to the profile's last vertical angle (50°).
    let w = web(
        "luxtest/test_vstripes_hquadrants_nonuniform_aimDown.ies",
        Profile::Spec,
    );
    let last = (50f64).to_radians();
    let scale = 1.0 / 6.0;
    let s = shaping(w.clone(), scale, AngleScaleFormula::TwoBranch);
    for phi in [0.0f64, 45.0, 100.0, 200.0, 300.0] {
        let p = phi.to_radians();
        for t in [31.0, 60.0, 120.0, 179.0] {
            let want = w.intensity(last, p);
            let got = s.factor(dir_deg(t, phi))[0];
            assert!(
                (got - want).abs() <= 1e-12 * want,
                "θ {t} φ {phi}: {got} vs {want}"
            );
        }
        for t in [9.0, 20.0, 29.0] {
            assert_eq!(s.factor(dir_deg(t, phi))[0], 0.0, "θ {t} φ {phi}");
        }
        let want = w.intensity((5.0f64 / scale).to_radians(), p);
        let got = s.factor(dir_deg(5.0, phi))[0];
        assert!(
            (got - want).abs() <= 1e-5 * want.max(1.0),
            "{got} vs {want}"
        );
    }
    // the aimUp profile (130..180°) at angleScale −1/6: θies = 6(θ − π) + π is < 0 (→ 0)
    // below 150°, inside the profile from 175° on
    let w = web(
        "luxtest/test_vstripes_hquadrants_nonuniform_aimUp.ies",
        Profile::Spec,
    );
    let s = shaping(w.clone(), -1.0 / 6.0, AngleScaleFormula::TwoBranch);
    assert_eq!(s.factor(dir_deg(140.0, 10.0)), DVec3::ZERO);
    let want = w.intensity(150f64.to_radians(), 10f64.to_radians());
    let got = s.factor(dir_deg(175.0, 10.0))[0];
    assert!(
        (got - want).abs() <= 1e-4 * want.max(1.0),
        "{got} vs {want}"
    );
}
