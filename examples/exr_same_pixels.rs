//! Whether two EXRs hold the same pixels, bit for bit (`f32` bits of every RGBA channel, data
//! window and display window), whatever their header attributes say: the comparison of
//! `scripts/bit_check.sh` when a change renames a settings attribute.
//!
//! `cargo run --release --example exr_same_pixels -- A.exr B.exr` exits 0 when the same, 1
//! when they differ (printing how many pixels), 2 when a file cannot be read.

use lux::render::image_io::read_exr_band;
use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [a, b] = args.as_slice() else {
        eprintln!("usage: exr_same_pixels A.exr B.exr");
        std::process::exit(2);
    };
    let read = |p: &str| {
        read_exr_band(Path::new(p)).unwrap_or_else(|e| {
            eprintln!("{e}");
            std::process::exit(2)
        })
    };
    let (a, b) = (read(a), read(b));
    let shape =
        |x: &lux::render::image_io::ExrBand| (x.image.width, x.image.height, x.y0, x.display);
    if shape(&a) != shape(&b) {
        println!("windows differ: {:?} vs {:?}", shape(&a), shape(&b));
        std::process::exit(1);
    }
    let bits = |p: &[f32; 4]| p.map(f32::to_bits);
    let differ = a
        .image
        .pixels
        .iter()
        .zip(&b.image.pixels)
        .filter(|(p, q)| bits(p) != bits(q))
        .count();
    if differ > 0 {
        println!("{differ} pixels differ");
        std::process::exit(1);
    }
}
