//! Two estimators of one picture compared block by block: per seed, the mean RGB of each
//! block of pixels; the blocks' means over seeds must agree within their standard errors.

use lux::render::render::{RenderOptions, Renderer};
use lux::render::stats::RenderStats;

/// Per seed `1000 + i` (`i < seeds`), the mean RGB of each `block` × `block` block of a
/// `size` × `size` render of `scene` with `options`, and the render's statistics.
pub fn block_means(
    scene: &lux::usd::Scene,
    options: &RenderOptions,
    size: u32,
    block: u32,
    seeds: u64,
) -> (Vec<Vec<[f64; 3]>>, Vec<RenderStats>) {
    (0..seeds)
        .map(|seed| {
            let mut o = options.clone();
            o.seed = 1000 + seed;
            o.resolution = Some([size, size]);
            let r = Renderer::new(scene, o).unwrap();
            let warnings: Vec<&String> = r.warnings().collect();
            assert!(warnings.is_empty(), "{warnings:?}");
            let (img, stats) = r.render(&|_| {});
            assert_eq!(stats.non_finite_samples, 0);
            let nb = size / block;
            let mut blocks = vec![[0.0; 3]; (nb * nb) as usize];
            for y in 0..size {
                for x in 0..size {
                    let p = img.pixels[(y * size + x) as usize];
                    let b = &mut blocks[((y / block) * nb + x / block) as usize];
                    for c in 0..3 {
                        b[c] += p[c] as f64 / (block * block) as f64;
                    }
                }
            }
            (blocks, stats)
        })
        .unzip()
}

/// Mean and standard error over seeds of block `b`, channel `c`.
pub fn stat(runs: &[Vec<[f64; 3]>], b: usize, c: usize) -> (f64, f64) {
    let n = runs.len() as f64;
    let m = runs.iter().map(|r| r[b][c]).sum::<f64>() / n;
    let v = runs.iter().map(|r| (r[b][c] - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (v / n).sqrt())
}

/// Every block's mean agrees within 4 combined standard errors (and 0.1 % of the brightest
/// block, for blocks whose seeds agree to the last bit), and some blocks are lit (green mean
/// above `lit`).
pub fn agree(a: &[Vec<[f64; 3]>], b: &[Vec<[f64; 3]>], lit: f64, what: &str) {
    let blocks = a[0].len();
    let top = (0..blocks).map(|k| stat(a, k, 1).0).fold(0.0f64, f64::max);
    assert!(top > lit, "{what}: lit ({top})");
    let mut worst = 0.0f64;
    for k in 0..blocks {
        for c in 0..3 {
            let ((ma, sa), (mb, sb)) = (stat(a, k, c), stat(b, k, c));
            let z = (ma - mb).abs() / (sa * sa + sb * sb).sqrt().max(1e-3 * top);
            worst = worst.max(z);
            assert!(
                z < 4.0,
                "{what}: block {k} channel {c}: {ma:.5} ± {sa:.5} vs {mb:.5} ± {sb:.5}"
            );
        }
    }
    let rel = (0..blocks)
        .map(|k| {
            let ((ma, sa), (_, sb)) = (stat(a, k, 1), stat(b, k, 1));
            (sa * sa + sb * sb).sqrt() / ma.max(1e-9)
        })
        .fold(0.0f64, f64::max);
    eprintln!("{what}: worst block {worst:.2} standard errors; largest relative error {rel:.4}");
}
