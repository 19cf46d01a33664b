//! Shared helpers of the integration tests: the IES corpus in `tests/data/ies`, synthetic
//! profiles, and proptest strategies for IES files.

#![allow(dead_code)]

use glam::DVec3;
use lux_ies::{Edition, HeaderLine, IesFile, PhotometricType, PhotometricWeb, Tilt, Units};
use lux_math::Profile;
use proptest::prelude::*;
use std::path::{Path, PathBuf};

pub fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/ies")
        .join(rel)
}

pub fn load(rel: &str) -> IesFile {
    let text = std::fs::read_to_string(data(rel)).unwrap();
    IesFile::parse(&text).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

pub fn web(rel: &str, profile: Profile) -> PhotometricWeb {
    PhotometricWeb::new(&load(rel), profile).unwrap()
}

/// The malformed files of the corpus (see tests/data/ies/SOURCES.md).
pub const MALFORMED: [&str; 3] = [
    "appleseed/test_iesparser_4.ies",
    "appleseed/test_iesparser_5.ies",
    "mdl-sdk/test_file_format_error.ies",
];

/// Every well-formed `.ies` file of the corpus, as `dir/name`.
pub fn corpus() -> Vec<String> {
    let mut v = Vec::new();
    for dir in [
        "appleseed",
        "lidrs",
        "luxcore",
        "luxtest",
        "mdl-sdk",
        "radiance",
    ] {
        for e in std::fs::read_dir(data(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "ies") {
                let rel = format!("{dir}/{}", p.file_name().unwrap().to_str().unwrap());
                if !MALFORMED.contains(&rel.as_str()) {
                    v.push(rel);
                }
            }
        }
    }
    v.sort();
    v
}

/// Light-space unit direction at polar angle θ off −Z and IES azimuth φ (degrees).
pub fn dir_deg(theta_deg: f64, phi_deg: f64) -> DVec3 {
    lux_math::light_direction(theta_deg.to_radians(), phi_deg.to_radians())
}

/// An absolute-photometry LM-63-2002 file with the given angles (degrees) and candela rows
/// (one row of `v.len()` values per horizontal angle).
pub fn file(ptype: PhotometricType, v: Vec<f64>, h: Vec<f64>, candela: Vec<f64>) -> IesFile {
    IesFile {
        edition: Edition::Lm63_2002,
        header: vec![HeaderLine::Keyword {
            name: "TEST".into(),
            value: "lux-shaping".into(),
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

pub fn web_of(f: &IesFile) -> PhotometricWeb {
    PhotometricWeb::new(f, Profile::Spec).unwrap()
}

/// Random valid IES files: type C (all horizontal symmetries, vertical ranges that do and do not
/// cover the sphere) and types A/B, with random candela values including zeros.
pub fn arb_file() -> impl Strategy<Value = IesFile> {
    let ptype = prop_oneof![
        6 => Just(PhotometricType::C),
        1 => Just(PhotometricType::B),
        1 => Just(PhotometricType::A)
    ];
    (ptype, 2usize..9, 1usize..7, 0u8..4, 0u8..3)
        .prop_flat_map(|(pt, nv, nh, hmode, vmode)| {
            let (vlo, vhi) = if pt == PhotometricType::C {
                [(0.0, 180.0), (0.0, 90.0), (90.0, 180.0)][vmode as usize]
            } else {
                (-90.0, 90.0)
            };
            let hs: Vec<f64> = if nh == 1 {
                vec![0.0]
            } else if pt == PhotometricType::C {
                if hmode == 3 {
                    (0..nh)
                        .map(|k| 90.0 + 180.0 * k as f64 / (nh - 1) as f64)
                        .collect()
                } else {
                    let last = [90.0, 180.0, 360.0][hmode as usize];
                    (0..nh).map(|k| last * k as f64 / (nh - 1) as f64).collect()
                }
            } else {
                let first = if hmode == 0 { -90.0 } else { 0.0 };
                (0..nh)
                    .map(|k| first + (90.0 - first) * k as f64 / (nh - 1) as f64)
                    .collect()
            };
            let vs = proptest::collection::vec(0.01f64..1.0, nv - 1).prop_map(move |gaps| {
                let total: f64 = gaps.iter().sum();
                let mut acc = 0.0;
                let mut out = vec![vlo];
                for g in &gaps[..gaps.len() - 1] {
                    // interior angles at the cumulative gap fractions
                    acc += g;
                    out.push(vlo + (vhi - vlo) * acc / total);
                }
                out.push(vhi);
                out.dedup();
                out
            });
            let cd =
                proptest::collection::vec(prop_oneof![1 => Just(0.0), 4 => 0.0f64..1e4], nv * nh);
            (Just(pt), vs, Just(hs), cd)
        })
        .prop_filter_map("needs 2 distinct vertical angles", |(pt, vs, hs, cd)| {
            let nv = vs.len();
            if nv < 2 {
                return None;
            }
            let cd = cd[..nv * hs.len()].to_vec();
            let f = file(pt, vs, hs, cd);
            f.validate().is_ok().then_some(f)
        })
}
