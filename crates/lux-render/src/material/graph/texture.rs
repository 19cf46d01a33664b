//! `image` and `tiledimage` (`MaterialX.StandardNodes.md`, "Texture Nodes"), their files'
//! colour spaces (`MaterialX.Specification.md`, "Color Spaces and Color Management": the
//! cmlib transforms to `lin_rec709`, lux's working space), and the cache that loads each
//! file once per colour space.

use crate::image_io::{Texture, linear_to_srgb, srgb_to_linear};
use glam::{DVec2, DVec4};
use lux_usd::shading::FileValue;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

pub use lux_usd::shading::color_space::ColorSpace;
use lux_usd::shading::color_space::is_float_format;

/// Linear Rec.709 from a texel's encoded value `c` in `space` (sRGB decoded through the
/// `f32` EOTF lux's image loaders use, the other spaces by [`ColorSpace::decode`]).
fn decode_texel(space: ColorSpace, c: [f64; 3]) -> [f64; 3] {
    match space {
        ColorSpace::Srgb => c.map(|x| f64::from(srgb_to_linear(x as f32))),
        _ => space.decode(c),
    }
}

/// Textures loaded for shading graphs: one per resolved file and colour space, converted to
/// linear Rec.709 once (failures remembered too, so a missing file warns once per material).
#[derive(Debug, Default)]
pub struct TextureCache {
    loaded: HashMap<(PathBuf, ColorSpace), Result<Arc<Texture>, String>>,
}

impl TextureCache {
    /// An empty cache.
    pub fn new() -> TextureCache {
        TextureCache::default()
    }

    /// How many distinct (file, colour space) textures are held.
    pub fn len(&self) -> usize {
        self.loaded.values().filter(|t| t.is_ok()).count()
    }

    /// Whether no texture is held.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The texture of `file` in linear Rec.709, or why there is none. An unknown colour
    /// space name is read as the file type's default and reported in `notes`.
    pub fn get(
        &mut self,
        file: &FileValue,
        notes: &mut Vec<String>,
    ) -> Result<Arc<Texture>, String> {
        let Some(path) = &file.asset.resolved else {
            return Err(format!(
                "texture file {:?} does not resolve to a file",
                file.asset.authored
            ));
        };
        let space = match ColorSpace::of(&file.colorspace, path) {
            Some(s) => s,
            None => {
                notes.push(format!(
                    "colour space {:?} of {} is unknown; read as {}",
                    file.colorspace,
                    path.display(),
                    if is_float_format(path) {
                        "lin_rec709"
                    } else {
                        "srgb_texture"
                    }
                ));
                ColorSpace::of("", path).unwrap_or(ColorSpace::Linear)
            }
        };
        self.loaded
            .entry((path.clone(), space))
            .or_insert_with(|| load(path, space))
            .clone()
    }
}

/// Loads `path` and converts its texels from `space` to linear Rec.709. lux's loaders decode
/// integer formats from sRGB and keep float formats as stored, so the encoded value is first
/// recovered (re-encoding to sRGB) where the file's colour space is not sRGB.
fn load(path: &Path, space: ColorSpace) -> Result<Arc<Texture>, String> {
    let tex = crate::assets::load_texture(path).map_err(|e| e.to_string())?;
    let float = is_float_format(path);
    let as_loaded = matches!(
        (float, space),
        (false, ColorSpace::Srgb) | (true, ColorSpace::Linear)
    );
    if as_loaded {
        return Ok(Arc::new(tex));
    }
    let texels = tex
        .texels()
        .iter()
        .map(|t| {
            let encoded = if float {
                [t[0], t[1], t[2]].map(f64::from)
            } else {
                [t[0], t[1], t[2]].map(|x| f64::from(linear_to_srgb(x)))
            };
            let c = decode_texel(space, encoded);
            [c[0] as f32, c[1] as f32, c[2] as f32, t[3]]
        })
        .collect();
    Texture::from_texels(tex.width(), tex.height(), texels)
        .map(Arc::new)
        .map_err(|e| e.to_string())
}

/// How a texture coordinate outside \[0, 1\] is handled (`uaddressmode`, `vaddressmode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Address {
    /// `constant`: the `default` value outside \[0, 1\].
    Constant,
    /// `clamp`: the edge texels.
    Clamp,
    /// `periodic`: repeat.
    Periodic,
    /// `mirror`: repeat, every other tile mirrored.
    Mirror,
}

impl Address {
    /// The mode an address mode string names (`None`: unknown).
    pub(crate) fn of(name: &str) -> Option<Address> {
        Some(match name {
            "constant" => Address::Constant,
            "clamp" => Address::Clamp,
            "periodic" | "" => Address::Periodic,
            "mirror" => Address::Mirror,
            _ => return None,
        })
    }

    /// Texel index `i` folded into `0..n`.
    #[inline]
    fn index(self, i: i64, n: i64) -> usize {
        let j = match self {
            Address::Constant | Address::Clamp => i.clamp(0, n - 1),
            Address::Periodic => i.rem_euclid(n),
            Address::Mirror => {
                let m = i.rem_euclid(2 * n);
                if m >= n { 2 * n - 1 - m } else { m }
            }
        };
        j as usize
    }
}

/// A prepared `image` lookup: the texture in linear Rec.709, address modes, filter.
#[derive(Clone, Debug)]
pub(crate) struct ImageOp {
    pub(crate) tex: Arc<Texture>,
    pub(crate) address: [Address; 2],
    /// `filtertype = "closest"` (else bilinear; `cubic` is read as bilinear).
    pub(crate) closest: bool,
}

impl ImageOp {
    /// The texel value at texture coordinates `uv` ((0, 0) at the image's lower left), or
    /// `default` where a `constant` address mode leaves \[0, 1\] or `uv` is not finite.
    pub(crate) fn sample(&self, uv: DVec2, default: DVec4) -> DVec4 {
        if !uv.is_finite() {
            return default;
        }
        for (k, x) in [uv.x, uv.y].into_iter().enumerate() {
            if self.address[k] == Address::Constant && !(0.0..=1.0).contains(&x) {
                return default;
            }
        }
        let (w, h) = (self.tex.width() as i64, self.tex.height() as i64);
        // Texel (i, j) counted from the lower left; row 0 of the texture is the top.
        let fetch = |i: i64, j: i64| -> DVec4 {
            let x = self.address[0].index(i, w);
            let y = self.address[1].index(j, h);
            let t = self.tex.texel(x, h as usize - 1 - y);
            DVec4::new(t[0].into(), t[1].into(), t[2].into(), t[3].into())
        };
        // Saturating float → integer conversion keeps huge coordinates finite.
        let cell = |x: f64| x.floor().clamp(-1.0e15, 1.0e15) as i64;
        if self.closest {
            return fetch(cell(uv.x * w as f64), cell(uv.y * h as f64));
        }
        let x = uv.x * w as f64 - 0.5;
        let y = uv.y * h as f64 - 0.5;
        let (i0, j0) = (cell(x), cell(y));
        let (tx, ty) = (x - x.floor(), y - y.floor());
        let bottom = fetch(i0, j0) * (1.0 - tx) + fetch(i0 + 1, j0) * tx;
        let top = fetch(i0, j0 + 1) * (1.0 - tx) + fetch(i0 + 1, j0 + 1) * tx;
        bottom * (1.0 - ty) + top * ty
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn address_modes() {
        assert_eq!(Address::Periodic.index(-1, 4), 3);
        assert_eq!(Address::Periodic.index(5, 4), 1);
        assert_eq!(Address::Clamp.index(-3, 4), 0);
        assert_eq!(Address::Mirror.index(4, 4), 3);
        assert_eq!(Address::Mirror.index(-1, 4), 0);
        assert_eq!(Address::Mirror.index(9, 4), 1);
    }

    #[test]
    fn colour_spaces() {
        let p = Path::new("a.png");
        assert_eq!(ColorSpace::of("", p), Some(ColorSpace::Srgb));
        assert_eq!(
            ColorSpace::of("", Path::new("a.EXR")),
            Some(ColorSpace::Linear)
        );
        assert_eq!(ColorSpace::of("bogus", p), None);
        let c = ColorSpace::AcesCg.decode([1.0, 1.0, 1.0]);
        // AP1 white is Rec.709 white (up to the matrix's rounding).
        assert!(c.iter().all(|x| (x - 1.0).abs() < 1e-3));
        assert!((ColorSpace::Gamma22.decode([0.5, 0.0, 0.0])[0] - 0.5f64.powf(2.2)).abs() < 1e-15);
    }
}
