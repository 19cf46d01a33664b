//! Image input and output for the renderer: textures in, EXR / PNG out.
//!
//! # Conventions
//!
//! * **Row order.** Every pixel array is row-major and starts at the **top** row: the pixel at
//!   column `x`, row `y` is `pixels[y * width + x]`, `y = 0` is the top of the image. This is
//!   the order of PNG, JPEG, Radiance HDR and OpenEXR's default (`INCREASING_Y`) line order.
//! * **Texture coordinates.** [`Texture::nearest`] and [`Texture::bilinear`] take `(u, v)` with
//!   `u` running left → right and `v = 0` at the **top** row (image order, *not* the OpenGL /
//!   USD `st` convention — flip `v` yourself if you hold `st`). `u` wraps (repeat), `v` clamps
//!   to the edge. A NaN coordinate selects column / row 0.
//! * **Colour.** All pixel values in memory are *linear*. 8- and 16-bit PNG and JPEG files are
//!   taken to be sRGB-encoded and decoded with the exact sRGB EOTF ([`srgb_to_linear`]);
//!   OpenEXR and Radiance `.hdr` files are linear already. Embedded colour profiles
//!   (`gAMA`, `iCCP`, …) are ignored. Alpha is never colour-encoded; a missing alpha is 1.
//!   Grey and grey + alpha images expand to RGB(A).
//! * **Storage.** Texels are held as `f32` RGBA, except an OpenEXR file whose R, G, B (and A)
//!   channels are half floats, held as its `f16` (8 bytes a texel instead of 16), and an 8-bit
//!   image, held as its codes (4 bytes, 1 for grey without alpha; colour decoded through the
//!   sRGB table, alpha `a/255`):
//!   every lookup reads back the same `f32` values. Materials decode their texture files in
//!   parallel before they are prepared, or each when first read (`material::TextureDecoding`).
//! * **Sanitising.** Loaded textures never contain NaN or ±∞: such texels (possible in EXR) are
//!   replaced by 0 and counted ([`Texture::non_finite_count`]). Negative values are kept.
//! * **Limits.** Images must be between 1 and [`MAX_DIMENSION`] pixels per side and hold at most
//!   [`MAX_PIXELS`] pixels. File dimensions are checked from the header *before* any pixel
//!   storage is allocated, so absurd headers give [`ImageError::InvalidDimensions`], not an
//!   allocation failure.
//! * **Errors, not panics.** Bad input (truncated or garbage files, unsupported formats, bad
//!   sizes) gives a typed [`ImageError`] naming the file. As a last line of defence, a panic
//!   inside a third-party decoder is caught and reported as [`ImageError::Decode`].
//! * **Atomic writes.** [`write_exr`] and [`write_png`] write a temporary file in the target's
//!   directory and rename it over the target ([`write_atomically`]); on error the target is
//!   untouched and the temporary file removed.

mod band;
mod error;
mod read;
mod texture;
mod write;

pub use band::{ExrBand, read_exr_band, stage_exr_band};
pub use error::{IN_MEMORY, ImageError};
pub use texture::Texture;
pub use write::{
    StagedFile, stage_atomically, stage_exr, stage_png, stage_png_opaque, write_atomically,
    write_exr, write_png,
};

use std::path::Path;

/// The largest supported width or height, in pixels (for reading, writing and textures).
pub const MAX_DIMENSION: usize = 32_768;

/// The largest supported pixel count `width × height` (2²⁸, i.e. 4 GiB of RGBA `f32`).
pub const MAX_PIXELS: usize = 1 << 28;

/// An RGBA float image: row-major from the **top** row, linear values.
///
/// The pixel at column `x`, row `y` (`y = 0` at the top) is `pixels[y * width + x]`; channels
/// are `[r, g, b, a]`. The writers require `pixels.len() == width * height` and a size within
/// [`MAX_DIMENSION`] / [`MAX_PIXELS`].
#[derive(Clone, Debug, PartialEq)]
pub struct ImageRgba {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// `width * height` pixels, row-major, top row first, linear `[r, g, b, a]`.
    pub pixels: Vec<[f32; 4]>,
}

/// The sRGB EOTF (IEC 61966-2-1): an sRGB-encoded value to linear.
///
/// `c ≤ 0.04045 → c / 12.92`, otherwise `((c + 0.055) / 1.055)^2.4`, evaluated in `f64`.
/// The formula is applied as is outside `[0, 1]` (negative inputs use the linear segment);
/// NaN propagates.
pub fn srgb_to_linear(c: f32) -> f32 {
    srgb_to_linear_f64(f64::from(c)) as f32
}

/// The sRGB OETF (IEC 61966-2-1): a linear value to sRGB encoding.
///
/// `c ≤ 0.0031308 → 12.92·c`, otherwise `1.055·c^(1/2.4) − 0.055`, evaluated in `f64`.
/// No clamping is done (negative inputs use the linear segment); NaN propagates. The PNG writer
/// clamps to `[0, 1]` before applying it.
pub fn linear_to_srgb(c: f32) -> f32 {
    linear_to_srgb_f64(f64::from(c)) as f32
}

/// Whether the IEEE 754 half float of bits `b` is finite: NaN and ±∞ are those whose five
/// exponent bits are all set (`b & 0x7C00 == 0x7C00`).
#[inline(always)]
pub(crate) fn half_finite(b: u16) -> bool {
    b & 0x7C00 != 0x7C00
}

/// [`srgb_to_linear`] in `f64` (the one formula, `lux_usd::shading::color_space`'s, which
/// MaterialX colour values and texture texels share).
pub(crate) fn srgb_to_linear_f64(c: f64) -> f64 {
    lux_usd::shading::color_space::srgb_to_linear(c)
}

/// [`linear_to_srgb`] in `f64`.
pub(crate) fn linear_to_srgb_f64(c: f64) -> f64 {
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Checks `width × height` against the size limits (before anything is allocated).
pub(crate) fn check_dimensions(path: &Path, width: u64, height: u64) -> Result<(), ImageError> {
    let max_dim = MAX_DIMENSION as u64;
    let ok = (1..=max_dim).contains(&width)
        && (1..=max_dim).contains(&height)
        && width * height <= MAX_PIXELS as u64;
    if ok {
        Ok(())
    } else {
        Err(ImageError::InvalidDimensions {
            path: path.to_path_buf(),
            width,
            height,
        })
    }
}

/// Checks an in-memory image's size and pixel count.
pub(crate) fn check_buffer(
    path: &Path,
    width: usize,
    height: usize,
    len: usize,
) -> Result<(), ImageError> {
    check_dimensions(path, width as u64, height as u64)?;
    if len == width * height {
        Ok(())
    } else {
        Err(ImageError::PixelCountMismatch {
            path: path.to_path_buf(),
            width,
            height,
            len,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_curves_invert_each_other() {
        for i in 0..=1000 {
            let x = i as f64 / 1000.0;
            let back = srgb_to_linear_f64(linear_to_srgb_f64(x));
            assert!((back - x).abs() < 1e-12, "{x} -> {back}");
        }
    }

    #[test]
    fn srgb_segments_meet() {
        // The two segments of each curve agree at the breakpoint to ~1e-8 (the standard's
        // rounded constants make them not exactly continuous).
        let lin = 0.003_130_8_f64;
        let a = 12.92 * lin;
        let b = 1.055 * lin.powf(1.0 / 2.4) - 0.055;
        assert!((a - b).abs() < 1e-7);
        let s = 0.04045_f64;
        let c = s / 12.92;
        let d = ((s + 0.055) / 1.055).powf(2.4);
        assert!((c - d).abs() < 1e-7);
    }

    #[test]
    fn dimension_checks() {
        let p = Path::new("x.png");
        assert!(check_dimensions(p, 1, 1).is_ok());
        assert!(check_dimensions(p, 32_768, 8_192).is_ok());
        assert!(check_dimensions(p, 0, 5).is_err());
        assert!(check_dimensions(p, 5, 0).is_err());
        assert!(check_dimensions(p, 32_769, 1).is_err());
        assert!(check_dimensions(p, 32_768, 8_193).is_err());
        assert!(check_dimensions(p, u64::from(u32::MAX), u64::from(u32::MAX)).is_err());
        assert!(check_buffer(p, 2, 2, 4).is_ok());
        assert!(matches!(
            check_buffer(p, 2, 2, 3),
            Err(ImageError::PixelCountMismatch { len: 3, .. })
        ));
    }
}
