//! Properties that hold for every input: bounds, the identities the schema text states, the cone's
//! shape, the two softness rules, and the IES lookup.

mod common;

use common::{arb_file, web_of};
use core::f64::consts::PI;
use glam::DVec3;
use lux_ies::Interpolation;
use lux_math::{Profile, light_direction, light_polar, smooth_step};
use lux_shaping::{AngleScaleFormula, Shaping, ShapingOptions, ShapingParams};
use proptest::prelude::*;

fn arb_params() -> impl Strategy<Value = ShapingParams> {
    (
        prop_oneof![Just(0.0), -2.0f64..0.0, 0.0f64..8.0, 8.0f64..500.0],
        prop::array::uniform3(prop_oneof![0.0f64..1.0, Just(1.0), 1.0f64..4.0]),
        prop_oneof![
            0.0f64..180.0,
            Just(90.0),
            Just(180.0),
            180.0f64..400.0,
            -10.0f64..0.0
        ],
        prop_oneof![Just(0.0), 0.0f64..1.0, Just(1.0), -1.0f64..2.5],
        prop_oneof![Just(0.0), Just(1.0), -3.0f64..3.0],
        any::<bool>(),
    )
        .prop_map(|(focus, tint, cone, soft, scale, norm)| ShapingParams {
            focus,
            focus_tint: DVec3::from_array(tint),
            cone_angle_deg: cone,
            cone_softness: soft,
            ies_angle_scale: scale,
            ies_normalize: norm,
        })
}

fn arb_options() -> impl Strategy<Value = ShapingOptions> {
    (any::<bool>(), any::<bool>(), any::<bool>()).prop_map(|(hd, legacy, cubic)| ShapingOptions {
        profile: if hd { Profile::HdEmbree } else { Profile::Spec },
        angle_scale: if legacy {
            AngleScaleFormula::Legacy
        } else {
            AngleScaleFormula::TwoBranch
        },
        interpolation: if cubic {
            Interpolation::Bicubic
        } else {
            Interpolation::Bilinear
        },
    })
}

/// A direction given by (θ, φ) in radians, with a random length; θ is drawn with extra weight
/// on the poles and the equator, where the edge cases are.
fn arb_dir() -> impl Strategy<Value = DVec3> {
    (
        prop_oneof![
            0.0f64..=PI,
            Just(0.0),
            Just(PI),
            Just(PI / 2.0),
            0.0f64..1e-6,
            (PI - 1e-6)..=PI
        ],
        0.0f64..core::f64::consts::TAU,
        prop_oneof![Just(1.0), 1e-3f64..1e3],
    )
        .prop_map(|(t, p, len)| light_direction(t, p) * len)
}

fn arb_shaping() -> impl Strategy<Value = Shaping> {
    (
        arb_params(),
        arb_options(),
        prop::option::weighted(0.6, arb_file()),
    )
        .prop_filter_map("legacy −1 is rejected", |(p, o, f)| {
            Shaping::new(&p, f.as_ref().map(web_of), o).ok()
        })
}

/// `n` directions inside the cone of half-angle `h` around the unit `axis`, including its rim.
fn cone_dirs(axis: DVec3, h: f64, n: usize, seed: u64) -> Vec<DVec3> {
    let f = lux_math::Frame::from_normal(axis);
    let mut s = seed | 1;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|k| {
            // uniform in solid angle on the cap, plus a ring of directions on the rim
            let ct = if k % 4 == 0 {
                h.cos()
            } else {
                1.0 - next() * (1.0 - h.cos())
            };
            let st = (1.0 - ct * ct).max(0.0).sqrt();
            let p = next() * core::f64::consts::TAU;
            f.to_world(DVec3::new(st * p.cos(), st * p.sin(), ct))
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn factor_is_finite_non_negative_and_below_max_factor(s in arb_shaping(), d in arb_dir()) {
        let f = s.factor(d);
        let m = s.max_factor();
        prop_assert!(m.is_finite() && m >= 0.0);
        for c in f.to_array() {
            prop_assert!(c.is_finite() && c >= 0.0 && c <= m, "{:?} max {}", f, m);
        }
    }

    #[test]
    fn nothing_is_emitted_beyond_the_emission_half_angle(
        s in arb_shaping(),
        t in 0.0f64..=1.0,
        p in 0.0f64..core::f64::consts::TAU,
    ) {
        let e = s.emission_half_angle();
        prop_assert!((0.0..=PI).contains(&e), "{}", e);
        // every direction strictly outside the cone e, from just past its rim to +Z
        let theta = e + 1e-6 + t * (PI - e - 1e-6).max(0.0);
        if theta <= PI {
            let f = s.factor(light_direction(theta, p));
            prop_assert_eq!(f, DVec3::ZERO, "θ {} beyond θe {}", theta, e);
        }
    }

    #[test]
    fn max_factor_in_cone_is_conservative(
        s in arb_shaping(),
        axis in arb_dir(),
        h in prop_oneof![0.0f64..0.3, 0.0f64..PI, Just(0.0)],
        seed in any::<u64>(),
    ) {
        let bound = s.max_factor_in_cone(axis, h);
        prop_assert!(bound <= s.max_factor());
        let a = axis.normalize();
        for d in cone_dirs(a, h, 64, seed).into_iter().chain([a]) {
            let f = s.factor(d);
            for c in f.to_array() {
                prop_assert!(c <= bound, "{:?} in cone ({:?}, {}) above bound {}", f, a, h, bound);
            }
        }
    }

    #[test]
    fn white_tint_disables_focus(
        mut p in arb_params(),
        o in arb_options(),
        file in prop::option::of(arb_file()),
        d in arb_dir(),
    ) {
        p.focus_tint = DVec3::ONE;
        let a = Shaping::new(&p, file.as_ref().map(web_of), o);
        p.focus = 0.0;
        let b = Shaping::new(&p, file.as_ref().map(web_of), o);
        if let (Ok(a), Ok(b)) = (a, b) {
            prop_assert_eq!(a.factor(d), b.factor(d));
        }
    }

    #[test]
    fn non_positive_focus_is_ignored(
        focus in prop_oneof![-1e6f64..=0.0, Just(f64::NAN), Just(f64::NEG_INFINITY)],
        tint in prop::array::uniform3(0.0f64..3.0),
        d in arb_dir(),
    ) {
        let p = ShapingParams { focus, focus_tint: DVec3::from_array(tint), ..ShapingParams::NO_SHAPING };
        let s = Shaping::new(&p, None, ShapingOptions::default()).unwrap();
        prop_assert!(s.is_identity());
        prop_assert_eq!(s.factor(d), DVec3::ONE);
    }

    #[test]
    fn cone_of_180_degrees_without_softness_is_the_identity(d in arb_dir(), hd in any::<bool>()) {
        let o = ShapingOptions { profile: if hd { Profile::HdEmbree } else { Profile::Spec }, ..Default::default() };
        for angle in [180.0, 181.0, 360.0, f64::INFINITY] {
            let p = ShapingParams { cone_angle_deg: angle, ..Default::default() };
            let s = Shaping::new(&p, None, o).unwrap();
            prop_assert!(s.is_identity());
            prop_assert_eq!(s.factor(d), DVec3::ONE);
            prop_assert_eq!(s.max_factor(), 1.0);
        }
    }

    #[test]
    fn cone_is_non_increasing_and_continuous_at_its_edge(
        angle in 0.5f64..179.5,
        soft in 0.0f64..=1.0,
        t1 in 0.0f64..=PI,
        t2 in 0.0f64..=PI,
        phi in 0.0f64..core::f64::consts::TAU,
    ) {
        let p = ShapingParams { cone_angle_deg: angle, cone_softness: soft, ..Default::default() };
        let s = Shaping::new(&p, None, ShapingOptions::default()).unwrap();
        let f = |t: f64| s.factor(light_direction(t, phi))[0] as f64;
        let (lo, hi) = if t1 <= t2 { (t1, t2) } else { (t2, t1) };
        prop_assert!(f(lo) >= f(hi), "f({lo}) = {} < f({hi}) = {}", f(lo), f(hi));
        let cut = angle.to_radians();
        prop_assert_eq!(f((cut + 1e-6).min(PI)) * (cut + 1e-6 <= PI) as u8 as f64, 0.0);
        if soft > 0.0 {
            // 1 − smoothstep ≈ 3(1 − t)² near the edge: continuous, reaching 0
            let w = soft * cut;
            let delta = 1e-3 * w;
            let near = f(cut - delta);
            prop_assert!(near <= 3.0 * 1e-6 + 1e-6, "{near}");
            prop_assert!(near > 0.0);
        } else {
            prop_assert_eq!(f(cut - 1e-9), 1.0);
        }
    }

    #[test]
    fn softness_outside_unit_interval_clamps_under_spec_only(
        angle in 5.0f64..175.0,
        soft in prop_oneof![1.0f64..5.0, -5.0f64..0.0],
        d in arb_dir(),
    ) {
        let mk = |s: f64, profile| Shaping::new(
            &ShapingParams { cone_angle_deg: angle, cone_softness: s, ..Default::default() },
            None,
            ShapingOptions { profile, ..Default::default() },
        ).unwrap();
        let spec = mk(soft, Profile::Spec);
        let clamped = mk(soft.clamp(0.0, 1.0), Profile::Spec);
        prop_assert_eq!(spec.factor(d), clamped.factor(d));
        let hd = mk(soft, Profile::HdEmbree);
        let on_axis = hd.factor(DVec3::NEG_Z)[0];
        if soft < 0.0 {
            // a reversed ramp: dark everywhere
            prop_assert_eq!(hd.factor(d), DVec3::ZERO);
            prop_assert_eq!(hd.max_factor(), 0.0);
        } else if soft > 1.0 {
            // ramp starts below 0: the axis itself is dimmed to 1 − smoothStep(0, (1−s)θc, θc)
            let cut = angle.to_radians();
            let want = 1.0 - smooth_step(0.0, (1.0 - soft) * cut, cut);
            prop_assert!((on_axis - want).abs() < 1e-6, "{on_axis} vs {want}");
            // the factor is f32: the dimming shows once it exceeds f32's resolution below 1
            // (softness 1 + 6e-5 dims the axis by ~1e-8, which rounds to 1)
            if want < 1.0 - f64::from(f32::EPSILON) {
                prop_assert!(on_axis < 1.0);
            }
            prop_assert_eq!(spec.factor(DVec3::NEG_Z), DVec3::ONE);
        }
    }

    #[test]
    fn angle_scale_zero_and_one_are_the_identity_for_the_ies_lookup(
        file in arb_file(),
        d in arb_dir(),
        cubic in any::<bool>(),
    ) {
        let w = web_of(&file);
        let interpolation = if cubic { Interpolation::Bicubic } else { Interpolation::Bilinear };
        let (t, p) = light_polar(d).unwrap();
        let want = w.intensity_with(t, p, interpolation);
        for formula in [AngleScaleFormula::TwoBranch, AngleScaleFormula::Legacy] {
            let scales: &[f64] = if formula == AngleScaleFormula::TwoBranch { &[0.0, 1.0] } else { &[0.0] };
            for &scale in scales {
                let params = ShapingParams { ies_angle_scale: scale, ..ShapingParams::NO_SHAPING };
                let o = ShapingOptions { angle_scale: formula, interpolation, ..Default::default() };
                let s = Shaping::new(&params, Some(w.clone()), o).unwrap();
                // the same interpolant, to the even grid's rounding (see `Shaping::factor`)
                let err = (s.factor(d) - DVec3::splat(want)).abs().max_element();
                prop_assert!(err <= 1e-12 * w.max_candela(), "{} vs {}", s.factor(d), want);
            }
        }
    }

    #[test]
    fn factor_is_the_product_of_the_three_terms(
        p in arb_params(),
        file in arb_file(),
        d in arb_dir(),
    ) {
        let o = ShapingOptions::default();
        let Ok(all) = Shaping::new(&p, Some(web_of(&file)), o) else { return Ok(()) };
        let focus_only = Shaping::new(&ShapingParams { cone_angle_deg: 180.0, cone_softness: 0.0, ..p }, None, o).unwrap();
        let cone_only = Shaping::new(&ShapingParams { focus: 0.0, ..p }, None, o).unwrap();
        let ies_only = Shaping::new(&ShapingParams { focus: 0.0, cone_angle_deg: 180.0, cone_softness: 0.0, ..p }, Some(web_of(&file)), o).unwrap();
        let (a, b, c, e) = (all.factor(d), focus_only.factor(d), cone_only.factor(d)[0], ies_only.factor(d)[0]);
        for k in 0..3 {
            let want = b[k] * c * e;
            prop_assert!((a[k] - want).abs() <= 1e-12 * want.max(1e-30) + 1e-30, "{a:?} vs {b:?}·{c}·{e}");
        }
    }
}

#[test]
fn identity_and_defaults() {
    let id = Shaping::identity();
    assert!(id.is_identity() && !id.has_ies());
    assert_eq!(id.params(), &ShapingParams::NO_SHAPING);
    assert_eq!(id.options(), ShapingOptions::default());
    assert_eq!(id.max_factor(), 1.0);
    assert_eq!(id.max_factor_in_cone(DVec3::Z, 0.1), 1.0);
    assert_eq!(id.factor(DVec3::new(0.3, -2.0, 5.0)), DVec3::ONE);
    assert!(id.ies().is_none() && id.ies_normalizer().is_none());
    // with ShapingAPI and nothing authored: a 90° hard cone
    let d = Shaping::new(&ShapingParams::default(), None, ShapingOptions::default()).unwrap();
    assert!(!d.is_identity());
    assert_eq!(d.factor(DVec3::new(1.0, 0.0, -1e-9)), DVec3::ONE);
    assert_eq!(
        d.factor(DVec3::new(1.0, 0.0, 0.0)),
        DVec3::ONE,
        "inclusive edge"
    );
    assert_eq!(d.factor(DVec3::new(1.0, 0.0, 1e-9)), DVec3::ZERO);
    // the query cone just behind the 90° cone sees nothing, the one straddling it everything
    assert_eq!(d.max_factor_in_cone(DVec3::Z, 0.5), 0.0);
    assert_eq!(d.max_factor_in_cone(DVec3::new(1.0, 0.0, 0.2), 0.3), 1.0);
    fn assert_send_sync<T: Send + Sync + Clone + std::fmt::Debug>() {}
    assert_send_sync::<Shaping>();
}

#[test]
fn max_factor_values() {
    let mk = |p: ShapingParams| Shaping::new(&p, None, ShapingOptions::default()).unwrap();
    // tint ≤ 1: the axis value, exactly 1
    let s = mk(ShapingParams {
        focus: 3.0,
        focus_tint: DVec3::new(0.2, 1.0, 0.5),
        cone_angle_deg: 30.0,
        cone_softness: 0.5,
        ..Default::default()
    });
    assert_eq!(s.max_factor(), 1.0);
    // tint 2.5 in green with a 90° cone: at θ → 90° the focus factor → 0, the colour → tint
    let s = mk(ShapingParams {
        focus: 1.0,
        focus_tint: DVec3::new(0.0, 2.5, 0.0),
        ..Default::default()
    });
    assert!((s.max_factor() - 2.5).abs() < 1e-6);
    // ... and a 60° cone keeps |cos θ| ≥ 1/2: max 2.5 − 1.5 · 0.5 = 1.75
    let s = mk(ShapingParams {
        focus: 1.0,
        focus_tint: DVec3::new(0.0, 2.5, 0.0),
        cone_angle_deg: 60.0,
        ..Default::default()
    });
    assert!((s.max_factor() - 1.75).abs() < 1e-6, "{}", s.max_factor());
    // hdEmbree softness 1.5 on a 40° cone: the axis value 1 − S(1/3) = 20/27
    let s = Shaping::new(
        &ShapingParams {
            cone_angle_deg: 40.0,
            cone_softness: 1.5,
            ..Default::default()
        },
        None,
        ShapingOptions {
            profile: Profile::HdEmbree,
            ..Default::default()
        },
    )
    .unwrap();
    assert!((s.max_factor() - 20.0 / 27.0).abs() < 1e-6);
    assert!((s.factor(DVec3::NEG_Z)[0] - 20.0 / 27.0).abs() < 1e-6);
}

#[test]
fn ies_bounds_follow_the_vertical_bands() {
    // a 0..180 profile bright only near the nadir and dim towards the zenith
    let v = vec![0.0, 10.0, 20.0, 90.0, 180.0];
    let f = common::file(
        lux_ies::PhotometricType::C,
        v,
        vec![0.0],
        vec![1000.0, 800.0, 50.0, 10.0, 2.0],
    );
    let s = Shaping::new(
        &ShapingParams::NO_SHAPING,
        Some(web_of(&f)),
        ShapingOptions::default(),
    )
    .unwrap();
    assert!((s.max_factor() - 1000.0).abs() < 1e-3);
    // looking at the zenith ± 30°: only the 90..180 band (≤ 10 cd)
    let up = s.max_factor_in_cone(DVec3::Z, 30f64.to_radians());
    assert!((up - 10.0).abs() < 1e-4, "{up}");
    // around 45° ± 10°: the 20..90 band (≤ 50 cd)
    let mid = s.max_factor_in_cone(common::dir_deg(45.0, 0.0), 10f64.to_radians());
    assert!((mid - 50.0).abs() < 1e-4, "{mid}");
    // the same with angleScale 0.5: θies = 2θ, so 45° ± 10° looks at 70..110° (≤ 50 cd)
    // and 5° ± 4° at 2..18° (≤ 1000 cd)
    let s = Shaping::new(
        &ShapingParams {
            ies_angle_scale: 0.5,
            ..ShapingParams::NO_SHAPING
        },
        Some(web_of(&f)),
        ShapingOptions::default(),
    )
    .unwrap();
    let mid = s.max_factor_in_cone(common::dir_deg(45.0, 0.0), 10f64.to_radians());
    assert!((mid - 50.0).abs() < 1e-4, "{mid}");
    // beyond θ = 90° θies ≥ 180°: the value at the last vertical angle (2 cd)
    let back = s.max_factor_in_cone(DVec3::Z, 60f64.to_radians());
    assert!((back - 2.0).abs() < 1e-5, "{back}");
}

#[test]
fn emission_half_angle_values() {
    let deg = |s: &Shaping| s.emission_half_angle().to_degrees();
    let with = |p: ShapingParams, ies: Option<&lux_ies::IesFile>| {
        Shaping::new(&p, ies.map(web_of), ShapingOptions::default()).unwrap()
    };
    assert_eq!(Shaping::identity().emission_half_angle(), PI);
    // the schema default cone (90°) and a hard and a soft cone: their cut-off angle
    assert!((deg(&with(ShapingParams::SCHEMA_DEFAULTS, None)) - 90.0).abs() < 1e-5);
    let cone = |a: f64, s: f64| ShapingParams {
        cone_angle_deg: a,
        cone_softness: s,
        ..ShapingParams::SCHEMA_DEFAULTS
    };
    assert!((deg(&with(cone(30.0, 0.0), None)) - 30.0).abs() < 1e-5);
    assert!((deg(&with(cone(40.0, 0.7), None)) - 40.0).abs() < 1e-5);
    assert_eq!(with(cone(-5.0, 0.0), None).emission_half_angle(), 0.0);
    // a downlight profile, dark from 60° on: 60°, or 30° once angleScale 0.5 doubles θies
    let f = common::file(
        lux_ies::PhotometricType::C,
        vec![0.0, 30.0, 60.0, 90.0, 180.0],
        vec![0.0],
        vec![900.0, 500.0, 0.0, 0.0, 0.0],
    );
    let ies = |scale: f64, cone_deg: f64| ShapingParams {
        ies_angle_scale: scale,
        ..cone(cone_deg, 0.0)
    };
    let s = with(ies(0.0, 180.0), Some(&f));
    assert!((deg(&s) - 60.0).abs() < 1e-5, "{}", deg(&s));
    // tight: just inside, the profile still emits
    assert!(s.factor(light_direction(59.9f64.to_radians(), 0.3))[0] > 0.0);
    assert!((deg(&with(ies(0.5, 180.0), Some(&f))) - 30.0).abs() < 1e-5);
    // whichever of the cone and the profile is narrower
    assert!((deg(&with(ies(0.0, 45.0), Some(&f))) - 45.0).abs() < 1e-5);
    // focus alone never darkens the back: θe = π
    let focus = ShapingParams {
        focus: 3.0,
        focus_tint: DVec3::splat(0.0),
        ..ShapingParams::NO_SHAPING
    };
    assert_eq!(with(focus, None).emission_half_angle(), PI);
}
