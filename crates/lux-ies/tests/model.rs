//! Symmetry expansion, interpolation, edge rules, errors, editions and the writer's round trip.

use lux_ies::{
    Edition, HeaderLine, IesError, IesFile, Interpolation, LampGeometry, ParseOptions,
    PhotometricType, PhotometricWeb, Tilt, TiltData, Units,
};
use lux_math::Profile;
use proptest::prelude::*;
use std::f64::consts::{PI, TAU};

fn base(ptype: PhotometricType, v: Vec<f64>, h: Vec<f64>, candela: Vec<f64>) -> IesFile {
    IesFile {
        edition: Edition::Lm63_2002,
        header: vec![HeaderLine::Keyword {
            name: "TEST".into(),
            value: "unit".into(),
        }],
        tilt: Tilt::None,
        lamp_count: 1,
        lumens_per_lamp: -1.0,
        candela_multiplier: 1.0,
        photometric_type: ptype,
        units: Units::Meters,
        width: 0.0,
        length: 0.0,
        height: 0.0,
        ballast_factor: 1.0,
        third_factor: 1.0,
        input_watts: 10.0,
        vertical_angles_deg: v,
        horizontal_angles_deg: h,
        candela,
    }
}

/// A smooth test function of (γ, C) in degrees, even in C (bilateral-symmetric, smooth across the
/// 0° and 180° planes once mirrored).
fn f(v: f64, h: f64) -> f64 {
    100.0
        + 50.0 * (v.to_radians()).cos()
        + 20.0 * (h.to_radians()).cos()
        + 7.0 * (2.0 * h.to_radians()).cos()
}

/// A candela function of (vertical, horizontal) degrees.
type Profile2d = dyn Fn(f64, f64) -> f64;

fn grid(vs: &[f64], hs: &[f64], g: impl Fn(f64, f64) -> f64) -> Vec<f64> {
    let g = &g;
    hs.iter()
        .flat_map(|&h| vs.iter().map(move |&v| g(v, h)))
        .collect()
}

fn web(file: &IesFile) -> PhotometricWeb {
    PhotometricWeb::new(file, Profile::Spec).unwrap()
}

const V: [f64; 7] = [0.0, 10.0, 25.0, 45.0, 90.0, 135.0, 180.0];

#[test]
fn symmetric_files_equal_their_explicit_full_versions() {
    // quadrant-symmetric function: depends on |cos C| pattern via cos(2C)
    let q = |v: f64, h: f64| 10.0 + v * 0.1 + 3.0 * (2.0 * h.to_radians()).cos();
    // bilateral (0-180 plane mirror): even in C
    let b = |v: f64, h: f64| 10.0 + v * 0.1 + 3.0 * h.to_radians().cos();
    // bilateral about 90-270: even under C -> 180 - C
    let b90 = |v: f64, h: f64| 10.0 + v * 0.1 + 3.0 * h.to_radians().sin();
    let full: Vec<f64> = (0..=24).map(|k| 15.0 * k as f64).collect();
    let cases: [(Vec<f64>, &Profile2d); 4] = [
        ((0..=6).map(|k| 15.0 * k as f64).collect(), &q),
        ((0..=12).map(|k| 15.0 * k as f64).collect(), &b),
        ((6..=18).map(|k| 15.0 * k as f64).collect(), &b90),
        (vec![0.0], &|v: f64, _h: f64| 10.0 + v * 0.1),
    ];
    for (hs, g) in cases {
        let sym = web(&base(
            PhotometricType::C,
            V.to_vec(),
            hs.clone(),
            grid(&V, &hs, g),
        ));
        let explicit = web(&base(
            PhotometricType::C,
            V.to_vec(),
            full.clone(),
            grid(&V, &full, g),
        ));
        for i in 0..=36 {
            for j in 0..=72 {
                let (t, p) = (i as f64 * 5f64.to_radians(), j as f64 * 5f64.to_radians());
                let (a, e) = (sym.intensity(t, p), explicit.intensity(t, p));
                assert!(
                    (a - e).abs() <= 1e-9 * e.abs().max(1.0),
                    "{hs:?} θ{i} φ{j}: {a} vs {e}"
                );
            }
        }
        assert!((sym.flux_exact() - explicit.flux_exact()).abs() < 1e-9 * explicit.flux_exact());
        assert!(
            (sym.flux_midpoint() - explicit.flux_midpoint()).abs()
                < 1e-9 * explicit.flux_midpoint()
        );
    }
}

#[test]
fn bilateral_90_270_without_a_180_plane_closes_the_circle() {
    // planes 90, 150, 210, 270: the mirror plane 180 lies between two tabulated planes. The
    // mirrored distribution is f(180 − C) outside 90..270; its bilinear interpolant equals that
    // of the explicit full file below, whose 0/180/360 planes hold the midpoint of the 150 and
    // 210 planes and whose 30/330 planes are the mirror images of 150/210.
    let val = |v: f64, h: f64| 10.0 + v * 0.1 + h * 0.05;
    let hs = [90.0, 150.0, 210.0, 270.0];
    let sym = web(&base(
        PhotometricType::C,
        V.to_vec(),
        hs.to_vec(),
        grid(&V, &hs, val),
    ));
    let mid = |v: f64| 0.5 * (val(v, 150.0) + val(v, 210.0));
    let full = [0.0, 30.0, 90.0, 150.0, 180.0, 210.0, 270.0, 330.0, 360.0];
    let explicit = web(&base(
        PhotometricType::C,
        V.to_vec(),
        full.to_vec(),
        grid(&V, &full, |v, h| match h as i32 {
            0 | 180 | 360 => mid(v),
            30 => val(v, 150.0),
            330 => val(v, 210.0),
            _ => val(v, h),
        }),
    ));
    for i in 0..=36 {
        for j in 0..=72 {
            let (t, p) = (i as f64 * 5f64.to_radians(), j as f64 * 5f64.to_radians());
            let (a, e) = (sym.intensity(t, p), explicit.intensity(t, p));
            assert!((a - e).abs() <= 1e-9 * e, "θ{i} φ{j}: {a} vs {e}");
        }
    }
    // φ = 10°: mirror of 170°, 1/3 of the way from the 150 plane to the 210 plane
    let want = (2.0 * val(45.0, 150.0) + val(45.0, 210.0)) / 3.0;
    let got = sym.intensity(45f64.to_radians(), 10f64.to_radians());
    assert!((got - want).abs() < 1e-12, "{got} vs {want}");
    assert!((sym.flux_exact() - explicit.flux_exact()).abs() < 1e-9 * explicit.flux_exact());
}

#[test]
fn type_b_mirror_equals_explicit_and_integrates_the_hemisphere() {
    let vs: Vec<f64> = (-6..=6).map(|k| 15.0 * k as f64).collect();
    let half: Vec<f64> = (0..=6).map(|k| 15.0 * k as f64).collect();
    let full: Vec<f64> = (-6..=6).map(|k| 15.0 * k as f64).collect();
    let g = |v: f64, h: f64| 5.0 + v.to_radians().cos() + h.to_radians().cos();
    let a = web(&base(
        PhotometricType::B,
        vs.clone(),
        half.clone(),
        grid(&vs, &half, g),
    ));
    let b = web(&base(
        PhotometricType::B,
        vs.clone(),
        full.clone(),
        grid(&vs, &full, g),
    ));
    for i in 0..40 {
        for j in 0..80 {
            let (t, p) = (i as f64 * 0.08, j as f64 * 0.08);
            assert!((a.intensity(t, p) - b.intensity(t, p)).abs() < 1e-9);
        }
    }
    // constant 1 cd over H, V ∈ [-90, 90] is the front hemisphere: flux 2π, exactly.
    let one = web(&base(
        PhotometricType::B,
        vs.clone(),
        full.clone(),
        vec![1.0; vs.len() * full.len()],
    ));
    assert!((one.flux_exact() - TAU).abs() < 1e-12);
    // H = 0, V = 0 is the light axis (θ = 0); V = 90° is light +Y (type B) or +X (type A).
    let mut file = base(
        PhotometricType::B,
        vs.clone(),
        full.clone(),
        grid(&vs, &full, |v, h| {
            1.0 + v.max(0.0) + 1000.0 * (h == 0.0 && v == 0.0) as u8 as f64
        }),
    );
    let w = web(&file);
    assert_eq!(w.intensity(0.0, 0.0), 1001.0);
    let (t, p) = lux_math::light_polar(glam::DVec3::Y).unwrap();
    assert!((w.intensity(t, p) - 91.0).abs() < 1e-9);
    file.photometric_type = PhotometricType::A;
    let w = web(&file);
    let (t, p) = lux_math::light_polar(glam::DVec3::X).unwrap();
    assert!((w.intensity(t, p) - 91.0).abs() < 1e-9);
    // behind the light (+Z) is outside the measured range
    assert_eq!(w.intensity(PI * 0.999, 0.3), 0.0);
}

#[test]
fn phi_orientation_follows_the_spec() {
    // a plane-dependent profile: C = 90 bright. φ = 90° is light −Y.
    let hs = [0.0, 90.0, 180.0, 270.0, 360.0];
    let w = web(&base(
        PhotometricType::C,
        V.to_vec(),
        hs.to_vec(),
        grid(&V, &hs, |_, h| if h == 90.0 { 10.0 } else { 1.0 }),
    ));
    let (t, p) = lux_math::light_polar(glam::DVec3::new(0.0, -1.0, -1.0)).unwrap();
    assert!((w.intensity(t, p) - 10.0).abs() < 1e-12);
    let (t, p) = lux_math::light_polar(glam::DVec3::new(0.0, 1.0, -1.0)).unwrap();
    assert!((w.intensity(t, p) - 1.0).abs() < 1e-12);
}

#[test]
fn edge_rules() {
    let vs = [0.0, 30.0, 50.0];
    let file = base(
        PhotometricType::C,
        vs.to_vec(),
        vec![0.0],
        vec![4.0, 3.0, 2.0],
    );
    let w = web(&file);
    assert_eq!(w.intensity(-1e-9, 0.0), 0.0);
    assert_eq!(w.intensity(f64::NAN, 0.0), 0.0);
    assert_eq!(w.intensity(0.0, 0.0), 4.0);
    assert_eq!(w.intensity(50f64.to_radians(), 0.0), 2.0);
    assert_eq!(w.intensity(60f64.to_radians(), 0.0), 0.0);
    // θ ≥ π gives the last vertical angle's value even though it is 50°
    assert_eq!(w.intensity(PI, 0.0), 2.0);
    assert_eq!(w.intensity(4.0, 0.0), 2.0);
    // profile starting at 130°: below is 0
    let file = base(
        PhotometricType::C,
        vec![130.0, 180.0],
        vec![0.0],
        vec![1.0, 3.0],
    );
    let w = web(&file);
    assert_eq!(w.intensity(1.0, 0.0), 0.0);
    assert_eq!(w.intensity(155f64.to_radians(), 2.0), 2.0);
    // φ is periodic
    assert_eq!(w.intensity(155f64.to_radians(), 2.0 + 3.0 * TAU), 2.0);
    assert_eq!(w.intensity(155f64.to_radians(), f64::INFINITY), 0.0);
}

#[test]
fn candela_scale_and_2019_generation_type() {
    let mut file = base(
        PhotometricType::C,
        vec![0.0, 90.0],
        vec![0.0],
        vec![10.0, 10.0],
    );
    file.candela_multiplier = 2.0;
    file.ballast_factor = 0.5;
    file.third_factor = 0.9;
    // up to 2002 the third factor (ballast-lamp factor) multiplies
    assert_eq!(file.candela_scale(Profile::Spec), 0.9);
    assert_eq!(web(&file).intensity(0.0, 0.0), 9.0);
    // in 2019 it is a code (spec) — the reference multiplies by it
    file.edition = Edition::Lm63_2019;
    file.third_factor = 1.10001;
    assert_eq!(file.candela_scale(Profile::Spec), 1.0);
    assert_eq!(file.candela_scale(Profile::HdEmbree), 1.10001);
    assert_eq!(file.file_generation_type(), Some(1.10001));
    let s = PhotometricWeb::new(&file, Profile::Spec).unwrap();
    let h = PhotometricWeb::new(&file, Profile::HdEmbree).unwrap();
    assert_eq!(s.intensity(0.0, 0.0), 10.0);
    assert!((h.intensity(0.0, 0.0) - 11.0001).abs() < 1e-12);
    // ies:normalize is immune to the factor: I / flux is the same for both scales, whichever
    // rule integrates the flux (each web's mean_intensity uses its own profile's rule)
    for flux in [PhotometricWeb::flux_exact, PhotometricWeb::flux_midpoint] {
        let rs = s.intensity(0.3, 0.0) / flux(&s);
        let rh = h.intensity(0.3, 0.0) / flux(&h);
        assert!((rs - rh).abs() < 1e-12);
    }
    assert_eq!(s.flux(), s.flux_exact());
    assert_eq!(h.flux(), h.flux_midpoint());
}

#[test]
fn editions_1986_and_2019_and_tilt_files() {
    let body = "1 1000 1 3 1 1 1 -0.5 -0.5 0\n1 1.00001 20\n0 45 90\n0\n100 60 0";
    // 1986: no version line, free text before TILT=
    let t86 = format!("Acme lighting\nsome photometric report\nTILT=NONE\n{body}");
    let f = IesFile::parse(&t86).unwrap();
    assert_eq!(f.edition, Edition::Lm63_1986);
    assert_eq!(
        f.header,
        vec![
            HeaderLine::Text("Acme lighting".into()),
            HeaderLine::Text("some photometric report".into())
        ]
    );
    assert_eq!(
        f.luminous_opening(),
        lux_ies::LuminousOpening::Circle { diameter: 0.5 }
    );
    // 2019 with CRLF, commas and no final newline
    let t19 = format!(
        "IES:LM-63-2019\r\n[TEST] x\r\n[TESTLAB] y\r\nTILT=NONE\r\n{}",
        body.replace(' ', ",").replace('\n', "\r\n")
    );
    let p = IesFile::parse_with(&t19, &ParseOptions::default()).unwrap();
    assert_eq!(p.file.edition, Edition::Lm63_2019);
    assert_eq!(p.file.file_generation_type(), Some(1.00001));
    assert!(
        p.warnings.iter().any(
            |w| matches!(w, lux_ies::Warning::MissingKeyword { name, .. } if name == "LUMCAT")
        )
    );
    // TILT=<file>: unresolved is a warning unless required; resolved through the callback
    let tf = format!("IESNA:LM-63-2002\nTILT=lamp.tlt\n{body}");
    let p = IesFile::parse_with(&tf, &ParseOptions::default()).unwrap();
    assert_eq!(
        p.file.tilt,
        Tilt::File {
            name: "lamp.tlt".into(),
            data: None
        }
    );
    let strict = ParseOptions {
        require_tilt_file: true,
        ..Default::default()
    };
    assert!(
        matches!(IesFile::parse_with(&tf, &strict), Err(IesError::TiltFileMissing { at, .. }) if at.line == 2)
    );
    let resolver =
        |name: &str| (name == "lamp.tlt").then(|| "2\n3\n0 90 180\n1 .5 1\n".to_string());
    let opts = ParseOptions {
        tilt_resolver: Some(&resolver),
        require_tilt_file: true,
        ..Default::default()
    };
    let p = IesFile::parse_with(&tf, &opts).unwrap();
    let d = p.file.tilt.data().unwrap();
    assert_eq!(d.geometry, LampGeometry::HorizontalParallel);
    assert_eq!(p.file.tilt.tilt_factor(45.0), 0.75);
    let bad = |_: &str| Some("2\n3\n0 90 x\n".to_string());
    let opts = ParseOptions {
        tilt_resolver: Some(&bad),
        ..Default::default()
    };
    match IesFile::parse_with(&tf, &opts).unwrap_err() {
        IesError::TiltFile { inner, .. } => assert_eq!((inner.line(), inner.column()), (3, 6)),
        e => panic!("{e}"),
    }
}

fn err(text: &str) -> IesError {
    IesFile::parse(text).unwrap_err()
}

#[test]
fn precise_errors() {
    let head = "IESNA:LM-63-2002\nTILT=NONE\n";
    // absurd count: refused before allocating
    let e = err(&format!("{head}1 -1 1 99999999999 1 1 1 0 0 0\n1 1 1\n"));
    assert!(
        matches!(
            e,
            IesError::AbsurdCount {
                field: "number of vertical angles",
                ..
            }
        ),
        "{e}"
    );
    let e = err(&format!("{head}1 -1 1 50000 50000 1 1 0 0 0\n1 1 1\n"));
    assert!(
        matches!(
            e,
            IesError::AbsurdCount {
                field: "number of candela values",
                ..
            }
        ),
        "{e}"
    );
    // non-monotonic vertical angles, position of the offending angle
    let e = err(&format!(
        "{head}1 -1 1 3 1 1 1 0 0 0\n1 1 1\n0 50 40\n0\n1 1 1\n"
    ));
    assert!(
        matches!(e, IesError::NonMonotonic { field: "vertical", at, .. } if at.line == 5 && at.column == 6),
        "{e}"
    );
    // NaN / inf / negative candela
    let e = err(&format!(
        "{head}1 -1 1 2 1 1 1 0 0 0\n1 1 1\n0 90\n0\n1 NaN\n"
    ));
    assert!(
        matches!(e, IesError::NotANumber { ref found, .. } if found == "NaN"),
        "{e}"
    );
    let e = err(&format!(
        "{head}1 -1 1 2 1 1 1 0 0 0\n1 1 1\n0 90\n0\n1 1e999\n"
    ));
    assert!(matches!(e, IesError::InvalidValue { .. }), "{e}");
    let e = err(&format!(
        "{head}1 -1 1 2 1 1 1 0 0 0\n1 1 1\n0 90\n0\n1 -2\n"
    ));
    assert!(
        matches!(e, IesError::InvalidValue { field: "candela value", at, .. } if at.line == 7 && at.column == 3),
        "{e}"
    );
    // illegal type C vertical range
    let e = err(&format!(
        "{head}1 -1 1 2 1 1 1 0 0 0\n1 1 1\n-10 90\n0\n1 1\n"
    ));
    assert!(
        matches!(
            e,
            IesError::IllegalAngleRange {
                field: "vertical",
                ..
            }
        ),
        "{e}"
    );
    let e = err(&format!(
        "{head}1 -1 1 2 2 1 1 0 0 0\n1 1 1\n0 90\n0 45\n1 1 1 1\n"
    ));
    assert!(
        matches!(
            e,
            IesError::IllegalAngleRange {
                field: "horizontal",
                ..
            }
        ),
        "{e}"
    );
    // unknown photometric type, non-integral count
    let e = err(&format!("{head}1 -1 1 2 1 4 1 0 0 0\n"));
    assert!(
        matches!(
            e,
            IesError::InvalidValue {
                field: "photometric type",
                ..
            }
        ),
        "{e}"
    );
    let e = err(&format!("{head}1 -1 1 2.5 1 1 1 0 0 0\n"));
    assert!(matches!(e, IesError::InvalidValue { .. }), "{e}");
    // detached sign, missing TILT, truncation
    let e = err(&format!("{head}1 -1 + 1 2 1 1 1 0 0 0\n"));
    assert!(
        matches!(e, IesError::NotANumber { ref found, .. } if found == "+"),
        "{e}"
    );
    assert!(matches!(
        err("IESNA91\n[TEST] a\n"),
        IesError::MissingTilt { .. }
    ));
    let e = err(&format!("{head}1 -1 1 2 1 1 1 0 0 0\n1 1 1\n0 90\n0\n1"));
    assert!(
        matches!(e, IesError::Truncated { ref expected, .. } if expected.starts_with("candela value 2 of 2")),
        "{e}"
    );
    assert_eq!(e.to_string().split(':').next(), Some("7"));
    // negative multiplier
    let e = err(&format!("{head}1 -1 -1 2 1 1 1 0 0 0\n"));
    assert!(
        matches!(
            e,
            IesError::InvalidValue {
                field: "candela multiplier",
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn bilinear_lookup_matches_exact_bisection_evaluation() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/luxtest/bega_omni001_1238lm.ies"
    ))
    .unwrap();
    let file = IesFile::parse(&text).unwrap();
    let w = web(&file);
    let (v, h) = (w.vertical_angles(), w.horizontal_angles());
    let nv = v.len();
    let find = |a: &[f64], x: f64| {
        a.partition_point(|&q| q <= x)
            .saturating_sub(1)
            .min(a.len() - 2)
    };
    let mut rng = 0x2545F4914F6CDD1Du64;
    let mut next = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..20000 {
        let (t, p) = (next() * PI, next() * TAU);
        let (i, j) = (find(v, t), find(h, p));
        let tv = (t - v[i]) / (v[i + 1] - v[i]);
        let th = (p - h[j]) / (h[j + 1] - h[j]);
        let c = |hh: usize, vv: usize| w.values()[hh * nv + vv];
        let a = (1.0 - tv) * c(j, i) + tv * c(j, i + 1);
        let b = (1.0 - tv) * c(j + 1, i) + tv * c(j + 1, i + 1);
        let exact = (1.0 - th) * a + th * b;
        let got = w.intensity(t, p);
        assert!(
            (got - exact).abs() <= 1e-6 * exact.abs().max(1e-300) || (got - exact).abs() < 1e-9,
            "{t} {p}: {got} vs {exact}"
        );
    }
}

#[test]
fn interpolation_is_continuous_and_bicubic_interpolates_the_nodes() {
    let hs: Vec<f64> = (0..=12).map(|k| 15.0 * k as f64).collect();
    let file = base(PhotometricType::C, V.to_vec(), hs.clone(), grid(&V, &hs, f));
    let w = web(&file);
    for interp in [Interpolation::Bilinear, Interpolation::Bicubic] {
        // nodes are reproduced
        for &vv in &V {
            for &hh in &hs {
                let got = w.intensity_with(vv.to_radians(), hh.to_radians(), interp);
                assert!((got - f(vv, hh)).abs() < 1e-9, "{interp:?} {vv} {hh}");
            }
        }
        // continuity across every node line, including the 0/360 seam
        let eps = 1e-7;
        for &vv in &V[1..V.len() - 1] {
            for k in 0..50 {
                let p = k as f64 * 0.125;
                let a = w.intensity_with(vv.to_radians() - eps, p, interp);
                let b = w.intensity_with(vv.to_radians() + eps, p, interp);
                assert!((a - b).abs() < 1e-3, "{interp:?} v {vv} φ {p}: {a} {b}");
            }
        }
        for k in 1..36 {
            let t = k as f64 * 5f64.to_radians();
            let a = w.intensity_with(t, TAU - eps, interp);
            let b = w.intensity_with(t, eps, interp);
            assert!((a - b).abs() < 1e-3, "{interp:?} seam θ {t}: {a} {b}");
        }
    }
    // on a uniform 10° x 15° grid, bicubic (O(h^3..4)) approximates a smooth function much
    // better than bilinear (O(h^2)) between nodes
    let vs: Vec<f64> = (0..=18).map(|k| 10.0 * k as f64).collect();
    let w = web(&base(
        PhotometricType::C,
        vs.clone(),
        hs.clone(),
        grid(&vs, &hs, f),
    ));
    let (mut e1, mut e3) = (0.0f64, 0.0f64);
    for i in 0..90 {
        for j in 0..90 {
            let (vv, hh) = (i as f64 * 2.0 + 0.7, j as f64 * 4.0 + 1.3);
            let truth = f(vv, hh);
            e1 = e1.max((w.intensity(vv.to_radians(), hh.to_radians()) - truth).abs());
            e3 = e3.max(
                (w.intensity_with(vv.to_radians(), hh.to_radians(), Interpolation::Bicubic)
                    - truth)
                    .abs(),
            );
        }
    }
    assert!(e3 < 0.2 * e1, "bicubic {e3} vs bilinear {e1}");
}

#[test]
fn max_and_beam_field_angles() {
    // Gaussian-like spot, σ = 10°: 50 % at γ = σ·sqrt(2 ln 2) = 11.774°, 10 % at σ·sqrt(2 ln 10) = 21.460°
    let vs: Vec<f64> = (0..=180).map(|k| k as f64 * 0.5).collect();
    let g = |v: f64, _h: f64| 1000.0 * (-(v * v) / (2.0 * 100.0)).exp();
    let file = base(
        PhotometricType::C,
        vs.clone(),
        vec![0.0],
        grid(&vs, &[0.0], g),
    );
    let w = web(&file);
    assert_eq!(w.max_candela(), 1000.0);
    assert_eq!(w.max_direction(), (0.0, 0.0));
    let beam = w.beam_angles();
    let field = w.field_angles();
    let b = 2.0 * 10.0 * (2.0 * 2f64.ln()).sqrt();
    let fl = 2.0 * 10.0 * (2.0 * 10f64.ln()).sqrt();
    // piecewise-linear interpolation of the Gaussian on a 0.5° grid: within 0.01°; the angles
    // are radians
    let deg = |a: Option<f64>| a.unwrap().to_degrees();
    assert!((deg(beam.c0_c180) - b).abs() < 0.01, "{beam:?} {b}");
    assert!((deg(beam.c90_c270) - b).abs() < 0.01);
    assert!((deg(field.c0_c180) - fl).abs() < 0.01, "{field:?} {fl}");
    // a uniform sphere never drops: no beam angle
    let file = base(
        PhotometricType::C,
        vec![0.0, 180.0],
        vec![0.0],
        vec![1.0, 1.0],
    );
    assert_eq!(web(&file).beam_angles().c0_c180, None);
}

fn arb_file() -> impl Strategy<Value = IesFile> {
    let ptype = prop_oneof![
        Just(PhotometricType::C),
        Just(PhotometricType::B),
        Just(PhotometricType::A)
    ];
    (
        ptype,
        2usize..8,
        1usize..6,
        any::<bool>(),
        any::<bool>(),
        0u8..3,
    )
        .prop_flat_map(|(pt, nv, nh, e19, tilt, hmode)| {
            let (vlo, vhi) = if pt == PhotometricType::C {
                (0.0, 180.0)
            } else {
                (-90.0, 90.0)
            };
            let hs: Vec<f64> = if nh == 1 {
                vec![0.0]
            } else if pt == PhotometricType::C {
                let last = [90.0, 180.0, 360.0][hmode as usize];
                (0..nh).map(|k| last * k as f64 / (nh - 1) as f64).collect()
            } else {
                let first = if hmode == 0 { -90.0 } else { 0.0 };
                (0..nh)
                    .map(|k| first + (90.0 - first) * k as f64 / (nh - 1) as f64)
                    .collect()
            };
            let vs = proptest::collection::vec(0.001f64..1.0, nv).prop_map(move |gaps| {
                let total: f64 = gaps.iter().sum();
                let mut acc = 0.0;
                let mut out = vec![vlo];
                for g in &gaps[..gaps.len() - 1] {
                    acc += g;
                    out.push(vlo + (vhi - vlo) * acc / total);
                }
                out
            });
            let cd = proptest::collection::vec(0.0f64..1e5, nv * nh);
            // `[MORE]` is the continuation marker, not a keyword name.
            let name = "[A-Z_]{1,8}".prop_filter("MORE is a continuation", |n| n != "MORE");
            let kw =
                proptest::collection::vec((name, "[a-zA-Z0-9 .,:-]{0,20}", "[a-z ]{0,10}"), 0..4);
            let nums = (
                -2.0f64..5.0,
                0.01f64..10.0,
                -3.0f64..3.0,
                0.1f64..2.0,
                0.5f64..1.5,
                0.0f64..500.0,
            );
            (Just(pt), vs, Just(hs), cd, kw, nums, Just(e19), Just(tilt))
        })
        .prop_map(
            |(pt, vs, hs, cd, kw, (lm, mult, w, bf, third, watts), e19, tilt)| {
                let mut f = base(pt, vs, hs, cd);
                f.edition = if e19 {
                    Edition::Lm63_2019
                } else {
                    Edition::Lm63_2002
                };
                f.header = kw
                    .into_iter()
                    .map(|(name, value, more)| {
                        let value = value.trim().to_string();
                        let more = more.trim().to_string();
                        let value = if more.is_empty() {
                            value
                        } else {
                            format!("{value}\n{more}")
                        };
                        HeaderLine::Keyword { name, value }
                    })
                    .collect();
                f.header.push(HeaderLine::Text("free text line".into()));
                f.lumens_per_lamp = lm;
                f.candela_multiplier = mult;
                f.width = w;
                f.length = -w;
                f.ballast_factor = bf;
                f.third_factor = third;
                f.input_watts = watts;
                if tilt {
                    f.tilt = Tilt::Include(TiltData {
                        geometry: LampGeometry::HorizontalPerpendicular,
                        angles_deg: vec![0.0, 45.5, 90.0],
                        factors: vec![1.0, 0.7, 0.123456789],
                    });
                }
                f
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    #[test]
    fn write_then_parse_is_identity(file in arb_file()) {
        prop_assert!(file.validate().is_ok());
        let text = file.write(file.edition);
        let back = IesFile::parse(&text).unwrap();
        prop_assert_eq!(back, file);
    }

    #[test]
    fn intensity_is_finite_non_negative_and_bounded(file in arb_file(), t in -1.0f64..4.0, p in -10.0f64..10.0) {
        let w = PhotometricWeb::new(&file, Profile::Spec).unwrap();
        let i = w.intensity(t, p);
        prop_assert!(i.is_finite() && i >= 0.0 && i <= w.max_candela() * (1.0 + 1e-12));
        let c = w.intensity_with(t, p, Interpolation::Bicubic);
        prop_assert!(c.is_finite() && c >= 0.0);
        prop_assert!(w.flux_exact() >= 0.0 && w.flux_midpoint() >= 0.0);
    }
}
