//! Variance ratios against area sampling (issue 5 targets), deterministic with a fixed seed.
//! The full table is printed by `cargo run -p lux-sample --release --example variance`.

mod common;

use common::*;

#[test]
fn variance_targets() {
    let n = 200_000;
    let r = ratio_receiver();
    for case in ratio_cases() {
        let (e_area, v_area) = estimator_variance(&case.area, &r, n, 11);
        for (name, light) in &case.better {
            let (e, v) = estimator_variance(light, &r, n, 12);
            let ratio = v_area / v;
            println!(
                "{}: {name}: ratio {ratio:.2} (E {e:.5} vs {e_area:.5})",
                case.name
            );
            // Every better technique must actually be better.
            assert!(ratio > 1.5, "{}: {name}: ratio {ratio}", case.name);
            // Issue targets: ≥ 10× for the sphere and the low rect.
            if case.name.starts_with("sphere") || case.name == "rect 1x1 at 0.25" {
                assert!(ratio >= 10.0, "{}: {name}: ratio {ratio} < 10", case.name);
            }
        }
    }
}

/// Justification of the disk's solid-angle technique with numbers (issue 5 allows "spherical
/// ellipse sampling, Guillén et al. 2017, or an equivalent you justify with numbers"): the
/// per-sample variance of the irradiance estimator of each disk technique against that of an
/// exact uniform solid-angle sampler (what spherical ellipse sampling achieves),
/// Var_Ω = Ω·∫cos²θ dω − E², computed by quadrature over the disk. Measured (n = 400 000):
///
/// | placement | elliptic cone | polar chord | area |
/// |---|---|---|---|
/// | on axis, h 0.5 | 0.999 | 0.997 | 17.0 |
/// | offset 0.3, h 0.5 | 0.995 | 14.0 | 18.9 |
/// | outside 0.8, h 0.5 | 0.984 | 2.67 | 21.4 |
/// | far out 1.5, h 0.3 | 0.990 | 4.47 | 18.9 |
/// | near, offset 0.3, h 0.1 | 0.996 | 1.04 | 66.0 |
/// | grazing 0.6, h 0.05 | 0.921 | 1.84 | 97.7 |
///
/// `EllipticCone` is asserted within 5 % of exact solid-angle sampling everywhere (on the axis
/// they coincide); `PolarChord`, exact only on the axis, is not.
#[test]
fn disk_solid_angle_techniques_against_exact_solid_angle_sampling() {
    use glam::{DMat4, DVec3};
    use lux_sample::*;
    let n = 400_000;
    let r = ratio_receiver();
    println!(
        "{:<24}{:>14}{:>14}{:>14}",
        "placement", "cone/exact", "chord/exact", "area/exact"
    );
    for (name, offset, h) in [
        ("on axis, h 0.5", 0.0, 0.5),
        ("offset 0.3, h 0.5", 0.3, 0.5),
        ("outside 0.8, h 0.5", 0.8, 0.5),
        ("far out 1.5, h 0.3", 1.5, 0.3),
        ("near, offset 0.3, h 0.1", 0.3, 0.1),
        ("grazing 0.6, h 0.05", 0.6, 0.05),
    ] {
        let m = xf(DMat4::from_translation(DVec3::new(offset, 0.0, h)));
        let light = |t| Light::Disk(DiskLight::new(0.5, m, t).unwrap());
        // Quadrature over the disk (midpoint rule in (ρ², φ), i.e. equal-area cells).
        let surf = disk_surface(0.5, m);
        let g = 1500;
        let (mut omega, mut e, mut m2) = (0.0, 0.0, 0.0);
        for i in 0..g {
            for j in 0..g {
                let (s, t) = ((i as f64 + 0.5) / g as f64, (j as f64 + 0.5) / g as f64);
                let (q, nrm, jac) = surf(s, t).unwrap();
                let v = q - r.p;
                let d2 = v.length_squared();
                let w = v / d2.sqrt();
                let dw = nrm.dot(-w).max(0.0) / d2 * jac / (g * g) as f64;
                let c = r.n.dot(w).max(0.0);
                omega += dw;
                e += c * dw;
                m2 += c * c * dw;
            }
        }
        let exact = omega * m2 - e * e;
        let mut ratios = [0.0; 3];
        for (k, t) in [
            DiskTechnique::EllipticCone,
            DiskTechnique::PolarChord,
            DiskTechnique::Area,
        ]
        .into_iter()
        .enumerate()
        {
            let (mean, v) = estimator_variance(&light(t), &r, n, 21 + k as u64);
            let se = (v / n as f64).sqrt();
            assert!((mean - e).abs() < 4.0 * se, "{name} {t:?}: {mean} vs {e}");
            ratios[k] = v / exact;
        }
        println!(
            "{name:<24}{:>14.3}{:>14.3}{:>14.3}",
            ratios[0], ratios[1], ratios[2]
        );
        assert!(
            ratios[0] < 1.05,
            "{name}: elliptic cone {:.3}× exact",
            ratios[0]
        );
        assert!(ratios[0] < ratios[2], "{name}: cone worse than area");
        if offset == 0.0 {
            assert!((ratios[0] - 1.0).abs() < 0.02 && (ratios[1] - 1.0).abs() < 0.02);
        }
    }
}
