mod common;
use common::*;
use glam::{DVec2, DVec3};
use lux_bsdf::*;

#[test]
fn explore() {
    let t = std::time::Instant::now();
    let _ = lux_bsdf::albedo::ggx(0.5, 0.5);
    let _ = lux_bsdf::albedo::dielectric(0.5, 0.5, 1.5);
    println!("tables {:?}", t.elapsed());
    for a in [0.05, 0.2, 0.5, 1.0] {
        for th in [0.0, 45.0, 80.0] {
            let b = single(
                conductor(DVec3::ZERO, DVec3::ZERO, DVec2::splat(a)),
                dir(th, 0.0),
            );
            let (m, se) = furnace(&b, 1 << 16, 1);
            let c = chi2(&b, 200_000, 2);
            println!(
                "cond a={a} th={th}: furnace {:.5} ± {:.5} albedo {:.5} chi2 p={:.3} int={:.4} none={:.4} err={:.2e}",
                m.x,
                se.x,
                b.albedo().x,
                c.p_value,
                c.pdf_integral,
                c.none_fraction,
                c.max_consistency_error
            );
        }
    }
    for a in [0.05, 0.3, 0.8] {
        for th in [0.0, 45.0, 80.0] {
            for entering in [true, false] {
                let mut b = Bsdf::new(dir(th, 0.0), DVec3::Z, entering, false);
                b.push(Node::Closure(dielectric(
                    1.5,
                    DVec2::splat(a),
                    ScatterMode::Rt,
                )))
                .unwrap();
                let (m, se) = furnace(&b, 1 << 16, 1);
                let c = chi2(&b, 200_000, 2);
                println!(
                    "diel RT a={a} th={th} ent={entering}: furnace {:.5} ± {:.5} albedo {:.5} chi2 p={:.3} int={:.4} none={:.4} err={:.2e}",
                    m.x,
                    se.x,
                    b.albedo().x,
                    c.p_value,
                    c.pdf_integral,
                    c.none_fraction,
                    c.max_consistency_error
                );
            }
        }
    }
}
