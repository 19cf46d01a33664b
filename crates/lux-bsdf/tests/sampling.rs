//! `sample` against `pdf`: a chi-square test of the sampled directions' histogram against the
//! pdf integrated over the same bins (with one bin for delta and failed samples, so the pdf's
//! integral is tested too), for each closure at several roughnesses, anisotropies and
//! incidence angles, and for trees; plus the exact consistency of each sample's `pdf` and
//! `weight` with `pdf(wi)` and `eval(wi)/pdf(wi)`.
//!
//! Significance: 1 % family-wise over the `CASES` tests (Šidák), as Mitsuba's tests do.

mod common;
use common::*;
use glam::{DVec2, DVec3};
use lux_bsdf::*;

const N: usize = 200_000;
/// Number of chi-square tests in this file (for the Šidák correction).
const CASES: f64 = 120.0;

fn threshold() -> f64 {
    1.0 - (1.0 - 0.01f64).powf(1.0 / CASES)
}

fn run(name: &str, b: &Bsdf, seed: u64) -> Chi2 {
    let c = chi2(b, N, seed);
    println!(
        "{name}: p = {:.4} (dof {}), ∫pdf = {:.4}, delta {:.4}, failed {:.4}, consistency {:.1e}",
        c.p_value,
        c.dof,
        c.pdf_integral,
        c.delta_fraction,
        c.none_fraction,
        c.max_consistency_error
    );
    assert!(
        c.p_value > threshold(),
        "{name}: chi-square p-value {}",
        c.p_value
    );
    assert!(
        c.max_consistency_error < 1e-9,
        "{name}: sample vs pdf/eval {}",
        c.max_consistency_error
    );
    // ∫pdf = 1 − P(delta) − P(failed), within 4 binomial standard errors and the bins'
    // integration accuracy.
    let rest = 1.0 - c.delta_fraction - c.none_fraction;
    let se = (rest * (1.0 - rest) / N as f64).sqrt();
    assert!(
        (c.pdf_integral - rest).abs() < 4.0 * se + 2e-3,
        "{name}: ∫pdf {} vs {}",
        c.pdf_integral,
        rest
    );
    c
}

#[test]
fn diffuse_closures() {
    let f = frame();
    let cases: Vec<(&str, Closure)> = vec![
        ("lambert", lambert(DVec3::splat(0.8))),
        (
            "oren_nayar σ=0.7",
            Closure::OrenNayar {
                weight: 1.0,
                color: DVec3::ONE,
                roughness: 0.7,
                energy_compensation: false,
                frame: f,
            },
        ),
        (
            "eon σ=1",
            Closure::OrenNayar {
                weight: 1.0,
                color: DVec3::ONE,
                roughness: 1.0,
                energy_compensation: true,
                frame: f,
            },
        ),
        (
            "burley σ=0.5",
            Closure::Burley {
                weight: 1.0,
                color: DVec3::ONE,
                roughness: 0.5,
                frame: f,
            },
        ),
        (
            "translucent",
            Closure::Translucent {
                weight: 1.0,
                color: DVec3::ONE,
                frame: f,
            },
        ),
        (
            "subsurface",
            Closure::Subsurface {
                weight: 1.0,
                color: DVec3::ONE,
                radius: DVec3::ONE,
                anisotropy: 0.0,
                frame: f,
            },
        ),
        (
            "sheen r=0.1",
            Closure::Sheen {
                weight: 1.0,
                color: DVec3::ONE,
                roughness: 0.1,
                mode: SheenMode::ContyKulla,
                frame: f,
            },
        ),
        (
            "zeltner sheen r=0.6",
            Closure::Sheen {
                weight: 1.0,
                color: DVec3::ONE,
                roughness: 0.6,
                mode: SheenMode::Zeltner,
                frame: f,
            },
        ),
    ];
    // (At r = 0.05 and θ ≤ 60° the fitted albedo is ~0 and the lobe black.)
    for (r, th) in [(0.3, 80.0), (1.0, 40.0)] {
        let c = Closure::Sheen {
            weight: 1.0,
            color: DVec3::ONE,
            roughness: r,
            mode: SheenMode::Zeltner,
            frame: f,
        };
        let res = run(
            &format!("zeltner sheen r={r} θ={th} φ=40"),
            &single(c, dir(th, 40.0)),
            150,
        );
        assert!((res.pdf_integral - 1.0).abs() < 2e-3);
    }
    for (k, (name, c)) in cases.into_iter().enumerate() {
        for th in [10.0, 70.0] {
            let r = run(
                &format!("{name} θ={th}"),
                &single(c, dir(th, 0.0)),
                100 + k as u64,
            );
            assert!(
                (r.pdf_integral - 1.0).abs() < 2e-3,
                "diffuse pdf integrates to 1"
            );
        }
    }
}

#[test]
fn conductors() {
    let gold = (
        DVec3::new(0.183, 0.421, 1.373),
        DVec3::new(3.424, 2.346, 1.770),
    );
    let mut seed = 1;
    for a in [
        DVec2::splat(0.1),
        DVec2::splat(0.35),
        DVec2::splat(0.9),
        DVec2::new(0.08, 0.5),
    ] {
        for (th, phi) in [(0.0, 0.0), (40.0, 0.0), (75.0, 0.0), (50.0, 60.0)] {
            seed += 1;
            let b = single(conductor(gold.0, gold.1, a), dir(th, phi));
            run(&format!("gold α={a} θ={th} φ={phi}"), &b, seed);
        }
    }
    let c = Closure::Conductor {
        weight: 1.0,
        ior: gold.0,
        extinction: gold.1,
        alpha: DVec2::splat(0.3),
        retroreflective: true,
        thinfilm: ThinFilm::default(),
        frame: frame(),
    };
    run(
        "retroreflective gold α=0.3 θ=50",
        &single(c, dir(50.0, 0.0)),
        99,
    );
}

#[test]
fn dielectrics() {
    let mut seed = 1000;
    for mode in [ScatterMode::Rt, ScatterMode::R, ScatterMode::T] {
        for a in [DVec2::splat(0.1), DVec2::splat(0.45), DVec2::new(0.1, 0.4)] {
            for th in [0.0, 40.0, 75.0] {
                for entering in [true, false] {
                    seed += 1;
                    let mut b = Bsdf::new(dir(th, 0.0), DVec3::Z, entering, false);
                    b.push(Node::Closure(dielectric(1.5, a, mode))).unwrap();
                    run(
                        &format!("dielectric {mode:?} α={a} θ={th} entering={entering}"),
                        &b,
                        seed,
                    );
                }
            }
        }
    }
    for mode in [ScatterMode::Rt, ScatterMode::T] {
        for th in [0.0, 60.0] {
            seed += 1;
            let mut b = Bsdf::new(dir(th, 0.0), DVec3::Z, true, true);
            b.push(Node::Closure(dielectric(1.5, DVec2::splat(0.3), mode)))
                .unwrap();
            run(&format!("thin dielectric {mode:?} θ={th}"), &b, seed);
        }
    }
    let mut c = dielectric(1.5, DVec2::splat(0.3), ScatterMode::Rt);
    if let Closure::Dielectric {
        retroreflective, ..
    } = &mut c
    {
        *retroreflective = true;
    }
    run(
        "retroreflective dielectric RT θ=50",
        &single(c, dir(50.0, 0.0)),
        7,
    );
    // A thin film: the reflect/refract choice follows the coloured Airy reflectance.
    let c = Closure::Dielectric {
        weight: 1.0,
        tint: DVec3::ONE,
        ior: 1.5,
        alpha: DVec2::splat(0.25),
        retroreflective: false,
        thinfilm: ThinFilm {
            thickness: 500.0,
            ior: 1.3,
        },
        mode: ScatterMode::Rt,
        frame: frame(),
    };
    run("filmed dielectric RT θ=35", &single(c, dir(35.0, 0.0)), 9);
    // A smooth dielectric: only delta samples (the pdf integrates to 0).
    let r = run(
        "smooth dielectric RT θ=30",
        &single(
            dielectric(1.5, DVec2::ZERO, ScatterMode::Rt),
            dir(30.0, 0.0),
        ),
        8,
    );
    assert_eq!(r.delta_fraction, 1.0);
}

#[test]
fn generalized_schlick() {
    let mut seed = 2000;
    for mode in [ScatterMode::R, ScatterMode::Rt] {
        for a in [0.15, 0.5] {
            for th in [20.0, 70.0] {
                seed += 1;
                let c = schlick(
                    DVec3::new(0.9, 0.5, 0.1),
                    DVec3::new(0.7, 0.8, 1.0),
                    DVec2::splat(a),
                    mode,
                );
                run(
                    &format!("schlick {mode:?} α={a} θ={th}"),
                    &single(c, dir(th, 0.0)),
                    seed,
                );
            }
        }
    }
}

/// Layered trees: a rough and a smooth dielectric coat over Lambert, sheen over gold in a
/// mix with Burley, and multiply/add.
#[test]
fn trees() {
    for (k, alpha) in [0.2, 0.0].into_iter().enumerate() {
        for th in [0.0, 60.0] {
            let mut b = Bsdf::new(dir(th, 0.0), DVec3::Z, true, false);
            let base = b
                .push(Node::Closure(lambert(DVec3::new(0.8, 0.5, 0.2))))
                .unwrap();
            let top = b
                .push(Node::Closure(dielectric(
                    1.5,
                    DVec2::splat(alpha),
                    ScatterMode::R,
                )))
                .unwrap();
            b.push(Node::Layer {
                top,
                base: Some(base),
            })
            .unwrap();
            let r = run(
                &format!("dielectric α={alpha} over lambert θ={th}"),
                &b,
                300 + k as u64,
            );
            if alpha == 0.0 {
                assert!(r.delta_fraction > 0.0);
            }
        }
    }
    let mut b = Bsdf::new(dir(45.0, 30.0), DVec3::Z, true, false);
    let gold = b
        .push(Node::Closure(conductor(
            DVec3::new(0.183, 0.421, 1.373),
            DVec3::new(3.424, 2.346, 1.770),
            DVec2::splat(0.25),
        )))
        .unwrap();
    let sheen = b
        .push(Node::Closure(Closure::Sheen {
            weight: 0.7,
            color: DVec3::ONE,
            roughness: 0.3,
            mode: SheenMode::ContyKulla,
            frame: frame(),
        }))
        .unwrap();
    let coated = b
        .push(Node::Layer {
            top: sheen,
            base: Some(gold),
        })
        .unwrap();
    let burley = b
        .push(Node::Closure(Closure::Burley {
            weight: 1.0,
            color: DVec3::splat(0.6),
            roughness: 0.4,
            frame: frame(),
        }))
        .unwrap();
    let trans = b
        .push(Node::Closure(Closure::Translucent {
            weight: 1.0,
            color: DVec3::splat(0.3),
            frame: frame(),
        }))
        .unwrap();
    let scaled = b
        .push(Node::Multiply {
            a: trans,
            weight: DVec3::new(0.5, 1.0, 0.2),
        })
        .unwrap();
    let sum = b
        .push(Node::Add {
            a: Some(burley),
            b: Some(scaled),
        })
        .unwrap();
    b.push(Node::Mix {
        fg: Some(coated),
        bg: Some(sum),
        mix: 0.4,
    })
    .unwrap();
    run("mix(sheen over gold, burley + 0.5·translucent)", &b, 400);
}
