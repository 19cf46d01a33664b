//! lux-spectral benchmarks. Issue 8 target: spectrum → RGB for a 5 nm SPD ≤ 2 µs.

use criterion::{Criterion, criterion_group, criterion_main};
use lux_spectral::{
    Blackbody, ColorSpace, Illuminant, Interpolation, SampledSpectrum, Spectrum, spectrum_to_xyz,
};
use std::hint::black_box;

fn spectrum_to_rgb_5nm(c: &mut Criterion) {
    // CIE D65, 300–780 nm at 5 nm (97 samples), linear.
    let d65 = Illuminant::D65.spectrum();
    let mut g = c.benchmark_group("spectrum_to_rgb_5nm");
    g.bench_function("d65_linear_rec709", |b| {
        b.iter(|| ColorSpace::Rec709.xyz_to_rgb(spectrum_to_xyz(black_box(&d65))))
    });
    let f11 = Illuminant::F11.spectrum();
    g.bench_function("f11_linear_acescg", |b| {
        b.iter(|| ColorSpace::AcesCg.xyz_to_rgb(spectrum_to_xyz(black_box(&f11))))
    });
    let cubic = SampledSpectrum::new(
        d65.wavelengths().to_vec(),
        d65.values().to_vec(),
        Interpolation::Cubic,
    )
    .unwrap();
    g.bench_function("d65_cubic_rec709", |b| {
        b.iter(|| ColorSpace::Rec709.xyz_to_rgb(spectrum_to_xyz(black_box(&cubic))))
    });
    g.finish();
}

fn blackbody_to_rgb(c: &mut Criterion) {
    let bb = Spectrum::Blackbody(Blackbody::visible(3200.0).unwrap());
    c.bench_function("blackbody_to_rgb_380_780", |b| {
        b.iter(|| black_box(&bb).to_rgb(ColorSpace::Rec709))
    });
}

criterion_group!(benches, spectrum_to_rgb_5nm, blackbody_to_rgb);
criterion_main!(benches);
