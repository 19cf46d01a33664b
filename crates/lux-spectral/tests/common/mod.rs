//! Test helpers: read the CSV test data copied into tests/data.
#![allow(dead_code)]

use std::path::PathBuf;

pub fn data_path(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

/// Rows of a CSV file (header and `#` comment lines skipped), each parsed as f64 where possible;
/// the first column is kept as a string.
pub fn read_csv(rel: &str) -> Vec<(String, Vec<f64>)> {
    let text = std::fs::read_to_string(data_path(rel)).expect("test data present");
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .skip(1)
        .map(|l| {
            let mut it = l.split(',');
            let key = it.next().unwrap().trim().to_owned();
            let vals = it.map(|v| v.trim().parse::<f64>().unwrap()).collect();
            (key, vals)
        })
        .collect()
}

/// Relative difference |a − b| / |b|.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Small deterministic PRNG (SplitMix64) for Monte Carlo tests.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}
