//! Bad input: NaN and infinite parameters, degenerate directions. The constructor never panics
//! and either returns a documented error or a shaping whose factor is finite and non-negative.

mod common;

use common::{arb_file, dir_deg, web_of};
use glam::DVec3;
use lux_math::Profile;
use lux_shaping::{AngleScaleFormula, Shaping, ShapingError, ShapingOptions, ShapingParams};
use proptest::prelude::*;

fn attribute(e: &ShapingError) -> &'static str {
    match e {
        ShapingError::InvalidParameter { attribute, .. } => attribute,
        _ => "",
    }
}

/// Any f64 with the special values well represented.
fn wild() -> impl Strategy<Value = f64> {
    prop_oneof![
        any::<f64>(),
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(0.0),
        Just(-0.0),
        Just(f64::MIN_POSITIVE),
        Just(f64::MAX),
        Just(-1.0),
        -10.0f64..400.0,
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn arbitrary_parameters_and_directions_never_give_nan(
        focus in wild(), tint in prop::array::uniform3(wild()), cone in wild(), soft in wild(),
        scale in wild(), normalize in any::<bool>(), hd in any::<bool>(), legacy in any::<bool>(),
        file in prop::option::of(arb_file()),
        d in prop::array::uniform3(wild()),
    ) {
        let p = ShapingParams {
            focus, focus_tint: DVec3::from_array(tint), cone_angle_deg: cone, cone_softness: soft,
            ies_angle_scale: scale, ies_normalize: normalize,
        };
        let o = ShapingOptions {
            profile: if hd { Profile::HdEmbree } else { Profile::Spec },
            angle_scale: if legacy { AngleScaleFormula::Legacy } else { AngleScaleFormula::TwoBranch },
            ..Default::default()
        };
        match Shaping::new(&p, file.as_ref().map(web_of), o) {
            Err(e) => {
                // only the documented errors
                let a = attribute(&e);
                let ok = (a == "inputs:shaping:cone:angle" && cone.is_nan())
                    || (a == "inputs:shaping:focusTint" && focus > 0.0 && tint.iter().any(|t| !t.is_finite()))
                    || (a == "inputs:shaping:ies:angleScale" && file.is_some()
                        && (!scale.is_finite() || (legacy && scale == -1.0)));
                prop_assert!(ok, "unexpected error {}", e);
                prop_assert!(!e.to_string().is_empty());
            }
            Ok(s) => {
                prop_assert!(!cone.is_nan());
                let m = s.max_factor();
                prop_assert!(m.is_finite() && m >= 0.0);
                for dir in [DVec3::from_array(d), DVec3::NEG_Z, DVec3::Z, DVec3::X, dir_deg(33.0, 71.0)] {
                    let f = s.factor(dir);
                    for c in f.to_array() {
                        prop_assert!(c.is_finite() && c >= 0.0 && c <= m, "{:?} at {:?} (max {})", f, dir, m);
                    }
                }
                let b = s.max_factor_in_cone(DVec3::from_array(d), tint[0]);
                prop_assert!(b.is_finite() && b >= 0.0 && b <= m);
            }
        }
    }

    #[test]
    fn integrals_of_arbitrary_parameters_are_not_nan(
        focus in wild(), tint in prop::array::uniform3(wild()), cone in wild(), soft in wild(),
        hd in any::<bool>(),
    ) {
        let p = ShapingParams {
            focus, focus_tint: DVec3::from_array(tint), cone_angle_deg: cone, cone_softness: soft,
            ..ShapingParams::default()
        };
        let o = ShapingOptions {
            profile: if hd { Profile::HdEmbree } else { Profile::Spec },
            ..Default::default()
        };
        if let Ok(s) = Shaping::new(&p, None, o) {
            for v in s.integral_sphere().to_array().into_iter().chain(s.integral_cos_hemisphere().to_array()) {
                // a tint near f64::MAX may overflow to +∞, never to NaN or below 0
                prop_assert!(v >= 0.0, "{:?}", v);
            }
        }
    }

    #[test]
    fn degenerate_directions_give_zero_and_scale_does_not_matter(
        x in -1.0f64..1.0, y in -1.0f64..1.0, z in -1.0f64..1.0,
        k in prop_oneof![Just(1e-300), Just(1e-160), Just(1e150), Just(1e300)],
    ) {
        let p = ShapingParams { focus: 2.0, cone_angle_deg: 100.0, cone_softness: 0.5, ..Default::default() };
        let s = Shaping::new(&p, None, ShapingOptions::default()).unwrap();
        let d = DVec3::new(x, y, z);
        prop_assume!(d.length() > 1e-3);
        let a = s.factor(d);
        let b = s.factor(d * k);
        for c in 0..3 {
            prop_assert!((a[c] - b[c]).abs() <= 1e-6, "{:?} vs {:?}", a, b);
        }
    }
}

#[test]
fn documented_results_of_special_values() {
    let o = ShapingOptions::default();
    let ok = |p: ShapingParams| Shaping::new(&p, None, o).unwrap();
    let axis = DVec3::NEG_Z;
    let side = dir_deg(60.0, 0.0);
    // NaN focus: ignored
    let s = ok(ShapingParams {
        focus: f64::NAN,
        ..ShapingParams::NO_SHAPING
    });
    assert!(s.is_identity());
    // +∞ focus: the tint everywhere off the axis, white on it
    let s = ok(ShapingParams {
        focus: f64::INFINITY,
        focus_tint: DVec3::new(0.25, 0.5, 2.0),
        ..ShapingParams::NO_SHAPING
    });
    assert_eq!(s.factor(axis), DVec3::ONE);
    assert_eq!(s.factor(side), DVec3::new(0.25, 0.5, 2.0));
    // negative tint components count as 0
    let s = ok(ShapingParams {
        focus: 1.0,
        focus_tint: DVec3::new(-3.0, 0.0, 0.5),
        ..ShapingParams::NO_SHAPING
    });
    assert_eq!(s.factor(DVec3::X), DVec3::new(0.0, 0.0, 0.5));
    // NaN tint with focus off is never used
    assert!(
        ok(ShapingParams {
            focus_tint: DVec3::splat(f64::NAN),
            ..ShapingParams::NO_SHAPING
        })
        .is_identity()
    );
    // ... and an error with focus on
    let e = Shaping::new(
        &ShapingParams {
            focus: 1.0,
            focus_tint: DVec3::new(0.0, f64::INFINITY, 0.0),
            ..Default::default()
        },
        None,
        o,
    )
    .unwrap_err();
    assert_eq!(
        e,
        ShapingError::InvalidParameter {
            attribute: "inputs:shaping:focusTint",
            value: "(0, inf, 0)".into(),
            expected: "finite colour components",
        }
    );
    // NaN cone angle: an error naming the attribute
    let e = Shaping::new(
        &ShapingParams {
            cone_angle_deg: f64::NAN,
            ..Default::default()
        },
        None,
        o,
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "inputs:shaping:cone:angle = NaN: expected an angle in degrees (not NaN)"
    );
    // negative / −∞ cone: dark; +∞: no cone
    for c in [-1.0, -1e-300, f64::NEG_INFINITY] {
        let s = ok(ShapingParams {
            cone_angle_deg: c,
            ..Default::default()
        });
        assert_eq!(s.factor(axis), DVec3::ZERO);
        assert_eq!(s.max_factor(), 0.0);
        assert_eq!(s.integral_sphere(), DVec3::ZERO);
    }
    assert!(
        ok(ShapingParams {
            cone_angle_deg: f64::INFINITY,
            cone_softness: 0.5,
            ..Default::default()
        })
        .is_identity()
    );
    // NaN softness: 0
    let s = ok(ShapingParams {
        cone_angle_deg: 45.0,
        cone_softness: f64::NAN,
        ..Default::default()
    });
    assert_eq!(s.factor(dir_deg(44.9, 0.0)), DVec3::ONE);
    // ±∞ softness: clamped under spec, dark under hdEmbree
    let hd = ShapingOptions {
        profile: Profile::HdEmbree,
        ..Default::default()
    };
    for soft in [f64::INFINITY, f64::NEG_INFINITY] {
        let p = ShapingParams {
            cone_angle_deg: 45.0,
            cone_softness: soft,
            ..Default::default()
        };
        assert_eq!(ok(p).factor(axis), DVec3::ONE);
        assert_eq!(
            Shaping::new(&p, None, hd).unwrap().factor(axis),
            DVec3::ZERO
        );
    }
    // angleScale NaN / ∞: an error only when there is a profile
    let spot = common::web("luxtest/bega_84693k4.ies", Profile::Spec);
    for scale in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let p = ShapingParams {
            ies_angle_scale: scale,
            ..Default::default()
        };
        assert!(Shaping::new(&p, None, o).is_ok());
        let e = Shaping::new(&p, Some(spot.clone()), o).unwrap_err();
        assert_eq!(attribute(&e), "inputs:shaping:ies:angleScale");
    }
    // degenerate directions
    let s = ok(ShapingParams::default());
    for d in [
        DVec3::ZERO,
        DVec3::new(f64::NAN, 0.0, -1.0),
        DVec3::new(0.0, f64::INFINITY, -1.0),
        DVec3::splat(f64::NEG_INFINITY),
    ] {
        assert_eq!(s.factor(d), DVec3::ZERO, "{d:?}");
        assert_eq!(Shaping::identity().factor(d), DVec3::ZERO, "{d:?}");
    }
    // tiny and huge but valid directions
    assert_eq!(s.factor(DVec3::new(0.0, 0.0, -1e-320)), DVec3::ONE);
    assert_eq!(s.factor(DVec3::new(1e308, 0.0, -1e308)), DVec3::ONE);
    // a huge tint is the factor off the axis, bounded by max_factor; the largest one
    // saturates the bound at f64::MAX instead of overflowing
    let s = ok(ShapingParams {
        focus: 1.0,
        focus_tint: DVec3::new(1e300, 0.0, 0.0),
        ..ShapingParams::NO_SHAPING
    });
    assert_eq!(s.factor(DVec3::X)[0], 1e300);
    assert!(s.max_factor() >= 1e300 && s.max_factor().is_finite());
    let s = ok(ShapingParams {
        focus: 1.0,
        focus_tint: DVec3::new(f64::MAX, 0.0, 0.0),
        ..ShapingParams::NO_SHAPING
    });
    assert_eq!(s.factor(DVec3::X)[0], f64::MAX);
    assert_eq!(s.max_factor(), f64::MAX);
}

/// A soft cone of a subnormal angle whose softness reaches far past the axis (`hdEmbree`
/// profile: softness unclamped): on the axis `1 − smoothStep` cancels to ~2·10⁻⁵, and the
/// bound, computed as the factor computes it, still holds (found by the proptest above).
#[test]
fn a_tiny_soft_cone_stays_under_its_bound_on_the_axis() {
    let p = ShapingParams {
        cone_angle_deg: f64::MIN_POSITIVE,
        cone_softness: 360.2421417267986,
        ..ShapingParams::NO_SHAPING
    };
    let o = ShapingOptions {
        profile: Profile::HdEmbree,
        ..Default::default()
    };
    let s = Shaping::new(&p, None, o).unwrap();
    let (f, m) = (s.factor(DVec3::NEG_Z), s.max_factor());
    assert!(f[0] > 0.0 && f[0] < 1e-4, "{f:?}");
    assert!(f.max_element() <= m, "{f:?} above {m}");
}
