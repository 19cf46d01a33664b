//! Hand-computed factors for the luxtest RectLight frames 21–50 (`usd/rect.usda`, parameters from
//! luxtest's `light_descriptions.json`, CC-BY-4.0, see tests/data/NOTICE.md). The rect light has
//! `ShapingAPI` applied, so an unauthored cone angle is the schema's 90°.
//!
//! Every expected value below is written out from the schema formulas with the frame's
//! constants; directions are given as (θ off the light's −Z, φ) in degrees.

mod common;

use common::dir_deg;
use glam::DVec3;
use lux_shaping::{Shaping, ShapingOptions, ShapingParams};

/// The schema defaults with `ShapingAPI` applied (what every frame starts from).
const RECT: ShapingParams = ShapingParams::SCHEMA_DEFAULTS;

fn factor(p: ShapingParams, theta_deg: f64, phi_deg: f64) -> DVec3 {
    Shaping::new(&p, None, ShapingOptions::default())
        .unwrap()
        .factor(dir_deg(theta_deg, phi_deg))
}

#[track_caller]
fn check(p: ShapingParams, theta_deg: f64, want: [f64; 3]) {
    for phi in [0.0, 37.0, 200.0] {
        let got = factor(p, theta_deg, phi);
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() <= 1e-12 * want[c].abs().max(1.0),
                "θ {theta_deg}° φ {phi}°: got {got:?}, want {want:?}"
            );
        }
    }
}

fn grey(x: f64) -> [f64; 3] {
    [x; 3]
}

#[test]
fn frames_21_to_25_cone_angle() {
    // intensity 125, cone 170/130/90/50/10, softness 0: 1 inside (inclusive), 0 outside
    for (frame, cone) in [(21, 170.0), (22, 130.0), (23, 90.0), (24, 50.0), (25, 10.0)] {
        let p = ShapingParams {
            cone_angle_deg: cone,
            ..RECT
        };
        check(p, 0.0, grey(1.0));
        check(p, cone - 0.5, grey(1.0));
        check(p, cone + 0.5, grey(0.0));
        check(p, 180.0, grey(0.0));
        let s = Shaping::new(&p, None, ShapingOptions::default()).unwrap();
        assert_eq!(s.max_factor(), 1.0, "frame {frame}");
    }
}

#[test]
fn frames_26_to_30_focus_with_blue_tint() {
    // cone 170, focus 2, focusTint (0, 0, 1); the frames rotate the light, which does not
    // change the light-space factor: R = G = |cos θ|², B = lerp(f, 1, 1) = 1
    let p = ShapingParams {
        cone_angle_deg: 170.0,
        focus: 2.0,
        focus_tint: DVec3::new(0.0, 0.0, 1.0),
        ..RECT
    };
    check(p, 0.0, [1.0, 1.0, 1.0]);
    check(p, 60.0, [0.25, 0.25, 1.0]);
    check(p, 45.0, [0.5, 0.5, 1.0]);
    // the absolute value: the back hemisphere is lit too (up to the 170° cone)
    check(p, 120.0, [0.25, 0.25, 1.0]);
    check(p, 90.0, [0.0, 0.0, 1.0]);
    check(p, 175.0, [0.0, 0.0, 0.0]);
}

#[test]
fn frames_31_to_35_cone_softness() {
    // cone 45°, softness 0, .25, .5, .75, 1: ramp from θs = (1 − s)·45° to 45°,
    // factor 1 − (3u² − 2u³), u = (θ − θs)/(45° − θs)
    let smooth = |u: f64| 1.0 - (3.0 * u * u - 2.0 * u * u * u);
    for (frame, s) in [(31, 0.0), (32, 0.25), (33, 0.5), (34, 0.75), (35, 1.0)] {
        let p = ShapingParams {
            cone_angle_deg: 45.0,
            cone_softness: s,
            ..RECT
        };
        let ts = (1.0 - s) * 45.0;
        for theta in [0.0, 5.0, 12.0, 20.0, 30.0, 33.75, 40.0, 44.0, 44.99] {
            let want = if theta <= ts {
                1.0
            } else {
                smooth((theta - ts) / (45.0 - ts))
            };
            check(p, theta, grey(want));
        }
        check(p, 46.0, grey(0.0));
        if frame == 33 {
            // θs = 22.5°: u(33.75°) = 1/2 → 1/2; u(30°) = 1/3 → 1 − 7/27 = 20/27
            check(p, 33.75, grey(0.5));
            check(p, 30.0, grey(20.0 / 27.0));
        }
        if frame == 35 {
            // θs = 0: u(15°) = 1/3 → 20/27; u(30°) = 2/3 → 1 − 20/27 = 7/27
            check(p, 15.0, grey(20.0 / 27.0));
            check(p, 30.0, grey(7.0 / 27.0));
        }
    }
}

#[test]
fn frames_36_to_40_focus() {
    // focus 0, 1.25, 2.5, 3.75, 5; tint black; unauthored cone = 90°: |cos θ|^focus inside
    for (frame, f) in [(36, 0.0), (37, 1.25), (38, 2.5), (39, 3.75), (40, 5.0)] {
        let p = ShapingParams { focus: f, ..RECT };
        for theta in [0.0, 10.0, 30.0, 60.0, 85.0, 90.0] {
            let c = f64::to_radians(theta).cos();
            let want = if f > 0.0 { c.powf(f) } else { 1.0 };
            check(p, theta, grey(want));
        }
        check(p, 95.0, grey(0.0));
        if frame == 38 {
            // cos 60° = 1/2: 2^−2.5 = 0.176777
            check(p, 60.0, grey(0.176_776_695_296_636_9));
        }
        // the flat light's cos-weighted output: 2π/(f + 2) of the unshaped π
        let s = Shaping::new(&p, None, ShapingOptions::default()).unwrap();
        let got = s.integral_cos_hemisphere()[0];
        let want = core::f64::consts::TAU / (f + 2.0);
        assert!(
            (got / want - 1.0).abs() < 1e-9,
            "frame {frame}: {got} vs {want}"
        );
    }
}

#[test]
fn frames_41_to_45_focus_with_red_tint() {
    // cone 60, focusTint (1, 0, 0): R = 1, G = B = |cos θ|^focus
    for f in [0.0, 1.25, 2.5, 3.75, 5.0] {
        let p = ShapingParams {
            cone_angle_deg: 60.0,
            focus_tint: DVec3::new(1.0, 0.0, 0.0),
            focus: f,
            ..RECT
        };
        for theta in [0.0, 20.0, 45.0, 59.0] {
            let c = f64::to_radians(theta).cos();
            let g = if f > 0.0 { c.powf(f) } else { 1.0 };
            check(p, theta, [1.0, g, g]);
        }
        check(p, 61.0, grey(0.0));
    }
    // frame 45 at 60°: (1, 2^-5, 2^-5)
    let p = ShapingParams {
        cone_angle_deg: 60.0,
        focus_tint: DVec3::new(1.0, 0.0, 0.0),
        focus: 5.0,
        ..RECT
    };
    check(p, 60.0, [1.0, 0.03125, 0.03125]);
}

#[test]
fn frames_46_to_50_focus_tint_series() {
    // focus 3, cone 90; tint t → t + (1 − t)|cos θ|³ per channel
    let tints = [
        (46, [0.0, 0.0, 0.0]),
        (47, [0.0, 0.5, 0.0]),
        (48, [0.0, 1.0, 0.0]),
        (49, [0.5, 1.0, 0.5]),
        (50, [1.0, 1.0, 1.0]),
    ];
    for (frame, tint) in tints {
        let p = ShapingParams {
            focus: 3.0,
            focus_tint: DVec3::from_array(tint),
            ..RECT
        };
        for theta in [0.0, 30.0, 60.0, 89.0] {
            let f = f64::to_radians(theta).cos().powi(3);
            check(p, theta, tint.map(|t| t + (1.0 - t) * f));
        }
        check(p, 91.0, grey(0.0));
        // at 60°: f = 1/8 → frame 47 G = 0.5 + 0.5/8 = 0.5625, frame 49 (0.5625, 1, 0.5625)
        if frame == 47 {
            check(p, 60.0, [0.125, 0.5625, 0.125]);
        }
        if frame == 49 {
            check(p, 60.0, [0.5625, 1.0, 0.5625]);
        }
        if frame == 50 {
            // white tint disables the focus: only the 90° cone remains
            let s = Shaping::new(&p, None, ShapingOptions::default()).unwrap();
            let plain = Shaping::new(&RECT, None, ShapingOptions::default()).unwrap();
            for theta in [0.0, 45.0, 80.0, 100.0] {
                assert_eq!(
                    s.factor(dir_deg(theta, 10.0)),
                    plain.factor(dir_deg(theta, 10.0))
                );
            }
        }
    }
}
