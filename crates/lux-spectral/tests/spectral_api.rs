//! LTESpectralAPI: presets, units, interpolation, Sellmeier, and bad input.

mod common;

use common::rel;
use glam::DVec3;
use lux_spectral::*;
use proptest::prelude::*;

fn emission(values: Vec<[f32; 2]>, preset: Option<Illuminant>) -> SpectralInputs {
    SpectralInputs {
        emission: Some(SpectralAttribute {
            values,
            illuminant_preset: preset,
            ..Default::default()
        }),
        ..Default::default()
    }
}

#[test]
fn sellmeier_bk7() {
    // Schott N-BK7: n_d (587.56 nm) = 1.5168, n_F (486.13) = 1.5224, n_C (656.27) = 1.5143.
    // Schott N-BK7 Sellmeier coefficients (C in µm²), stored as USD float2 (f32).
    let published: [(f64, f64); 3] = [
        (1.03961212, 6.00069867e-3),
        (0.231792344, 2.00179144e-2),
        (1.01046945, 1.03560653e2),
    ];
    let pairs: Vec<[f32; 2]> = published
        .iter()
        .map(|&(b, c)| [b as f32, c as f32])
        .collect();
    let inputs = SpectralInputs {
        ior: Some(IorAttribute {
            values: pairs,
            interpolation: IorInterpolation::Sellmeier,
            ..Default::default()
        }),
        ..Default::default()
    };
    let ior = inputs.ior().unwrap().unwrap();
    for (l, n) in [(587.56, 1.5168), (486.13, 1.5224), (656.27, 1.5143)] {
        assert!(
            (ior.eval(l).unwrap() - n).abs() < 5e-5,
            "{l}: {}",
            ior.eval(l).unwrap()
        );
    }
    assert!((Sellmeier::BK7.ior(587.6).unwrap() - 1.5168).abs() < 5e-5);
    // At the UV pole λ² = C₁ (λ ≈ 77.5 nm) n² is not finite: typed error, no panic.
    let pole = (6.000_698_67e-3_f64).sqrt() * 1000.0;
    assert!(matches!(
        Sellmeier::BK7.ior(pole),
        Err(SpectralError::SellmeierDomain { .. })
    ));
    assert!(Sellmeier::from_pairs::<f64>(&[]).is_err());
    assert!(Sellmeier::from_pairs(&[[1.0, 0.0]; 4]).is_err());
    assert!(Sellmeier::from_pairs(&[[f32::NAN, 0.0]]).is_err());
}

#[test]
fn ior_fallbacks_and_tables() {
    let scalar = SpectralInputs {
        scalar_ior: Some(1.33),
        ..Default::default()
    };
    assert_eq!(scalar.ior().unwrap(), Some(Ior::Constant(1.33)));
    let table = SpectralInputs {
        ior: Some(IorAttribute {
            values: vec![[450.0, 1.52], [550.0, 1.50], [650.0, 1.48]],
            ..Default::default()
        }),
        ..Default::default()
    };
    let ior = table.ior().unwrap().unwrap();
    assert!((ior.eval(500.0).unwrap() - 1.51).abs() < 1e-6);
    assert!((ior.eval(300.0).unwrap() - 1.52).abs() < 1e-6); // end values hold
    assert!((ior.eval(900.0).unwrap() - 1.48).abs() < 1e-6);
    let bad = SpectralInputs {
        scalar_ior: Some(f64::NAN),
        ..Default::default()
    };
    assert!(bad.ior().is_err());
}

#[test]
fn presets_and_explicit_values() {
    // Empty + preset → the CIE table.
    let s = emission(vec![], Some(Illuminant::D50))
        .emission_spectrum()
        .unwrap()
        .unwrap();
    assert_eq!(s, Illuminant::D50.spectrum());
    // Explicit values win over the preset.
    let s = emission(vec![[400.0, 1.0], [700.0, 2.0]], Some(Illuminant::D50))
        .emission_spectrum()
        .unwrap()
        .unwrap();
    assert_eq!(s.wavelengths(), &[400.0, 700.0]);
    // Empty without preset: typed error naming the attribute.
    let err = emission(vec![], None).emission_spectrum().unwrap_err();
    assert!(
        matches!(&err, SpectralError::EmptyWithoutPreset { attribute } if attribute == "wavelength:emission")
    );
    for t in ["a", "D65", "f11", "E"] {
        assert!(Illuminant::parse(t).is_ok());
    }
    assert!(Illuminant::parse("d55").is_err());
    // D65 emission in Rec.709 is white to the rounding of the sRGB white point (0.3127, 0.3290).
    let rgb = emission(vec![], Some(Illuminant::D65))
        .emission_rgb_per_nit(ColorSpace::Rec709)
        .unwrap()
        .unwrap();
    assert!((rgb - DVec3::ONE).abs().max_element() < 2e-3, "{rgb}");
}

#[test]
fn micrometre_units_rescale_wavelengths_and_densities() {
    let nm = emission(vec![[400.0, 2.0], [500.0, 3.0], [700.0, 1.0]], None);
    let mut um = emission(vec![[0.4, 2000.0], [0.5, 3000.0], [0.7, 1000.0]], None);
    um.unit_for_wavelength = WavelengthUnit::Micrometers;
    let a = nm.emission_spectrum().unwrap().unwrap();
    let b = um.emission_spectrum().unwrap().unwrap();
    // (f32 0.4 µm is 400.000006 nm, so probe inside the range.)
    for l in [410.0, 450.0, 612.0] {
        assert!(
            rel(b.eval(l), a.eval(l)) < 1e-6,
            "{l}: {} vs {}",
            b.eval(l),
            a.eval(l)
        );
    }
    // Per-attribute override beats the stage unit.
    um.unit_for_wavelength = WavelengthUnit::Nanometers;
    um.emission.as_mut().unwrap().unit_for_wavelength = Some(WavelengthUnit::Micrometers);
    assert_eq!(
        um.emission_spectrum().unwrap().unwrap().bounds().1,
        b.bounds().1
    );
    // Stage unit applies when the attribute has none.
    let mut stage = emission(vec![[0.4, 1.0], [0.7, 1.0]], None);
    stage.unit_for_wavelength = WavelengthUnit::parse("micrometers").unwrap();
    assert!(
        rel(
            stage.emission_spectrum().unwrap().unwrap().bounds().1,
            700.0
        ) < 1e-6
    );
    assert!(WavelengthUnit::parse("furlongs").is_err());
}

#[test]
fn bad_spectra_give_typed_errors() {
    let e = |v: Vec<[f32; 2]>| emission(v, None).emission_spectrum().unwrap_err();
    assert!(matches!(
        e(vec![[500.0, 1.0], [400.0, 1.0]]),
        SpectralError::Spectrum {
            source: SpectrumError::NotIncreasing { index: 1, .. },
            ..
        }
    ));
    assert!(matches!(
        e(vec![[400.0, 1.0], [400.0, 1.0]]),
        SpectralError::Spectrum {
            source: SpectrumError::NotIncreasing { .. },
            ..
        }
    ));
    assert!(matches!(
        e(vec![[400.0, f32::NAN], [500.0, 1.0]]),
        SpectralError::Spectrum {
            source: SpectrumError::NonFiniteValue { index: 0, .. },
            ..
        }
    ));
    assert!(matches!(
        e(vec![[f32::NAN, 1.0], [500.0, 1.0]]),
        SpectralError::Spectrum {
            source: SpectrumError::BadWavelength { index: 0, .. },
            ..
        }
    ));
    assert!(matches!(
        e(vec![[-1.0, 1.0], [500.0, 1.0]]),
        SpectralError::Spectrum {
            source: SpectrumError::BadWavelength { .. },
            ..
        }
    ));
    assert!(matches!(
        e(vec![[500.0, 1.0]]),
        SpectralError::Spectrum {
            source: SpectrumError::TooFewSamples { count: 1 },
            ..
        }
    ));
    assert!(matches!(
        e(vec![[400.0, -1.0], [500.0, 1.0]]),
        SpectralError::Spectrum {
            source: SpectrumError::ValueTooSmall { .. },
            ..
        }
    ));
    let msg = e(vec![[500.0, 1.0], [400.0, 1.0]]).to_string();
    assert!(
        msg.contains("wavelength:emission") && msg.contains("pair 1"),
        "{msg}"
    );
    let refl = SpectralInputs {
        reflectance: Some(SpectralAttribute {
            values: vec![[400.0, 0.5], [500.0, 1.5]],
            ..Default::default()
        }),
        ..Default::default()
    };
    assert!(matches!(
        refl.reflectance_spectrum(),
        Err(SpectralError::Spectrum {
            source: SpectrumError::ValueTooLarge { index: 1, .. },
            ..
        })
    ));
    assert!(Interpolation::parse("spline", "emissionInterpolation").is_err());
    assert!(IorInterpolation::parse("sellmeier").is_ok());
}

#[test]
fn constant_reflectance_is_grey() {
    let refl = SpectralInputs {
        reflectance: Some(SpectralAttribute {
            values: vec![[360.0, 0.5], [830.0, 0.5]],
            ..Default::default()
        }),
        ..Default::default()
    };
    let rgb = refl.reflectance_rgb(ColorSpace::Rec709).unwrap().unwrap();
    assert!(
        (rgb - DVec3::splat(0.5)).abs().max_element() < 1e-3,
        "{rgb}"
    );
}

#[test]
fn interpolation_modes_closed_forms() {
    let w = vec![400.0, 500.0, 600.0, 700.0];
    let v = vec![1.0, 3.0, 2.0, 2.0];
    let lin = SampledSpectrum::new(w.clone(), v.clone(), Interpolation::Linear).unwrap();
    assert_eq!(lin.eval(450.0), 2.0);
    assert_eq!(lin.eval(399.9), 0.0);
    assert_eq!(lin.eval(700.1), 0.0);
    assert_eq!(lin.integral(), 100.0 * (2.0 + 2.5 + 2.0));
    let held = SampledSpectrum::new(w.clone(), v.clone(), Interpolation::Held).unwrap();
    assert_eq!(held.eval(499.0), 1.0);
    assert_eq!(held.eval(500.0), 3.0);
    assert_eq!(held.eval(700.0), 2.0);
    assert_eq!(held.integral(), 100.0 * (1.0 + 3.0 + 2.0));
    let cubic = SampledSpectrum::new(w, v, Interpolation::Cubic).unwrap();
    assert_eq!(cubic.eval(500.0), 3.0);
    // Monotone: stays within [1, 3] (no overshoot past the peak at 500 nm).
    for i in 0..=300 {
        let y = cubic.eval(400.0 + i as f64);
        assert!((1.0..=3.0).contains(&y), "{i}: {y}");
    }
    // Flat segment stays flat.
    assert!((cubic.eval(650.0) - 2.0).abs() < 1e-12);
}

#[test]
fn colour_space_matrices() {
    for space in [ColorSpace::Rec709, ColorSpace::AcesCg] {
        let m = space.rgb_to_xyz_matrix();
        let white = m * DVec3::ONE;
        assert!((white.y - 1.0).abs() < 1e-12);
        assert!(
            (xy_chromaticity(white) - space.white_xy())
                .abs()
                .max_element()
                < 1e-12
        );
        assert!(
            (space.xyz_to_rgb_matrix() * m - glam::DMat3::IDENTITY)
                .abs()
                .to_cols_array()
                .iter()
                .all(|&e| e < 1e-12)
        );
    }
    // Published Rec.709 luminance weights (ITU-R BT.709): 0.2126, 0.7152, 0.0722.
    let m = ColorSpace::Rec709.rgb_to_xyz_matrix();
    assert!(
        (m.row(1) - DVec3::new(0.2126, 0.7152, 0.0722))
            .abs()
            .max_element()
            < 5e-5
    );
    // ... and the same weights as lux-math's one luminance, to rounding of the derivation
    assert!((m.row(1) - lux_math::REC709_LUMINANCE).abs().max_element() < 1e-15);
    let c = DVec3::new(0.3, 1.7, 0.05);
    assert!((ColorSpace::Rec709.luminance(c) - lux_math::luminance(c)).abs() < 1e-15);
    // Published AP1 → XYZ (S-2014-004): first row 0.6624542, 0.1340042, 0.1561877.
    let a = ColorSpace::AcesCg.rgb_to_xyz_matrix();
    assert!(
        (a.row(0) - DVec3::new(0.6624542, 0.1340042, 0.1561877))
            .abs()
            .max_element()
            < 1e-6
    );
    assert!(ColorSpace::parse("ACEScg").is_ok() && ColorSpace::parse("xyz").is_err());
}

/// Reference: midpoint sums of S·cmf on pieces split at the spectrum's knots and at the CMF
/// table ends (where the integrand jumps), ~`h` nm wide.
fn fine_xyz(s: &SampledSpectrum, h: f64) -> DVec3 {
    let mut fine = DVec3::ZERO;
    for seg in s.wavelengths().windows(2) {
        let (lo, hi) = (seg[0].max(CMF_MIN_NM), seg[1].min(CMF_MAX_NM));
        if lo >= hi {
            continue;
        }
        let n = ((hi - lo) / h).ceil() as usize;
        let step = (hi - lo) / n as f64;
        for i in 0..n {
            let l = lo + (i as f64 + 0.5) * step;
            fine += cmf(l) * s.eval(l) * step;
        }
    }
    fine * K_M
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// XYZ is linear in the spectrum and the exact integration equals a fine 0.01 nm Riemann
    /// sum of S·cmf for random linear spectra.
    #[test]
    fn xyz_matches_fine_quadrature(vals in proptest::collection::vec(0.0f64..10.0, 3..12), start in 350.0f64..500.0, step in 1.3f64..40.0) {
        let w: Vec<f64> = (0..vals.len()).map(|i| start + step * i as f64).collect();
        let s = SampledSpectrum::new(w.clone(), vals.clone(), Interpolation::Linear).unwrap();
        let xyz = spectrum_to_xyz(&s);
        let fine = fine_xyz(&s, 0.01);
        prop_assert!((xyz - fine).abs().max_element() <= 1e-5 * fine.max_element().max(1e-9));
        let doubled = SampledSpectrum::new(w, vals.iter().map(|v| 2.0 * v).collect(), Interpolation::Linear).unwrap();
        prop_assert!((spectrum_to_xyz(&doubled) - 2.0 * xyz).abs().max_element() <= 1e-9 * xyz.max_element().max(1e-9));
    }

    /// Cubic and held spectra integrate to the same XYZ as a fine Riemann sum.
    #[test]
    fn cubic_and_held_xyz_match_fine_quadrature(vals in proptest::collection::vec(0.0f64..10.0, 3..8), start in 380.0f64..500.0, step in 5.0f64..30.0, cubic in any::<bool>()) {
        let w: Vec<f64> = (0..vals.len()).map(|i| start + step * i as f64).collect();
        let mode = if cubic { Interpolation::Cubic } else { Interpolation::Held };
        let s = SampledSpectrum::new(w, vals, mode).unwrap();
        let xyz = spectrum_to_xyz(&s);
        let fine = fine_xyz(&s, 0.01);
        prop_assert!((xyz - fine).abs().max_element() <= 1e-5 * fine.max_element().max(1e-9), "{} vs {}", xyz, fine);
    }

    /// Arbitrary (possibly garbage) pairs never panic: either a valid spectrum or a typed error.
    #[test]
    fn arbitrary_pairs_never_panic(pairs in proptest::collection::vec((proptest::num::f32::ANY, proptest::num::f32::ANY), 0..20)) {
        let v: Vec<[f32; 2]> = pairs.iter().map(|&(a, b)| [a, b]).collect();
        if let Ok(s) = SampledSpectrum::from_pairs(&v, WavelengthUnit::Nanometers, 1.0, Interpolation::Cubic) {
            let xyz = spectrum_to_xyz(&s);
            prop_assert!(xyz.is_finite() || s.values().iter().any(|v| v.abs() > 1e300));
        }
    }
}

#[test]
fn restricted_and_cubic_integral() {
    let s = SampledSpectrum::new(
        vec![400.0, 500.0, 600.0],
        vec![0.0, 10.0, 0.0],
        Interpolation::Linear,
    )
    .unwrap();
    let r = s.restricted(450.0, 550.0).unwrap();
    assert_eq!(r.wavelengths(), &[450.0, 500.0, 550.0]);
    assert_eq!(r.values(), &[5.0, 10.0, 5.0]);
    assert_eq!(r.integral(), 750.0);
    assert!(s.restricted(700.0, 800.0).is_none());
    // Cubic integral is exact: compare with a fine midpoint sum of the Hermite curve.
    let c = SampledSpectrum::new(
        vec![400.0, 430.0, 500.0, 520.0],
        vec![1.0, 4.0, 2.0, 7.0],
        Interpolation::Cubic,
    )
    .unwrap();
    let n = 120_000;
    let h = 120.0 / n as f64;
    let fine: f64 = (0..n)
        .map(|i| c.eval(400.0 + (i as f64 + 0.5) * h) * h)
        .sum();
    assert!(rel(c.integral(), fine) < 1e-8, "{} vs {fine}", c.integral());
}

#[test]
fn acescg_has_no_chromatic_adaptation() {
    // D65 is white in Rec.709 but bluish in ACEScg (white = ACES ≈ D60); luminance stays 1.
    let d65 = emission(vec![], Some(Illuminant::D65));
    let rgb = d65
        .emission_rgb_per_nit(ColorSpace::AcesCg)
        .unwrap()
        .unwrap();
    assert!(rgb.z > 1.05 && rgb.x < 0.99, "{rgb}");
    assert!((ColorSpace::AcesCg.luminance(rgb) - 1.0).abs() < 1e-12);
}
