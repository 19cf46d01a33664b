//! lux-ies lookup benchmarks: `ies_lookup_bilinear` (target ≤ 10 ns) and `ies_lookup_bicubic`
//! (target ≤ 25 ns) on bega_omni001_1238lm.ies at random directions (evenly spaced angles: the
//! interval is found by arithmetic), and on test_vstripes_hquadrants_nonuniform.ies (uneven
//! vertical angles: the interval is found with the bin table), plus
//! `ies_parse_throughput` of lux-ies on the whole corpus (the comparison with lidrs lives in
//! crates/lux-ies/benches/parse_vs_lidrs.rs).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use lux_ies::{IesFile, Interpolation, PhotometricWeb};
use lux_math::Profile;
use std::hint::black_box;
use std::path::Path;

const N: usize = 4096;

fn directions() -> Vec<(f64, f64)> {
    let mut s = 0x9E3779B97F4A7C15u64;
    let mut next = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..N)
        .map(|_| {
            // uniform on the sphere
            let z = 2.0 * next() - 1.0;
            (z.acos(), next() * std::f64::consts::TAU)
        })
        .collect()
}

fn data(rel: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/ies")
        .join(rel);
    String::from_utf8_lossy(&std::fs::read(p).unwrap()).into_owned()
}

fn lookup(c: &mut Criterion) {
    let web = |rel: &str| {
        let file = IesFile::parse(&data(rel)).unwrap();
        PhotometricWeb::new(&file, Profile::Spec).unwrap()
    };
    let omni = web("luxtest/bega_omni001_1238lm.ies");
    let uneven = web("luxtest/test_vstripes_hquadrants_nonuniform.ies");
    let dirs = directions();
    for (name, interp) in [
        ("ies_lookup_bilinear", Interpolation::Bilinear),
        ("ies_lookup_bicubic", Interpolation::Bicubic),
    ] {
        let mut g = c.benchmark_group(name);
        g.throughput(Throughput::Elements(N as u64));
        for (id, web) in [
            ("bega_omni001_random_dirs", &omni),
            ("nonuniform_random_dirs", &uneven),
        ] {
            g.bench_function(id, |b| {
                b.iter(|| {
                    let mut acc = 0.0;
                    for &(t, p) in &dirs {
                        acc += web.intensity_with(black_box(t), black_box(p), interp);
                    }
                    black_box(acc)
                })
            });
        }
        g.finish();
    }
}

fn parse(c: &mut Criterion) {
    let mut files = Vec::new();
    for dir in [
        "appleseed",
        "lidrs",
        "luxcore",
        "luxtest",
        "mdl-sdk",
        "radiance",
    ] {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/ies")
            .join(dir);
        for e in std::fs::read_dir(root).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "ies") {
                let t = String::from_utf8_lossy(&std::fs::read(&p).unwrap()).into_owned();
                if IesFile::parse(&t).is_ok() {
                    files.push(t);
                }
            }
        }
    }
    let bytes: usize = files.iter().map(String::len).sum();
    let mut g = c.benchmark_group("ies_parse_throughput");
    g.throughput(Throughput::Bytes(bytes as u64));
    g.bench_function("lux_ies_corpus", |b| {
        b.iter(|| {
            for t in &files {
                black_box(IesFile::parse(black_box(t)).unwrap());
            }
        })
    });
    g.finish();
}

criterion_group!(benches, lookup, parse);
criterion_main!(benches);
