//! Rough cost of `eval`, `pdf`, `sample` and `albedo` for a standard_surface-like tree
//! (coat over sheen over (metal mix (specular layer over diffuse))). Run with
//! `cargo run -p lux-bsdf --release --example timing`.

use glam::{DVec2, DVec3};
use lux_bsdf::*;
use std::hint::black_box;
use std::time::Instant;

/// A smooth-ish dielectric reflection of roughness `alpha`, as the specular layer and the coat.
fn specular(alpha: f64, frame: Frame) -> Node {
    Node::Closure(Closure::Dielectric {
        weight: 1.0,
        tint: DVec3::ONE,
        ior: 1.5,
        alpha: DVec2::splat(alpha),
        retroreflective: false,
        thinfilm: ThinFilm::default(),
        mode: ScatterMode::R,
        frame,
    })
}

/// Pushes `top` layered over `base`.
fn layer(b: &mut Bsdf, top: NodeId, base: NodeId) -> NodeId {
    b.push(Node::Layer {
        top,
        base: Some(base),
    })
    .unwrap()
}

fn tree(wo: DVec3) -> Bsdf {
    let f = Frame::new(DVec3::Z, DVec3::X);
    let mut b = Bsdf::new(wo, DVec3::Z, true, false);
    let diffuse = b
        .push(Node::Closure(Closure::OrenNayar {
            weight: 1.0,
            color: DVec3::new(0.8, 0.4, 0.2),
            roughness: 0.3,
            energy_compensation: true,
            frame: f,
        }))
        .unwrap();
    let spec = b.push(specular(0.2, f)).unwrap();
    let dielectric = layer(&mut b, spec, diffuse);
    let metal = b
        .push(Node::Closure(Closure::Conductor {
            weight: 1.0,
            ior: DVec3::new(0.183, 0.421, 1.373),
            extinction: DVec3::new(3.424, 2.346, 1.770),
            alpha: DVec2::splat(0.3),
            retroreflective: false,
            thinfilm: ThinFilm::default(),
            frame: f,
        }))
        .unwrap();
    let base = b
        .push(Node::Mix {
            fg: Some(metal),
            bg: Some(dielectric),
            mix: 0.3,
        })
        .unwrap();
    let sheen = b
        .push(Node::Closure(Closure::Sheen {
            weight: 0.5,
            color: DVec3::ONE,
            roughness: 0.3,
            mode: SheenMode::ContyKulla,
            frame: f,
        }))
        .unwrap();
    let sheened = layer(&mut b, sheen, base);
    let coat = b.push(specular(0.05, f)).unwrap();
    layer(&mut b, coat, sheened);
    b
}

/// Runs `f(i)` for `i` in `0..n` and prints the mean time a call after `label`.
fn time(label: &str, n: usize, mut f: impl FnMut(usize)) {
    let t = Instant::now();
    for i in 0..n {
        f(i);
    }
    println!("{label} {:.0} ns", t.elapsed().as_nanos() as f64 / n as f64);
}

fn main() {
    let t = Instant::now();
    let _ = tree(DVec3::Z).albedo();
    println!("tables built on first use: {:?}", t.elapsed());
    let n = 200_000;
    let wo = DVec3::new(0.6, 0.0, 0.8);
    let b = tree(wo);
    let wi = DVec3::new(-0.3, 0.2, 0.9).normalize();
    let u = |i: usize| (i as f64 + 0.5) / n as f64;
    time("eval:  ", n, |i| {
        black_box(black_box(&b).eval(black_box(wi + DVec3::X * (i as f64 * 1e-9))));
    });
    time("pdf:   ", n, |_| {
        black_box(black_box(&b).pdf(black_box(wi)));
    });
    time("sample:", n, |i| {
        let u = u(i);
        black_box(black_box(&b).sample(u, [u * 7.0 % 1.0, u * 13.0 % 1.0]));
    });
    time("albedo:", n, |_| {
        black_box(black_box(&b).albedo());
    });
    let p = b.prepare();
    time("prepared eval:  ", n, |i| {
        black_box(black_box(&p).eval(black_box(wi + DVec3::X * (i as f64 * 1e-9))));
    });
    time("prepared sample:", n, |i| {
        let u = u(i);
        black_box(black_box(&p).sample(u, [u * 7.0 % 1.0, u * 13.0 % 1.0]));
    });
    time("prepare:", n, |_| {
        black_box(black_box(&b).prepare());
    });
    println!("size_of::<Bsdf>() = {} bytes", std::mem::size_of::<Bsdf>());
    println!(
        "size_of::<PreparedBsdf>() = {} bytes",
        std::mem::size_of::<PreparedBsdf>()
    );
}
