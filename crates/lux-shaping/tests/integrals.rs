//! `integral_sphere`, `integral_cos_hemisphere` and `integral_weighted` against closed forms, to
//! 1e-5 relative (the implementation asks its quadrature for 1e-10; the assertions below use
//! 1e-9 where the closed form is exact so that a loss of accuracy is seen early).

mod common;

use common::{file, web, web_of};
use core::f64::consts::{FRAC_PI_2, PI, TAU};
use glam::DVec3;
use lux_ies::{Interpolation, PhotometricType};
use lux_math::Profile;
use lux_shaping::{AngleScaleFormula, Shaping, ShapingOptions, ShapingParams};

fn shaping(p: ShapingParams) -> Shaping {
    Shaping::new(&p, None, ShapingOptions::default()).unwrap()
}

#[track_caller]
fn close(got: f64, want: f64, rel: f64) {
    let err = (got - want).abs() / want.abs().max(1e-300);
    assert!(
        err <= rel || (got - want).abs() < 1e-14,
        "got {got}, want {want} (rel err {err:e})"
    );
}

#[track_caller]
fn close3(got: impl Into<[f64; 3]>, want: impl Into<[f64; 3]>, rel: f64) {
    let (got, want) = (got.into(), want.into());
    for c in 0..3 {
        close(got[c], want[c], rel);
    }
}

const TIGHT: f64 = 1e-9;

/// `∫_0^1 u^n sin(a + b u) du` for n = 0..=3 by integration by parts (b ≠ 0).
fn sin_moments(a: f64, b: f64) -> [f64; 4] {
    let mut s = [0.0; 4];
    let mut c = [0.0; 4];
    for n in 0..4 {
        let nf = n as f64;
        let (s_prev, c_prev) = if n == 0 {
            (0.0, 0.0)
        } else {
            (s[n - 1], c[n - 1])
        };
        let start = if n == 0 { 1.0 } else { 0.0 };
        s[n] = (-(a + b).cos() + start * a.cos()) / b + nf / b * c_prev;
        c[n] = ((a + b).sin() - start * a.sin()) / b - nf / b * s_prev;
    }
    s
}

/// `∫_{θs}^{θc} (1 − smoothstep) g(θ) dθ` with g = sin (weight `k` = 1) or sin·cos = sin(2θ)/2
/// (`k` = 2), in closed form: u = (θ − θs)/w, 1 − 3u² + 2u³.
fn ramp_integral(ts: f64, tc: f64, k: f64) -> f64 {
    let w = tc - ts;
    let m = sin_moments(k * ts, k * w);
    let poly = m[0] - 3.0 * m[2] + 2.0 * m[3];
    let scale = if k == 1.0 { 1.0 } else { 0.5 };
    scale * w * poly
}

#[test]
fn no_shaping_is_the_sphere_and_the_cosine_hemisphere() {
    for s in [Shaping::identity(), shaping(ShapingParams::NO_SHAPING)] {
        close3(s.integral_sphere(), [4.0 * PI; 3], TIGHT);
        close3(s.integral_cos_hemisphere(), [PI; 3], TIGHT);
        close3(s.integral_weighted(|_| 1.0), [4.0 * PI; 3], TIGHT);
    }
    // the schema default cone (90°) keeps the front hemisphere
    let d = shaping(ShapingParams::default());
    close3(d.integral_sphere(), [TAU; 3], TIGHT);
    close3(d.integral_cos_hemisphere(), [PI; 3], TIGHT);
}

#[test]
fn hard_cones() {
    for deg in [1.0, 10.0, 33.3, 45.0, 89.0, 90.0, 91.0, 130.0, 170.0, 179.9] {
        let s = shaping(ShapingParams {
            cone_angle_deg: deg,
            ..Default::default()
        });
        let tc = f64::to_radians(deg);
        close3(s.integral_sphere(), [TAU * (1.0 - tc.cos()); 3], TIGHT);
        let hemi = if tc <= FRAC_PI_2 {
            PI * tc.sin().powi(2)
        } else {
            PI
        };
        close3(s.integral_cos_hemisphere(), [hemi; 3], TIGHT);
    }
    // negative: nothing at all
    let s = shaping(ShapingParams {
        cone_angle_deg: -5.0,
        ..Default::default()
    });
    assert_eq!(s.integral_sphere(), DVec3::ZERO);
}

#[test]
fn soft_cones_match_the_smoothstep_closed_form() {
    for (deg, soft) in [
        (45.0, 0.25),
        (45.0, 1.0),
        (10.0, 0.5),
        (90.0, 0.75),
        (130.0, 0.3),
        (170.0, 1.0),
        (250.0, 0.5),
    ] {
        let s = shaping(ShapingParams {
            cone_angle_deg: deg,
            cone_softness: soft,
            ..Default::default()
        });
        let tc: f64 = f64::to_radians(deg);
        let ts = (1.0 - soft) * tc;
        // sphere: plateau [0, ts] + ramp [ts, min(tc, π)] (a ramp beyond π is cut at π)
        let sphere = if tc <= PI {
            TAU * ((1.0 - ts.cos()) + ramp_integral(ts, tc, 1.0))
        } else {
            // the ramp runs from ts to tc > π; integrate the same cubic only up to π
            let w = tc - ts;
            let u_end = (PI - ts) / w;
            let m = sin_moments_partial(ts, w, u_end);
            TAU * ((1.0 - ts.cos()) + w * (m[0] - 3.0 * m[2] + 2.0 * m[3]))
        };
        close3(s.integral_sphere(), [sphere; 3], TIGHT);
        if tc <= FRAC_PI_2 {
            let hemi = PI * ts.sin().powi(2) + TAU * ramp_integral(ts, tc, 2.0);
            close3(s.integral_cos_hemisphere(), [hemi; 3], TIGHT);
        }
    }
}

/// `∫_0^{u_end} u^n sin(a + b u) du`: substitute v = u/u_end.
fn sin_moments_partial(a: f64, b: f64, u_end: f64) -> [f64; 4] {
    let m = sin_moments(a, b * u_end);
    [
        m[0] * u_end,
        m[1] * u_end.powi(2),
        m[2] * u_end.powi(3),
        m[3] * u_end.powi(4),
    ]
}

#[test]
fn focus_powers_of_the_cosine() {
    for f in [0.05, 0.5, 1.0, 2.0, 3.75, 10.0, 250.0, 1e4] {
        // no cone: |cos|^f over the whole sphere (both hemispheres)
        let s = shaping(ShapingParams {
            focus: f,
            cone_angle_deg: 180.0,
            ..Default::default()
        });
        close3(s.integral_sphere(), [4.0 * PI / (f + 1.0); 3], TIGHT);
        close3(s.integral_cos_hemisphere(), [TAU / (f + 2.0); 3], TIGHT);
        // with a tint: t + (1 − t)|cos|^f per channel
        let tint = [0.0, 0.25, 2.0];
        let s = shaping(ShapingParams {
            focus: f,
            focus_tint: DVec3::from_array(tint),
            cone_angle_deg: 180.0,
            ..Default::default()
        });
        let want = tint.map(|t| t * 4.0 * PI + (1.0 - t) * 4.0 * PI / (f + 1.0));
        close3(s.integral_sphere(), want, TIGHT);
        let want = tint.map(|t| t * PI + (1.0 - t) * TAU / (f + 2.0));
        close3(s.integral_cos_hemisphere(), want, TIGHT);
        // with a hard 40° cone: 2π(1 − cos^{f+1}θc)/(f + 1)
        let tc = 40f64.to_radians();
        let s = shaping(ShapingParams {
            focus: f,
            cone_angle_deg: 40.0,
            ..Default::default()
        });
        close3(
            s.integral_sphere(),
            [TAU * (1.0 - tc.cos().powf(f + 1.0)) / (f + 1.0); 3],
            TIGHT,
        );
        close3(
            s.integral_cos_hemisphere(),
            [TAU * (1.0 - tc.cos().powf(f + 2.0)) / (f + 2.0); 3],
            TIGHT,
        );
    }
}

#[test]
fn weighted_integral_agrees_with_the_special_cases() {
    let p = ShapingParams {
        focus: 1.5,
        focus_tint: DVec3::new(0.1, 0.6, 1.0),
        cone_angle_deg: 75.0,
        cone_softness: 0.4,
        ..Default::default()
    };
    let s = shaping(p);
    close3(s.integral_weighted(|_| 1.0), s.integral_sphere(), 1e-8);
    close3(
        s.integral_weighted(|d| (-d.z).max(0.0)),
        s.integral_cos_hemisphere(),
        1e-8,
    );
    // a weight that depends on φ: (1 + x) integrates to the same as 1 (x is odd)
    close3(
        s.integral_weighted(|d| 1.0 + d.x),
        s.integral_sphere(),
        1e-8,
    );
    // x² + y² + z² = 1 split: ∫ z² for |cos|^0 over the sphere = 4π/3
    let n = shaping(ShapingParams::NO_SHAPING);
    close3(
        n.integral_weighted(|d| d.z * d.z),
        [4.0 * PI / 3.0; 3],
        TIGHT,
    );
    close3(
        n.integral_weighted(|d| d.x * d.x),
        [4.0 * PI / 3.0; 3],
        TIGHT,
    );
}

fn ies_shaping(web: lux_ies::PhotometricWeb, p: ShapingParams, o: ShapingOptions) -> Shaping {
    Shaping::new(&p, Some(web), o).unwrap()
}

#[test]
fn linear_axial_profile_with_angle_scale() {
    // test_linear_vertical.ies: I(θ) = 1 − θ/π over 0..180, one plane.
    let w = web("luxtest/test_linear_vertical.ies", Profile::Spec);
    let base = ShapingParams {
        cone_angle_deg: 180.0,
        ..Default::default()
    };
    let s = ies_shaping(w.clone(), base, ShapingOptions::default());
    close3(s.integral_sphere(), [TAU; 3], TIGHT);
    // ∫_0^{π/2} (1 − θ/π) sinθ cosθ dθ = 1/2 − (1/π)(π/8) = 3/8
    close3(s.integral_cos_hemisphere(), [TAU * 3.0 / 8.0; 3], TIGHT);
    // angleScale 0.5: θies = 2θ; beyond θ = π/2 the 180° value (0).
    // 2π ∫_0^{π/2} (1 − 2θ/π) sinθ dθ = 2π (1 − 2/π)
    let s = ies_shaping(
        w.clone(),
        ShapingParams {
            ies_angle_scale: 0.5,
            ..base
        },
        ShapingOptions::default(),
    );
    close3(s.integral_sphere(), [TAU * (1.0 - 2.0 / PI); 3], TIGHT);
    // angleScale −0.5: θies = 2(θ − π) + π, < 0 (→ 0) for θ < π/2; I = 1 − θies/π = 2 − 2θ/π
    // 2π ∫_{π/2}^{π} (2 − 2θ/π) sinθ dθ = 2π (2 − (2/π)(π − 1)) = 2π · 2/π = 4
    let s = ies_shaping(
        w.clone(),
        ShapingParams {
            ies_angle_scale: -0.5,
            ..base
        },
        ShapingOptions::default(),
    );
    close3(s.integral_sphere(), [4.0; 3], TIGHT);
    // normalize: flux 2π over 4π → mean 1/2; sphere integral of I/mean = 4π
    let s = ies_shaping(
        w,
        ShapingParams {
            ies_normalize: true,
            ..base
        },
        ShapingOptions::default(),
    );
    close(s.ies_normalizer().unwrap(), 0.5, 1e-12);
    close3(s.integral_sphere(), [4.0 * PI; 3], TIGHT);
}

#[test]
fn non_axial_profiles_integrate_to_their_exact_flux() {
    let no_cone = ShapingParams {
        cone_angle_deg: 180.0,
        ..Default::default()
    };
    for rel in [
        "luxtest/bega_omni001_1238lm.ies",
        "luxtest/bega_omni002_4777lm.ies",
        "luxtest/bega_84659K4.ies",
        "luxtest/test_vstripes_hquadrants_nonuniform.ies",
        "radiance/examp1.ies",
        "appleseed/test_iesparser_3.ies",
    ] {
        let w = web(rel, Profile::Spec);
        let flux = w.flux_exact();
        let s = ies_shaping(w, no_cone, ShapingOptions::default());
        close3(s.integral_sphere(), [flux; 3], TIGHT);
    }
}

#[test]
fn type_b_profiles_integrate_numerically_to_their_exact_flux() {
    // types A/B are not aligned with (θ, φ): the φ integral is adaptive, 1e-5 is the target
    let no_cone = ShapingParams {
        cone_angle_deg: 180.0,
        ..Default::default()
    };
    for rel in ["appleseed/test_iesparser_2.ies", "mdl-sdk/test.ies"] {
        let w = web(rel, Profile::Spec);
        let flux = w.flux_exact();
        let s = ies_shaping(w, no_cone, ShapingOptions::default());
        close3(s.integral_sphere(), [flux; 3], 1e-7);
    }
}

#[test]
fn bicubic_and_weighted_paths_agree_with_the_exact_one() {
    // A smooth full-sphere profile where bilinear and bicubic nearly agree, with a cone and
    // focus so that every path (exact φ, numerical φ, 2-D weighted) is exercised.
    let vs: Vec<f64> = (0..=36).map(|k| 5.0 * k as f64).collect();
    let hs: Vec<f64> = (0..=24).map(|k| 15.0 * k as f64).collect();
    let g = |v: f64, h: f64| {
        100.0 + 60.0 * v.to_radians().cos() + 25.0 * h.to_radians().cos() * v.to_radians().sin()
    };
    let cd: Vec<f64> = hs
        .iter()
        .flat_map(|&h| vs.iter().map(move |&v| g(v, h)))
        .collect();
    let f = file(PhotometricType::C, vs, hs, cd);
    let p = ShapingParams {
        focus: 0.8,
        focus_tint: DVec3::new(0.3, 0.3, 0.3),
        cone_angle_deg: 120.0,
        cone_softness: 0.3,
        ies_angle_scale: 0.8,
        ies_normalize: true,
    };
    let bil = ies_shaping(web_of(&f), p, ShapingOptions::default());
    let exact = bil.integral_sphere();
    close3(bil.integral_weighted(|_| 1.0), exact, 1e-8);
    close3(
        bil.integral_weighted(|d| (-d.z).max(0.0)),
        bil.integral_cos_hemisphere(),
        1e-8,
    );
    let bic = ies_shaping(
        web_of(&f),
        p,
        ShapingOptions {
            interpolation: Interpolation::Bicubic,
            ..Default::default()
        },
    );
    // bicubic vs bilinear of a smooth function on a 5° × 15° grid: close, not equal
    close3(bic.integral_sphere(), exact, 2e-3);
    close3(bic.integral_weighted(|_| 1.0), bic.integral_sphere(), 1e-8);
    // legacy formula, a decreasing map (s < −1): everything maps to θies ≥ π
    let leg = ies_shaping(
        web_of(&f),
        ShapingParams {
            ies_angle_scale: -3.0,
            focus: 0.0,
            cone_angle_deg: 180.0,
            cone_softness: 0.0,
            ies_normalize: false,
            ..p
        },
        ShapingOptions {
            angle_scale: AngleScaleFormula::Legacy,
            ..Default::default()
        },
    );
    // value at 180°: g(180, h) = 100 − 60 = 40 cd everywhere → 4π · 40
    close3(leg.integral_sphere(), [4.0 * PI * 40.0; 3], 1e-9);
}

#[test]
fn types_a_and_b_with_an_angle_scale() {
    let vs: Vec<f64> = (-6..=6).map(|k| 15.0 * k as f64).collect();
    let hs: Vec<f64> = (0..=6).map(|k| 15.0 * k as f64).collect();
    // constant 1 cd over the measured range = the front hemisphere (θ ≤ 90°)
    let one = |pt| file(pt, vs.clone(), hs.clone(), vec![1.0; vs.len() * hs.len()]);
    // a profile with kinks on every grid line
    let bumpy = |pt| {
        let cd = hs
            .iter()
            .flat_map(|&h| {
                vs.iter()
                    .map(move |&v| 10.0 + (v * 0.37 + h * 0.11).sin().abs() * 20.0 + v.abs() * 0.1)
            })
            .collect();
        file(pt, vs.clone(), hs.clone(), cd)
    };
    for pt in [PhotometricType::A, PhotometricType::B] {
        // angleScale 0.5: θies = 2θ is in the front hemisphere for θ ≤ 45° and, wrapping
        // round, for θ ≥ 135°: 2 · 2π(1 − cos 45°)
        let s = ies_shaping(
            web_of(&one(pt)),
            ShapingParams {
                ies_angle_scale: 0.5,
                ..ShapingParams::NO_SHAPING
            },
            ShapingOptions::default(),
        );
        close3(
            s.integral_sphere(),
            [2.0 * TAU * (1.0 - 0.5f64.sqrt()); 3],
            1e-9,
        );
        // a scale that is not the identity but maps like it: the (θ, φ) path with its closed-
        // form grid crossings must agree with the native (V, H) path
        let p = ShapingParams {
            focus: 1.5,
            cone_angle_deg: 70.0,
            cone_softness: 0.4,
            ..ShapingParams::NO_SHAPING
        };
        let native = ies_shaping(web_of(&bumpy(pt)), p, ShapingOptions::default());
        let light = ies_shaping(
            web_of(&bumpy(pt)),
            ShapingParams {
                ies_angle_scale: 1.0 + 1e-13,
                ..p
            },
            ShapingOptions::default(),
        );
        let want = native.integral_sphere();
        close3(light.integral_sphere(), want, 1e-8);
        close3(
            light.integral_cos_hemisphere(),
            native.integral_cos_hemisphere(),
            1e-8,
        );
        // and the native path against the profile's exact flux with no shaping
        let plain = ies_shaping(
            web_of(&bumpy(pt)),
            ShapingParams::NO_SHAPING,
            ShapingOptions::default(),
        );
        close3(
            plain.integral_sphere(),
            [web_of(&bumpy(pt)).flux_exact(); 3],
            1e-12,
        );
    }
}
