//! [`Texture`]: a linear RGBA texture with allocation-free lookups.

use std::path::Path;

use super::{ImageError, error::IN_MEMORY};

/// A texture loaded for lookups: linear RGBA `f32`, row 0 = **top**.
///
/// Invariants: `1 ≤ width, height ≤ MAX_DIMENSION`, `width · height ≤ MAX_PIXELS`,
/// `texels.len() == width · height`, and every texel component is finite (NaN and ±∞ are
/// replaced by 0 on construction and counted in [`non_finite_count`](Self::non_finite_count)).
///
/// Lookups ([`nearest`](Self::nearest), [`bilinear`](Self::bilinear)) take `(u, v) ∈ [0, 1]²`
/// with `v = 0` at the top row; `u` wraps (repeat), `v` clamps to the edge. They never allocate
/// and never panic.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    width: usize,
    height: usize,
    /// `width` as `f64` (precomputed for the lookups).
    width_f: f64,
    /// `height` as `f64` (precomputed for the lookups).
    height_f: f64,
    texels: Vec<[f32; 4]>,
    non_finite: usize,
}

impl Texture {
    /// Loads a texture, choosing the decoder by the (case-insensitive) file extension:
    ///
    /// * `.exr` — OpenEXR via the `exr` crate: the first layer with `R`, `G`, `B` channels
    ///   (`A` optional, default 1) at its largest resolution level, any sample type
    ///   (f16 / f32 / u32, converted to `f32`); the layer's data window is the texture. Linear.
    /// * `.png` — 8- or 16-bit, grey / grey+alpha / RGB / RGBA; sRGB-decoded to linear.
    /// * `.jpg`, `.jpeg` — sRGB-decoded to linear.
    /// * `.hdr` — Radiance RGBE, linear.
    /// * `.tga`, `.bmp` — 8-bit, sRGB-decoded to linear.
    ///
    /// Anything else gives [`ImageError::UnsupportedFormat`]. Dimensions are checked against
    /// [`MAX_DIMENSION`](super::MAX_DIMENSION) / [`MAX_PIXELS`](super::MAX_PIXELS) from the
    /// file header before pixel storage is allocated. NaN and ±∞ texels become 0 (see
    /// [`non_finite_count`](Self::non_finite_count)).
    pub fn load(path: &Path) -> Result<Texture, ImageError> {
        let (width, height, texels) = super::read::load_rgba(path)?;
        Self::build(path, width, height, texels)
    }

    /// Decodes an image held in memory (e.g. an entry of a `.usdz` package); `name` gives the
    /// format by its extension, as for [`Texture::load`], and names the image in errors.
    pub fn from_bytes(name: &Path, bytes: &[u8]) -> Result<Texture, ImageError> {
        let (width, height, texels) =
            super::read::load_rgba_from(super::read::Source::memory(name, bytes))?;
        Self::build(name, width, height, texels)
    }

    /// Builds a texture from `width × height` linear texels (row-major, row 0 = top).
    ///
    /// Errors ([`ImageError::InvalidDimensions`], [`ImageError::PixelCountMismatch`], naming the
    /// pseudo file [`IN_MEMORY`]) if the size is empty or too large or `texels.len()` does not
    /// match. NaN and ±∞ components are replaced by 0.
    pub fn from_texels(
        width: usize,
        height: usize,
        texels: Vec<[f32; 4]>,
    ) -> Result<Texture, ImageError> {
        Self::build(Path::new(IN_MEMORY), width, height, texels)
    }

    fn build(
        path: &Path,
        width: usize,
        height: usize,
        mut texels: Vec<[f32; 4]>,
    ) -> Result<Texture, ImageError> {
        super::check_buffer(path, width, height, texels.len())?;
        let mut non_finite = 0;
        for c in texels.iter_mut().flat_map(|t| t.iter_mut()) {
            if !c.is_finite() {
                *c = 0.0;
                non_finite += 1;
            }
        }
        Ok(Texture {
            width,
            height,
            width_f: width as f64,
            height_f: height as f64,
            texels,
            non_finite,
        })
    }

    /// Width in texels.
    #[inline]
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in texels.
    #[inline]
    pub fn height(&self) -> usize {
        self.height
    }

    /// All texels, row-major, row 0 = top: texel `(x, y)` is `texels()[y * width + x]`.
    #[inline]
    pub fn texels(&self) -> &[[f32; 4]] {
        &self.texels
    }

    /// The texel at column `x`, row `y` (row 0 = top), with both indices clamped to the
    /// texture.
    #[inline]
    pub fn texel(&self, x: usize, y: usize) -> [f32; 4] {
        let x = x.min(self.width - 1);
        let y = y.min(self.height - 1);
        self.texels[y * self.width + x]
    }

    /// How many texel *components* were NaN or ±∞ in the source and were replaced by 0.
    #[inline]
    pub fn non_finite_count(&self) -> usize {
        self.non_finite
    }

    /// Nearest-texel lookup.
    ///
    /// `(u, v)` in `[0, 1]²` with `v = 0` at the **top** row. Texel `(x, y)` covers
    /// `[x/w, (x+1)/w) × [y/h, (y+1)/h)`. `u` wraps (repeat: `u − ⌊u⌋`), `v` clamps to
    /// `[0, 1]` (so `v = 1` is the bottom row). A NaN `u` (or ±∞, whose fractional part is
    /// NaN) selects column 0; a NaN `v` selects row 0 — so `(NaN, NaN)` gives texel `(0, 0)`.
    #[inline]
    pub fn nearest(&self, u: f64, v: f64) -> [f32; 4] {
        let fu = u - u.floor();
        // `as usize` saturates: negative → 0, NaN → 0, +∞ → usize::MAX.
        let x = ((fu * self.width_f) as usize).min(self.width - 1);
        let y = ((v * self.height_f) as usize).min(self.height - 1);
        self.texels[y * self.width + x]
    }

    /// Bilinear lookup between the four nearest texel centres.
    ///
    /// Texel `(x, y)` has its centre at `((x + 0.5)/w, (y + 0.5)/h)`; at a centre the result
    /// is that texel exactly. `v = 0` is the **top** edge. `u` wraps (the last column blends
    /// with the first), `v` clamps to the edge (above the first row's centre the first row is
    /// returned, below the last row's centre the last row). A NaN `u` (or ±∞) is treated as
    /// the centre of column 0, a NaN `v` as the centre of row 0.
    #[inline]
    pub fn bilinear(&self, u: f64, v: f64) -> [f32; 4] {
        let (w, h) = (self.width, self.height);

        let fu = u - u.floor();
        let mut x = fu * self.width_f - 0.5; // in [-0.5, w - 0.5]
        if x.is_nan() {
            x = 0.0;
        }
        let x0 = x.floor();
        let tx = (x - x0) as f32;
        let i0 = if x0 < 0.0 {
            w - 1
        } else {
            (x0 as usize).min(w - 1)
        };
        let i1 = if i0 + 1 >= w { 0 } else { i0 + 1 };

        let mut y = v * self.height_f - 0.5;
        if y.is_nan() {
            y = 0.0;
        }
        let y = y.clamp(0.0, self.height_f - 1.0);
        let y0 = y.floor();
        let ty = (y - y0) as f32;
        let j0 = (y0 as usize).min(h - 1);
        let j1 = (j0 + 1).min(h - 1);

        let r0 = j0 * w;
        let r1 = j1 * w;
        let (t00, t10) = (self.texels[r0 + i0], self.texels[r0 + i1]);
        let (t01, t11) = (self.texels[r1 + i0], self.texels[r1 + i1]);
        let (sx, sy) = (1.0 - tx, 1.0 - ty);
        let mut out = [0.0f32; 4];
        for c in 0..4 {
            let top = t00[c] * sx + t10[c] * tx;
            let bottom = t01[c] * sx + t11[c] * tx;
            out[c] = top * sy + bottom * ty;
        }
        out
    }

    /// The mean of all texels, per channel `[r, g, b, a]`, accumulated in `f64`
    /// (an `O(width · height)` pass; not cached).
    pub fn average(&self) -> [f64; 4] {
        let mut sum = [0.0f64; 4];
        // Sum rows separately to keep the accumulated rounding error small.
        for row in self.texels.chunks(self.width) {
            let mut row_sum = [0.0f64; 4];
            for t in row {
                for c in 0..4 {
                    row_sum[c] += f64::from(t[c]);
                }
            }
            for c in 0..4 {
                sum[c] += row_sum[c];
            }
        }
        let n = self.texels.len() as f64;
        sum.map(|s| s / n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tex3x2() -> Texture {
        // Row 0 (top): 0 1 2 ; row 1: 10 11 12 (all channels equal except alpha = 1).
        let v = [0.0, 1.0, 2.0, 10.0, 11.0, 12.0];
        Texture::from_texels(3, 2, v.iter().map(|&x| [x, x, x, 1.0]).collect()).unwrap()
    }

    #[test]
    fn nearest_wraps_and_clamps() {
        let t = tex3x2();
        assert_eq!(t.nearest(0.0, 0.0)[0], 0.0);
        assert_eq!(t.nearest(0.999, 0.999)[0], 12.0);
        assert_eq!(t.nearest(1.0, 1.0)[0], 10.0); // u wraps to 0, v clamps to the bottom row
        assert_eq!(t.nearest(-0.1, -5.0)[0], 2.0);
        assert_eq!(t.nearest(f64::NAN, f64::NAN)[0], 0.0);
        assert_eq!(t.nearest(f64::INFINITY, f64::INFINITY)[0], 10.0);
        assert_eq!(t.nearest(-1e-20, 0.5)[0], 12.0);
    }

    #[test]
    fn bilinear_wraps_in_u() {
        let t = tex3x2();
        // u = 0: halfway between column 2 (2) and column 0 (0) on the top row.
        assert_eq!(t.bilinear(0.0, 0.25)[0], 1.0);
        assert_eq!(t.bilinear(1.0, 0.25)[0], 1.0);
        // v = 0.5: halfway between rows.
        assert_eq!(t.bilinear(0.5, 0.5)[0], 6.0);
        assert_eq!(t.bilinear(f64::NAN, f64::NAN)[0], 0.0);
    }

    #[test]
    fn from_texels_sanitises() {
        let t = Texture::from_texels(1, 2, vec![[f32::NAN, 1.0, f32::INFINITY, 1.0], [-1.0; 4]])
            .unwrap();
        assert_eq!(t.texels()[0], [0.0, 1.0, 0.0, 1.0]);
        assert_eq!(t.texels()[1], [-1.0; 4]);
        assert_eq!(t.non_finite_count(), 2);
    }
}
