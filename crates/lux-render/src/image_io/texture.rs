//! [`Texture`]: a linear RGBA texture with allocation-free lookups.

use std::borrow::Cow;
use std::path::Path;

use exr::prelude::f16;

use super::{ImageError, error::IN_MEMORY, half_finite};

/// How a [`Texture`] holds its texels: `f32`, the `f16` bits of a half-float OpenEXR file as
/// stored (half the memory; three eighths for RGB without alpha), or the codes of an 8-bit
/// image (a quarter; a sixteenth for grey without alpha), each read back as the same `f32`
/// values: `f16` widened exactly, 8-bit codes through their decoding tables.
#[derive(Clone, Debug, PartialEq)]
enum Texels {
    F32(Vec<[f32; 4]>),
    /// The bits of a half-float file's RGBA.
    F16(Vec<[u16; 4]>),
    /// The bits of a half-float file's RGB without alpha (alpha 1).
    F16Rgb(Vec<[u16; 3]>),
    Srgb8(Vec<[u8; 4]>),
    /// Grey without alpha, one code a texel.
    Grey8(Vec<u8>),
}

/// The linear value of each 8-bit sRGB code, and each 8-bit alpha `a / 255`.
static SRGB8: std::sync::LazyLock<([f32; 256], [f32; 256])> = std::sync::LazyLock::new(|| {
    let alpha = std::array::from_fn(|a| f32::from(a as u8) / 255.0);
    (super::read::srgb8_table(), alpha)
});

/// An 8-bit texel's linear value.
#[inline(always)]
fn srgb8(p: [u8; 4]) -> [f32; 4] {
    let (c, a) = &*SRGB8;
    [
        c[usize::from(p[0])],
        c[usize::from(p[1])],
        c[usize::from(p[2])],
        a[usize::from(p[3])],
    ]
}

/// Replaces the components of `c` that are not `finite` (NaN, ±∞) by zero; how many there
/// were. A counting pass first (vectorised; most files have none), the replacement only then.
fn sanitise<T: Copy + Default>(c: &mut [T], finite: impl Fn(T) -> bool) -> usize {
    let bad = c.iter().filter(|&&x| !finite(x)).count();
    if bad > 0 {
        for x in c.iter_mut().filter(|x| !finite(**x)) {
            *x = T::default();
        }
    }
    bad
}

/// A texture loaded for lookups: linear RGBA read as `f32`, row 0 = **top**; held as `f32`,
/// as a half-float file's `f16` or as an 8-bit image's codes ([`Texture::is_half`],
/// [`Texture::is_8bit`], [`Texture::texel_bytes`]), with the same values either way.
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
    texels: Texels,
    non_finite: usize,
}

impl Texture {
    /// Loads a texture, choosing the decoder by the (case-insensitive) file extension:
    ///
    /// * `.exr` — OpenEXR via the `exr` crate: the first layer with `R`, `G`, `B` channels
    ///   (`A` optional, default 1) at its largest resolution level, any sample type
    ///   (f16 kept as stored when every colour channel is f16; f32; u32 converted to `f32`);
    ///   the layer's data window is the texture. Linear.
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
        Self::decoded(
            path,
            super::read::load_texels(super::read::Source::file(path))?,
        )
    }

    /// Decodes an image held in memory (e.g. an entry of a `.usdz` package); `name` gives the
    /// format by its extension, as for [`Texture::load`], and names the image in errors.
    pub fn from_bytes(name: &Path, bytes: &[u8]) -> Result<Texture, ImageError> {
        let source = super::read::Source::memory(name, bytes);
        Self::decoded(name, super::read::load_texels(source)?)
    }

    /// Checks, from its header alone, that [`Texture::load`] could start decoding the file at
    /// `path`: a format it reads, a header that parses, dimensions within the limits (the
    /// same errors). What lies past the header is not read.
    pub fn probe(path: &Path) -> Result<(), ImageError> {
        super::read::probe_texels(super::read::Source::file(path))
    }

    /// [`Texture::probe`] of an image held in memory, as [`Texture::from_bytes`] reads it.
    pub fn probe_bytes(name: &Path, bytes: &[u8]) -> Result<(), ImageError> {
        super::read::probe_texels(super::read::Source::memory(name, bytes))
    }

    /// A texture from what a decoder gave: `f32` texels, a half-float file's `f16` ones, or an
    /// 8-bit image's codes (always finite).
    fn decoded(path: &Path, d: super::read::Decoded) -> Result<Texture, ImageError> {
        match d {
            super::read::Decoded::F32(w, h, texels) => Self::build(path, w, h, texels),
            super::read::Decoded::F16(w, h, mut texels, bad) => {
                super::check_buffer(path, w, h, texels.len())?;
                let bad = bad.unwrap_or_else(|| sanitise(texels.as_flattened_mut(), half_finite));
                Ok(Self::with(w, h, Texels::F16(texels), bad))
            }
            super::read::Decoded::F16Rgb(w, h, mut texels, bad) => {
                super::check_buffer(path, w, h, texels.len())?;
                let bad = bad.unwrap_or_else(|| sanitise(texels.as_flattened_mut(), half_finite));
                Ok(Self::with(w, h, Texels::F16Rgb(texels), bad))
            }
            super::read::Decoded::Srgb8(w, h, codes) => {
                super::check_buffer(path, w, h, codes.len())?;
                Ok(Self::with(w, h, Texels::Srgb8(codes), 0))
            }
            super::read::Decoded::Grey8(w, h, codes) => {
                super::check_buffer(path, w, h, codes.len())?;
                Ok(Self::with(w, h, Texels::Grey8(codes), 0))
            }
        }
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
        let non_finite = sanitise(texels.as_flattened_mut(), f32::is_finite);
        Ok(Self::with(width, height, Texels::F32(texels), non_finite))
    }

    fn with(width: usize, height: usize, texels: Texels, non_finite: usize) -> Texture {
        Texture {
            width,
            height,
            width_f: width as f64,
            height_f: height as f64,
            texels,
            non_finite,
        }
    }

    /// Texel `i` (row-major), widened to `f32`.
    #[inline(always)]
    fn at(&self, i: usize) -> [f32; 4] {
        match &self.texels {
            Texels::F32(t) => t[i],
            Texels::F16(t) => t[i].map(|b| f16::from_bits(b).to_f32()),
            Texels::F16Rgb(t) => {
                let [r, g, b] = t[i].map(|b| f16::from_bits(b).to_f32());
                [r, g, b, 1.0]
            }
            Texels::Srgb8(t) => srgb8(t[i]),
            Texels::Grey8(t) => srgb8([t[i], t[i], t[i], 255]),
        }
    }

    /// How many texels there are (`width · height`).
    #[inline]
    fn len(&self) -> usize {
        self.width * self.height
    }

    /// Whether the texels are held as the `f16` of a half-float file (half the memory of
    /// `f32`, three eighths without alpha; lookups give the same values).
    pub fn is_half(&self) -> bool {
        matches!(self.texels, Texels::F16(_) | Texels::F16Rgb(_))
    }

    /// Whether the texels are held as the codes of an 8-bit image (a quarter of the memory of
    /// `f32`, a sixteenth for grey without alpha; lookups give the same values).
    pub fn is_8bit(&self) -> bool {
        matches!(self.texels, Texels::Srgb8(_) | Texels::Grey8(_))
    }

    /// Bytes the texels take.
    pub fn texel_bytes(&self) -> usize {
        match &self.texels {
            Texels::F32(t) => std::mem::size_of_val(t.as_slice()),
            Texels::F16(t) => std::mem::size_of_val(t.as_slice()),
            Texels::F16Rgb(t) => std::mem::size_of_val(t.as_slice()),
            Texels::Srgb8(t) => std::mem::size_of_val(t.as_slice()),
            Texels::Grey8(t) => t.len(),
        }
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

    /// All texels as `f32`, row-major, row 0 = top: texel `(x, y)` is
    /// `texels()[y * width + x]` (borrowed, or widened from `f16` into a copy).
    #[inline]
    pub fn texels(&self) -> Cow<'_, [[f32; 4]]> {
        match &self.texels {
            Texels::F32(t) => Cow::Borrowed(t),
            _ => Cow::Owned(self.texels_iter().collect()),
        }
    }

    /// Every texel as `f32`, row-major, row 0 = top, one at a time: [`Texture::texels`]
    /// without a widened copy of a compact texture.
    pub fn texels_iter(&self) -> impl ExactSizeIterator<Item = [f32; 4]> + '_ {
        (0..self.len()).map(|i| self.at(i))
    }

    /// The texels as `f32`, row-major, row 0 = top (for a conversion in place, then
    /// [`Texture::from_texels`]).
    #[inline]
    pub fn into_texels(self) -> Vec<[f32; 4]> {
        match self.texels {
            Texels::F32(t) => t,
            _ => self.texels_iter().collect(),
        }
    }

    /// The texel at column `x`, row `y` (row 0 = top), with both indices clamped to the
    /// texture.
    #[inline]
    pub fn texel(&self, x: usize, y: usize) -> [f32; 4] {
        let x = x.min(self.width - 1);
        let y = y.min(self.height - 1);
        self.at(y * self.width + x)
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
        self.at(y * self.width + x)
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
        let (t00, t10) = (self.at(r0 + i0), self.at(r0 + i1));
        let (t01, t11) = (self.at(r1 + i0), self.at(r1 + i1));
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
        for y in 0..self.height {
            let mut row_sum = [0.0f64; 4];
            for x in 0..self.width {
                let t = self.at(y * self.width + x);
                for c in 0..4 {
                    row_sum[c] += f64::from(t[c]);
                }
            }
            for c in 0..4 {
                sum[c] += row_sum[c];
            }
        }
        let n = self.len() as f64;
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
