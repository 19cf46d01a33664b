mod common;
use common::*;
use glam::{DVec2, DVec3};
use lux_bsdf::*;
#[test]
fn explore() {
    let t = std::time::Instant::now();
    let _ = lux_bsdf::albedo::dielectric(0.5, 0.5, 1.5);
    println!("tables {:?}", t.elapsed());
    for th in [20.0, 30.0, 35.0, 40.0, 45.0] { for a in [0.15, 0.3, 0.5] {
        let mut b = Bsdf::new(dir(th, 0.0), DVec3::Z, false, false);
        b.push(Node::Closure(dielectric(1.5, DVec2::splat(a), ScatterMode::R))).unwrap();
        let (m, se) = furnace(&b, 1 << 16, 3);
        println!("leaving R a={a} th={th}: {:.4} ± {:.4} albedo {:.4}", m.x, se.x, b.albedo().x);
    }}
}
