//! The film: the image's pixels, to which the tile loop adds each pixel's estimate
//! ([`Film::row_mut`]) and integrators add splats ([`Splats::add`]) — radiance landing on a pixel
//! other than the one whose sample made it, as a light tracer's particles do.
//!
//! Splats are summed in 64-bit fixed point (`2⁻²⁴` of a unit of radiance, ±2³⁹ in all): integer
//! addition is associative, so the sum — and the image — is the same bits for any thread count
//! and tile order. [`Film::finish`] adds the sums, divided by the number of camera samples that
//! could splat, to the pixels. Each splat's rounding is at most `2⁻²⁵`, far below any
//! estimator's noise.

use crate::image_io::ImageRgba;
use glam::DVec3;
use std::sync::atomic::{AtomicI64, Ordering};

/// Radiance landing on pixel `pixel` (`[x, y]`, y from the top): a splat.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splat {
    /// The pixel.
    pub pixel: [u32; 2],
    /// Its RGB radiance (before the division by the camera samples).
    pub rgb: DVec3,
}

/// Fixed-point units per unit of radiance in [`Splats`].
const SPLAT_SCALE: f64 = (1u64 << 24) as f64;

/// The splats' sums per pixel, in fixed point (see the module's doc).
pub struct Splats {
    width: u32,
    height: u32,
    sums: Vec<[AtomicI64; 3]>,
}

impl Splats {
    /// Zero sums for a `width × height` image.
    pub fn new(width: u32, height: u32) -> Splats {
        let sums = (0..width as usize * height as usize)
            .map(|_| std::array::from_fn(|_| AtomicI64::new(0)))
            .collect();
        Splats {
            width,
            height,
            sums,
        }
    }

    /// Adds `s` (from any thread): a splat outside the image, or not finite, is dropped and
    /// counted (the return value is false).
    pub fn add(&self, s: &Splat) -> bool {
        let [x, y] = s.pixel;
        if x >= self.width || y >= self.height || !s.rgb.is_finite() {
            return false;
        }
        let cell = &self.sums[y as usize * self.width as usize + x as usize];
        for (sum, v) in cell.iter().zip(s.rgb.to_array()) {
            // (saturating: a sum beyond ±2³⁹ is no longer a picture)
            let q = (v * SPLAT_SCALE).round().clamp(-9.0e15, 9.0e15) as i64;
            sum.fetch_add(q, Ordering::Relaxed);
        }
        true
    }

    /// The sum of the splats on pixel `[x, y]`.
    pub fn sum(&self, [x, y]: [u32; 2]) -> DVec3 {
        let cell = &self.sums[y as usize * self.width as usize + x as usize];
        DVec3::from_array(cell.each_ref().map(|s| s.load(Ordering::Relaxed) as f64)) / SPLAT_SCALE
    }
}

/// The image being made: RGBA per pixel (RGB radiance, alpha coverage); its splats sum
/// beside it in [`Splats`] (shared between threads while the pixels are written).
pub struct Film {
    width: u32,
    height: u32,
    pixels: Vec<[f32; 4]>,
}

impl Film {
    /// A black, transparent `width × height` film.
    pub fn new(width: u32, height: u32) -> Film {
        Film {
            width,
            height,
            pixels: vec![[0.0; 4]; width as usize * height as usize],
        }
    }

    /// The row-major RGBA of the `w` pixels from `[x, y]` on, to set.
    #[inline]
    pub fn row_mut(&mut self, [x, y]: [u32; 2], w: usize) -> &mut [[f32; 4]] {
        let from = y as usize * self.width as usize + x as usize;
        &mut self.pixels[from..from + w]
    }

    /// The image: each pixel of `window` (`[x0, y0, x1, y1)`) with its sum in `splats`
    /// divided by `samples` (the camera samples that could splat) added to its RGB.
    pub fn finish(self, window: [u32; 4], splats: Option<&Splats>, samples: u64) -> ImageRgba {
        let mut pixels = self.pixels;
        if let Some(splats) = splats
            && samples > 0
        {
            let [x0, y0, x1, y1] = window;
            for y in y0..y1 {
                for x in x0..x1 {
                    let add = splats.sum([x, y]) / samples as f64;
                    let p = &mut pixels[y as usize * self.width as usize + x as usize];
                    for (c, a) in p.iter_mut().zip(add.to_array()) {
                        *c = (*c as f64 + a) as f32;
                    }
                }
            }
        }
        ImageRgba {
            width: self.width as usize,
            height: self.height as usize,
            pixels,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Splats sum exactly in fixed point whatever the order, out-of-image and non-finite ones
    /// are dropped, and `finish` divides the sums by the samples.
    #[test]
    fn splats_sum_in_any_order() {
        let values: Vec<f64> = (0..1000)
            .map(|i| ((i * 7919) % 1013) as f64 * 0.37e-3)
            .collect();
        let s1 = Splats::new(2, 1);
        let s2 = Splats::new(2, 1);
        for v in &values {
            assert!(s1.add(&Splat {
                pixel: [1, 0],
                rgb: DVec3::splat(*v),
            }));
        }
        for v in values.iter().rev() {
            s2.add(&Splat {
                pixel: [1, 0],
                rgb: DVec3::splat(*v),
            });
        }
        assert_eq!(s1.sum([1, 0]), s2.sum([1, 0]));
        let exact: f64 = values.iter().sum();
        // (each splat rounds by at most 2⁻²⁵)
        assert!((s1.sum([1, 0]).x - exact).abs() <= 1000.0 * 2f64.powi(-25));
        assert!(!s1.add(&Splat {
            pixel: [2, 0],
            rgb: DVec3::ONE,
        }));
        assert!(!s1.add(&Splat {
            pixel: [0, 0],
            rgb: DVec3::new(f64::NAN, 0.0, 0.0),
        }));
        assert_eq!(s1.sum([0, 0]), DVec3::ZERO);
        let mut film = Film::new(2, 1);
        film.row_mut([0, 0], 1)[0] = [0.5, 0.5, 0.5, 1.0];
        let splats = Splats::new(2, 1);
        splats.add(&Splat {
            pixel: [0, 0],
            rgb: DVec3::new(4.0, 8.0, 0.0),
        });
        let img = film.finish([0, 0, 2, 1], Some(&splats), 4);
        assert_eq!(img.pixels[0], [1.5, 2.5, 0.5, 1.0]);
    }
}
