//! The constant-time lookup of `PhotometricWeb::intensity_with` against a straightforward
//! reference (bisection, a division per fraction, libm trigonometry, the Hermite interpolant
//! evaluated directly), on every file of the corpus and on random files, at random directions
//! and on every edge: θ < 0, NaN, θ ≥ π, outside the vertical range, on and next to every grid
//! angle, φ near 0 and 2π or far outside [0, 2π), types A and B.

// `!(x >= a)` is used on purpose: it is true for NaN, which must take the "outside" branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use lux_ies::{
    Edition, HeaderLine, IesFile, Interpolation, PhotometricType, PhotometricWeb, Symmetry, Tilt,
    Units,
};
use lux_math::{Profile, light_direction};
use proptest::prelude::*;
use std::f64::consts::{PI, TAU};
use std::path::Path;

/// Index `i ∈ [0, n − 2]` of the interval of the sorted `a` containing `x`, by bisection.
fn bisect(a: &[f64], x: f64) -> usize {
    a.partition_point(|&q| q <= x)
        .saturating_sub(1)
        .min(a.len() - 2)
}

/// Cubic Hermite on `[xs[1], xs[2]]` with Catmull-Rom tangents generalised to uneven spacing and
/// three-point one-sided tangents where a neighbour is missing (as documented on
/// `Interpolation::Bicubic`), evaluated directly.
fn hermite(x: f64, xs: [f64; 4], ps: [f64; 4]) -> f64 {
    let d = xs[2] - xs[1];
    let t = (x - xs[1]) / d;
    let secant = (ps[2] - ps[1]) / d;
    let has_left = xs[0] < xs[1];
    let has_right = xs[3] > xs[2];
    let m1 = if has_left {
        (ps[2] - ps[0]) / (xs[2] - xs[0])
    } else if has_right {
        let d2 = xs[3] - xs[2];
        secant + (secant - (ps[3] - ps[2]) / d2) * d / (d + d2)
    } else {
        secant
    };
    let m2 = if has_right {
        (ps[3] - ps[1]) / (xs[3] - xs[1])
    } else if has_left {
        let d0 = xs[1] - xs[0];
        secant + (secant - (ps[1] - ps[0]) / d0) * d / (d + d0)
    } else {
        secant
    };
    let (t2, t3) = (t * t, t * t * t);
    (2.0 * t3 - 3.0 * t2 + 1.0) * ps[1]
        + (t3 - 2.0 * t2 + t) * d * m1
        + (-2.0 * t3 + 3.0 * t2) * ps[2]
        + (t3 - t2) * d * m2
}

/// The reference evaluation of the spec's rules (§3) on the expanded web.
fn reference(w: &PhotometricWeb, theta: f64, phi: f64, interp: Interpolation) -> f64 {
    let (v, h, values) = (w.vertical_angles(), w.horizontal_angles(), w.values());
    let (nv, nh) = (v.len(), h.len());
    let (x, y) = match w.photometric_type() {
        PhotometricType::C => {
            if !(theta >= 0.0) || !phi.is_finite() {
                return 0.0;
            }
            let phi = phi.rem_euclid(TAU);
            // θ ≥ π: the last vertical angle
            (if theta >= PI { v[nv - 1] } else { theta }, phi)
        }
        t => {
            // light space → native (V, H) with libm: type B (−x, y, −z), type A (−y, x, −z)
            // are (cos V sin H, sin V, cos V cos H)
            let d = light_direction(theta, phi);
            let (a, b, c) = if t == PhotometricType::B {
                (-d.x, d.y, -d.z)
            } else {
                (-d.y, d.x, -d.z)
            };
            (b.clamp(-1.0, 1.0).asin(), a.atan2(c))
        }
    };
    if !(x >= v[0] && x <= v[nv - 1]) {
        return 0.0;
    }
    let axial = w.symmetry() == Symmetry::Axial;
    if !(axial || (y >= h[0] && y <= h[nh - 1])) {
        return 0.0;
    }
    let row = |k: usize| &values[k * nv..(k + 1) * nv];
    let i = bisect(v, x);
    match interp {
        Interpolation::Bilinear => {
            let tv = (x - v[i]) / (v[i + 1] - v[i]);
            let col = |k: usize| row(k)[i] + tv * (row(k)[i + 1] - row(k)[i]);
            if axial {
                return col(0);
            }
            let j = bisect(h, y);
            let th = (y - h[j]) / (h[j + 1] - h[j]);
            col(j) + th * (col(j + 1) - col(j))
        }
        Interpolation::Bicubic => {
            let vi = [i.saturating_sub(1), i, i + 1, (i + 2).min(nv - 1)];
            let vx = vi.map(|k| v[k]);
            let col = |k: usize| hermite(x, vx, vi.map(|q| row(k)[q])).max(0.0);
            if axial {
                return col(0);
            }
            let j = bisect(h, y);
            // type C: h[0] = 0 and h[nh − 1] = 2π are the same plane, neighbours wrap
            let periodic = w.photometric_type() == PhotometricType::C && nh > 2;
            let (i0, x0) = if j > 0 {
                (j - 1, h[j - 1])
            } else if periodic {
                (nh - 2, h[nh - 2] - TAU)
            } else {
                (j, h[j])
            };
            let (i3, x3) = if j + 2 < nh {
                (j + 2, h[j + 2])
            } else if periodic {
                (1, h[1] + TAU)
            } else {
                (j + 1, h[j + 1])
            };
            let p = [col(i0), col(j), col(j + 1), col(i3)];
            hermite(y, [x0, h[j], h[j + 1], x3], p).max(0.0)
        }
    }
}

/// Errors of the fast lookup against the reference: each value must be within 10⁻⁶ of the
/// reference relatively, or within 10⁻¹² of the web's largest value (where the reference itself
/// is a sum that cancels: rounding). Records the largest relative error where the value is at
/// least 10⁻⁶ of the largest, and the largest absolute error in units of the largest value
/// (per interpolation: bilinear, bicubic).
struct Check {
    rel: [f64; 2],
    abs: [f64; 2],
    at: [String; 2],
}

impl Check {
    fn new() -> Check {
        Check {
            rel: [0.0; 2],
            abs: [0.0; 2],
            at: [String::new(), String::new()],
        }
    }

    fn add(&mut self, w: &PhotometricWeb, name: &str, t: f64, p: f64) {
        let max = w.max_candela();
        for (k, interp) in [Interpolation::Bilinear, Interpolation::Bicubic]
            .into_iter()
            .enumerate()
        {
            let got = w.intensity_with(t, p, interp);
            let want = reference(w, t, p, interp);
            let at = || format!("{name} {interp:?} θ {t:e} φ {p:e}: {got} vs {want}");
            assert!(got.is_finite() && got >= 0.0, "{}", at());
            let err = (got - want).abs();
            assert!(err <= 1e-6 * want.abs() + 1e-12 * max, "{}", at());
            if want.abs() >= 1e-6 * max && err / want.abs() > self.rel[k] {
                self.rel[k] = err / want.abs();
                self.at[k] = at();
            }
            if max > 0.0 {
                self.abs[k] = self.abs[k].max(err / max);
            }
        }
    }
}

fn xorshift(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed | 1;
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Edge directions of a web: every grid angle (as light-space θ for type C), its neighbours one
/// ulp away, the ends of the ranges and beyond, φ around the seam.
fn edges(w: &PhotometricWeb) -> Vec<(f64, f64)> {
    let mut ts: Vec<f64> = vec![-1e-300, -0.0, 0.0, 1e-300, PI, PI.next_down(), 3.5, -2.0];
    let mut ps: Vec<f64> = vec![
        0.0,
        -0.0,
        1e-300,
        -1e-300,
        TAU,
        TAU.next_down(),
        TAU.next_up(),
        -TAU,
        7.0 * TAU + 0.3,
        -5.0,
        1e-12,
        -1e-12,
    ];
    if w.photometric_type() == PhotometricType::C {
        for &a in w.vertical_angles() {
            ts.extend([a, a.next_up(), a.next_down()]);
        }
        for &a in w.horizontal_angles() {
            ps.extend([a, a.next_up(), a.next_down()]);
        }
    } else {
        // light θ, φ of the native grid points
        for &v in w.vertical_angles() {
            for &h in w.horizontal_angles() {
                let (t, p) = w.native_to_light(v, h);
                ts.push(t);
                ps.push(p);
            }
        }
    }
    let mut out = Vec::new();
    for &t in &ts {
        for &p in &ps {
            out.push((t, p));
        }
    }
    for &t in &ts {
        out.push((t, f64::NAN));
        out.push((t, f64::INFINITY));
    }
    out.push((f64::NAN, 0.3));
    out
}

fn corpus() -> Vec<(String, PhotometricWeb)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let mut out = Vec::new();
    for dir in [
        "appleseed",
        "lidrs",
        "luxcore",
        "luxtest",
        "mdl-sdk",
        "radiance",
    ] {
        let mut files: Vec<_> = std::fs::read_dir(root.join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "ies"))
            .collect();
        files.sort();
        for p in files {
            let text = String::from_utf8_lossy(&std::fs::read(&p).unwrap()).into_owned();
            let Ok(file) = IesFile::parse(&text) else {
                continue;
            };
            let Ok(web) = PhotometricWeb::new(&file, Profile::Spec) else {
                continue;
            };
            let name = format!("{dir}/{}", p.file_name().unwrap().to_string_lossy());
            out.push((name, web));
        }
    }
    out
}

#[test]
fn fast_lookup_matches_the_reference_on_the_corpus() {
    let webs = corpus();
    assert!(webs.len() >= 18, "{}", webs.len());
    assert!(
        webs.iter()
            .any(|(_, w)| w.photometric_type() == PhotometricType::B),
        "the corpus has type B files"
    );
    let mut check = Check::new();
    let mut next = xorshift(0x2545F4914F6CDD1D);
    for (name, w) in &webs {
        for _ in 0..20_000 {
            // uniform on the sphere, plus a margin beyond [0, π] and φ beyond [0, 2π)
            let t = (2.0 * next() - 1.0).acos();
            let p = next() * TAU;
            check.add(w, name, t, p);
            let t = -0.2 + (PI + 0.4) * next();
            let p = -10.0 + 20.0 * next();
            check.add(w, name, t, p);
        }
        for (t, p) in edges(w) {
            check.add(w, name, t, p);
        }
    }
    for k in 0..2 {
        eprintln!(
            "corpus, {}: largest relative error {:e} ({}), largest absolute error {:e} of the peak",
            ["bilinear", "bicubic"][k],
            check.rel[k],
            check.at[k],
            check.abs[k]
        );
    }
}

fn file(
    ptype: PhotometricType,
    vertical_angles: Vec<f64>,
    horizontal_angles: Vec<f64>,
    candela: Vec<f64>,
) -> IesFile {
    IesFile {
        edition: Edition::Lm63_2002,
        header: vec![HeaderLine::Keyword {
            name: "TEST".into(),
            value: "lookup".into(),
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
        vertical_angles_deg: vertical_angles,
        horizontal_angles_deg: horizontal_angles,
        candela,
    }
}

/// Random valid files of every type and symmetry, with evenly spaced vertical angles (the
/// uniform fast path) or random gaps, and candela values including zeros.
fn arb_file() -> impl Strategy<Value = IesFile> {
    let ptype = prop_oneof![
        2 => Just(PhotometricType::C),
        1 => Just(PhotometricType::B),
        1 => Just(PhotometricType::A)
    ];
    (ptype, 2usize..12, 1usize..9, 0u8..4, 0u8..3, any::<bool>())
        .prop_flat_map(|(pt, nv, nh, hmode, vmode, even)| {
            let (vlo, vhi) = if pt == PhotometricType::C {
                [(0.0, 180.0), (0.0, 90.0), (90.0, 180.0)][vmode as usize]
            } else {
                [(-90.0, 90.0), (0.0, 90.0), (-40.0, 65.0)][vmode as usize]
            };
            let hs: Vec<f64> = if nh == 1 {
                vec![0.0]
            } else if pt == PhotometricType::C {
                match hmode {
                    3 => (0..nh)
                        .map(|k| 90.0 + 180.0 * k as f64 / (nh - 1) as f64)
                        .collect(),
                    m => {
                        let last = [90.0, 180.0, 360.0][m as usize];
                        (0..nh).map(|k| last * k as f64 / (nh - 1) as f64).collect()
                    }
                }
            } else {
                let first = if hmode == 0 { -90.0 } else { 0.0 };
                (0..nh)
                    .map(|k| first + (90.0 - first) * k as f64 / (nh - 1) as f64)
                    .collect()
            };
            let vs = proptest::collection::vec(0.001f64..1.0, nv).prop_map(move |gaps| {
                // nv − 1 gaps between vlo and vhi, all equal when `even`
                let g = if even {
                    vec![1.0; nv - 1]
                } else {
                    gaps[..nv - 1].to_vec()
                };
                let total: f64 = g.iter().sum();
                let mut acc = 0.0;
                let mut out = vec![vlo];
                for x in &g[..g.len() - 1] {
                    acc += x;
                    out.push(vlo + (vhi - vlo) * acc / total);
                }
                out.push(vhi);
                out
            });
            let cd =
                proptest::collection::vec(prop_oneof![Just(0.0), 0.0f64..1e4, Just(1e4)], nv * nh);
            (Just(pt), vs, Just(hs), cd)
        })
        .prop_map(|(pt, vs, hs, cd)| file(pt, vs, hs, cd))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn fast_lookup_matches_the_reference_on_random_files(
        f in arb_file(),
        dirs in proptest::collection::vec(
            (
                prop_oneof![
                    4 => -0.5f64..(PI + 0.5),
                    1 => 0.0f64..1e-6,
                    1 => (PI - 1e-6)..(PI + 1e-6),
                    1 => Just(0.0),
                    1 => Just(PI),
                    1 => Just(f64::NAN),
                ],
                prop_oneof![
                    4 => -20.0f64..20.0,
                    1 => -1e-9f64..1e-9,
                    1 => (TAU - 1e-9)..(TAU + 1e-9),
                    1 => Just(0.0),
                    1 => Just(TAU),
                    1 => Just(f64::INFINITY),
                ],
            ),
            64,
        ),
    ) {
        let w = PhotometricWeb::new(&f, Profile::Spec).unwrap();
        let mut check = Check::new();
        for (t, p) in dirs {
            check.add(&w, "random", t, p);
        }
        // the grid itself and its neighbours, for types A/B through their light-space angles
        for (t, p) in edges(&w).into_iter().step_by(7) {
            check.add(&w, "random", t, p);
        }
        prop_assert!(check.rel[0] <= 1e-6, "{}", check.at[0]);
        prop_assert!(check.rel[1] <= 1e-6, "{}", check.at[1]);
    }
}
