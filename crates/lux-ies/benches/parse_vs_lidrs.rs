//! Parse throughput (MB/s) of lux-ies side by side with the MIT `lidrs` crate, on the corpus files
//! lidrs can read. Group: `ies_parse_throughput`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use std::path::Path;

fn corpus() -> Vec<(String, String)> {
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
        let mut names: Vec<_> = std::fs::read_dir(root.join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        names.sort();
        for p in names
            .into_iter()
            .filter(|p| p.extension().is_some_and(|x| x == "ies"))
        {
            let text = String::from_utf8_lossy(&std::fs::read(&p).unwrap()).into_owned();
            out.push((
                format!("{dir}/{}", p.file_name().unwrap().to_string_lossy()),
                text,
            ));
        }
    }
    out
}

fn lidrs_parse(text: &String) -> bool {
    let mut f = lidrs::io::ies::IesFile::new();
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f.parse(text).is_ok()))
        .unwrap_or(false)
}

fn bench(c: &mut Criterion) {
    // files both parsers accept
    let files: Vec<(String, String)> = corpus()
        .into_iter()
        .filter(|(_, t)| lux_ies::IesFile::parse(t).is_ok() && lidrs_parse(t))
        .collect();
    let bytes: usize = files.iter().map(|f| f.1.len()).sum();
    eprintln!(
        "ies_parse_throughput: {} files both parsers read, {bytes} bytes",
        files.len()
    );
    let mut g = c.benchmark_group("ies_parse_throughput");
    g.throughput(Throughput::Bytes(bytes as u64));
    g.bench_function("lux_ies", |b| {
        b.iter(|| {
            for (_, t) in &files {
                black_box(lux_ies::IesFile::parse(black_box(t)).unwrap());
            }
        })
    });
    g.bench_function("lidrs", |b| {
        b.iter(|| {
            for (_, t) in &files {
                let mut f = lidrs::io::ies::IesFile::new();
                black_box(f.parse(black_box(t)).is_ok());
                black_box(f);
            }
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
