//! Light selection: uniform, power (alias table) and light BVH. The probabilities returned by
//! `sample` must equal `pmf`, sum to one, and match the observed frequencies (χ²).

mod common;

use common::*;
use glam::DVec3;
use lux_sample::*;
use std::f64::consts::FRAC_PI_2;

fn scattered(n: usize, seed: u64) -> Vec<Option<LightBounds>> {
    let mut rng = SplitMix64::new(seed);
    (0..n)
        .map(|i| {
            let c = DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) * 4.0;
            let axis = if i % 3 == 0 {
                DVec3::NEG_Z
            } else {
                DVec3::new(rng.next_f64() - 0.5, 0.3, -1.0)
            };
            let cone = if i % 5 == 0 {
                EmissionCone::SPHERE
            } else {
                EmissionCone::new(axis, 0.1, FRAC_PI_2 * (0.3 + 0.7 * rng.next_f64())).unwrap()
            };
            Some(
                LightBounds::new(c - 0.1, c + 0.1, 0.2 + rng.next_f64(), cone, i % 7 == 0).unwrap(),
            )
        })
        .collect()
}

/// χ² of observed index frequencies against `pmf` (bins with < 5 expected pooled).
fn discrete_chi2(sel: &LightSelector, r: &Reference, n_lights: usize, n: usize) -> f64 {
    let mut rng = SplitMix64::new(3);
    let mut obs = vec![0.0; n_lights];
    let mut none = 0.0;
    for _ in 0..n {
        match sel.sample(r, rng.next_f64()) {
            Some((i, p)) => {
                assert!(
                    (p - sel.pmf(r, i)).abs() <= 1e-12 * p,
                    "sample pmf {p} vs pmf {}",
                    sel.pmf(r, i)
                );
                obs[i] += 1.0;
            }
            None => none += 1.0,
        }
    }
    let total: f64 = (0..n_lights).map(|i| sel.pmf(r, i)).sum();
    let mut cells: Vec<(f64, f64)> = (0..n_lights)
        .map(|i| (obs[i], sel.pmf(r, i) * n as f64))
        .collect();
    cells.push((none, (1.0 - total).max(0.0) * n as f64));
    let (mut chi2, mut used, mut po, mut pe) = (0.0, 0, 0.0, 0.0);
    for (o, e) in cells {
        if e < 5.0 {
            po += o;
            pe += e;
        } else {
            chi2 += (o - e) * (o - e) / e;
            used += 1;
        }
    }
    if pe >= 5.0 {
        chi2 += (po - pe) * (po - pe) / pe;
        used += 1;
    } else {
        assert!(po <= 20.0, "{po} selections where pmf predicts {pe}");
    }
    chi2_p_value(chi2, used - 1)
}

#[test]
fn bvh_pmf_sums_to_one_and_matches_frequencies() {
    let bounds = scattered(200, 1);
    let bvh = LightSelector::Bvh(LightBvh::new(&bounds).unwrap());
    for r in [
        Reference::surface(DVec3::new(2.0, 2.0, -1.0), DVec3::Z),
        Reference::point(DVec3::new(1.0, 3.0, 2.0)),
        Reference::surface(DVec3::new(-3.0, 1.0, 0.5), DVec3::X),
    ] {
        // Cones can cull whole subtrees below a node that still had importance, so Σ pmf ≤ 1
        // and `sample` returns None with the rest (the χ² below has a bin for that).
        let total: f64 = (0..200).map(|i| bvh.pmf(&r, i)).sum();
        assert!(total <= 1.0 + 1e-12 && total > 0.5, "Σ pmf = {total}");
        let p = discrete_chi2(&bvh, &r, 200, 200_000);
        assert!(p > ALPHA, "BVH frequencies rejected: p = {p}");
    }
}

/// Lights emitting in all directions: nothing is culled, so Σ pmf = 1 exactly.
fn omni(n: usize, centre: DVec3, spread: f64, seed: u64) -> Vec<Option<LightBounds>> {
    let mut rng = SplitMix64::new(seed);
    (0..n)
        .map(|_| {
            let c = centre
                + (DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) - 0.5) * spread;
            Some(LightBounds::new(c - 0.01, c + 0.01, 1.0, EmissionCone::SPHERE, false).unwrap())
        })
        .collect()
}

#[test]
fn bvh_prefers_the_near_cluster() {
    // Two clusters of 20 equal lights, 100 units apart; the receiver is 1 unit from the first.
    let mut bounds = omni(20, DVec3::ZERO, 0.4, 1);
    bounds.extend(omni(20, DVec3::new(100.0, 0.0, 0.0), 0.4, 2));
    let sel = LightSelector::Bvh(LightBvh::new(&bounds).unwrap());
    let r = Reference::point(DVec3::new(0.0, 0.0, -1.0));
    let total: f64 = (0..40).map(|i| sel.pmf(&r, i)).sum();
    assert!((total - 1.0).abs() < 1e-12, "Σ pmf = {total}");
    // Importance ∝ Φ/d²: the far cluster's share is about (1/100)² / (1 + (1/100)²) ≈ 1e-4.
    let near: f64 = (0..20).map(|i| sel.pmf(&r, i)).sum();
    assert!(near > 0.999, "near cluster pmf {near}");
    assert!(discrete_chi2(&sel, &r, 40, 100_000) > ALPHA);
}

#[test]
fn bvh_with_infinite_and_powerless_lights() {
    let mut bounds = omni(20, DVec3::splat(2.0), 4.0, 3);
    bounds.push(None); // e.g. a dome
    bounds.push(None); // e.g. a distant light
    let cone = EmissionCone::SPHERE;
    bounds.push(Some(
        LightBounds::new(DVec3::ZERO, DVec3::ONE, 0.0, cone, false).unwrap(),
    ));
    let sel = LightSelector::Bvh(LightBvh::new(&bounds).unwrap());
    let r = Reference::point(DVec3::new(1.0, 1.0, 1.0));
    // Two infinite lights and the tree: each infinite light has probability 1/3.
    assert!((sel.pmf(&r, 20) - 1.0 / 3.0).abs() < 1e-15);
    assert!((sel.pmf(&r, 21) - 1.0 / 3.0).abs() < 1e-15);
    assert_eq!(sel.pmf(&r, 22), 0.0);
    let total: f64 = (0..23).map(|i| sel.pmf(&r, i)).sum();
    assert!((total - 1.0).abs() < 1e-12);
    assert!(discrete_chi2(&sel, &r, 23, 100_000) > ALPHA);
}

#[test]
fn one_sided_light_behind_receiver_is_never_chosen() {
    let down = EmissionCone::new(DVec3::NEG_Z, 0.0, FRAC_PI_2).unwrap();
    let b = |x: f64| {
        Some(
            LightBounds::new(
                DVec3::new(x, 0.0, 1.0),
                DVec3::new(x + 0.1, 0.1, 1.0),
                1.0,
                down,
                false,
            )
            .unwrap(),
        )
    };
    let bvh = LightBvh::new(&[b(0.0), b(3.0)]).unwrap();
    // Above both lights: both face away.
    let r = Reference::point(DVec3::new(1.5, 0.0, 2.0));
    assert_eq!(bvh.sample(&r, 0.3), None);
    assert_eq!(bvh.pmf(&r, 0), 0.0);
}

#[test]
fn power_and_uniform_selection() {
    let power = [1.0, 0.0, 3.0, 0.5, 2.5];
    let sel = LightSelector::power(&power).unwrap();
    let r = Reference::point(DVec3::ZERO);
    assert!((sel.pmf(&r, 2) - 3.0 / 7.0).abs() < 1e-15);
    assert_eq!(sel.pmf(&r, 1), 0.0);
    assert!(discrete_chi2(&sel, &r, 5, 100_000) > ALPHA);
    let uni = LightSelector::uniform(7).unwrap();
    assert!((uni.pmf(&r, 3) - 1.0 / 7.0).abs() < 1e-15);
    assert_eq!(uni.pmf(&r, 7), 0.0);
    assert!(discrete_chi2(&uni, &r, 7, 100_000) > ALPHA);
    assert!(LightSelector::uniform(0).is_err());
    assert!(LightSelector::power(&[0.0, 0.0]).is_err());
    assert!(LightSelector::power(&[1.0, f64::NAN]).is_err());
}

/// The χ² machinery detects a wrong pmf: BVH samples against a uniform pmf are rejected.
#[test]
fn wrong_pmf_is_rejected() {
    let bounds = scattered(50, 4);
    let bvh = LightBvh::new(&bounds).unwrap();
    let r = Reference::point(DVec3::new(0.0, 0.0, -0.5));
    let mut rng = SplitMix64::new(5);
    let mut obs = [0.0f64; 50];
    let n = 100_000;
    for _ in 0..n {
        if let Some((i, _)) = bvh.sample(&r, rng.next_f64()) {
            obs[i] += 1.0;
        }
    }
    let e = n as f64 / 50.0;
    let chi2: f64 = obs.iter().map(|o| (o - e) * (o - e) / e).sum();
    assert!(chi2_p_value(chi2, 49) < 1e-6);
}

/// `sample_each` (one descent for several numbers) answers what `sample` answers for each
/// number, bit for bit: with and without infinite lights, numbers in any order (repeats
/// included), more numbers than one stack chunk, from receivers with and without a normal.
#[test]
fn sample_each_equals_sample_per_number() {
    let mut bounds = scattered(37, 9);
    let with_infinite = {
        let mut b = bounds.clone();
        b.insert(5, None);
        b.push(None);
        b
    };
    bounds.truncate(37);
    let mut rng = SplitMix64::new(17);
    for bs in [&bounds, &with_infinite] {
        let bvh = LightBvh::new(bs).unwrap();
        let sel = LightSelector::Bvh(bvh.clone());
        for trial in 0..200 {
            let p = DVec3::new(
                rng.next_f64() - 0.5,
                rng.next_f64() - 0.5,
                rng.next_f64() - 0.5,
            );
            let r = if trial % 2 == 0 {
                Reference::point(p * 3.0)
            } else {
                Reference::surface(p * 3.0, DVec3::new(0.3, -0.5, 0.8).normalize())
            };
            let k = 1 + trial % 40;
            let mut us: Vec<f64> = (0..k).map(|_| rng.next_f64()).collect();
            if k > 3 {
                us[2] = us[1];
            }
            let mut out = vec![None; k];
            sel.sample_each(&r, &us, &mut out);
            for (u, o) in us.iter().zip(&out) {
                let one = bvh.sample(&r, *u);
                assert_eq!(
                    one.map(|(i, p)| (i, p.to_bits())),
                    o.map(|(i, p)| (i, p.to_bits())),
                    "u = {u}"
                );
            }
        }
    }
}

/// A receiver with a normal takes light from its side only: a light wholly below its horizon
/// is never chosen (it is without a normal), one straddling the horizon keeps a share.
#[test]
fn lights_below_the_receivers_horizon_are_never_chosen() {
    let any = EmissionCone::SPHERE;
    let ball = |c: DVec3, r: f64| {
        Some(LightBounds::new(c - DVec3::splat(r), c + DVec3::splat(r), 1.0, any, false).unwrap())
    };
    let bvh = LightBvh::new(&[
        ball(DVec3::new(1.0, 2.0, 0.0), 0.1),   // above
        ball(DVec3::new(-1.0, -2.0, 0.0), 0.1), // below
        ball(DVec3::new(0.0, 0.05, 1.0), 0.2),  // straddling
    ])
    .unwrap();
    let up = Reference::surface(DVec3::ZERO, DVec3::Y);
    assert_eq!(bvh.pmf(&up, 1), 0.0);
    assert!(bvh.pmf(&up, 0) > 0.0 && bvh.pmf(&up, 2) > 0.0);
    assert!((bvh.pmf(&up, 0) + bvh.pmf(&up, 2) - 1.0).abs() < 1e-12);
    let mut rng = SplitMix64::new(3);
    for _ in 0..10_000 {
        assert_ne!(bvh.sample(&up, rng.next_f64()).map(|c| c.0), Some(1));
    }
    let free = Reference::point(DVec3::ZERO);
    assert!(bvh.pmf(&free, 1) > 0.0);
}
