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
        let space = space_of(file, path).unwrap_or_else(|fallback| {
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
            fallback
        });
        self.loaded
            .entry((path.clone(), space))
            .or_insert_with(|| load(path, space))
            .clone()
    }

    /// Loads, in parallel, the files of the `image` and `tiledimage` nodes of `graphs` (those
    /// authored as a constant `file`) that the cache does not hold: what [`TextureCache::get`]
    /// would load for them one by one, failures included.
    pub fn prefetch(&mut self, graphs: &[&lux_usd::shading::ShadingGraph]) {
        use lux_usd::shading::{Source, Value};
        use rayon::prelude::*;
        let mut keys: Vec<(PathBuf, ColorSpace)> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        let nodes = graphs.iter().flat_map(|g| &g.nodes);
        for n in nodes.filter(|n| matches!(n.category.as_str(), "image" | "tiledimage")) {
            let Some(Source::Value(Value::File(file))) = n.input("file").map(|i| &i.source) else {
                continue;
            };
            let Some(path) = &file.asset.resolved else {
                continue;
            };
            let key = (path.clone(), space_of(file, path).unwrap_or_else(|s| s));
            if !self.loaded.contains_key(&key) && seen.insert(key.clone()) {
                keys.push(key);
            }
        }
        let loaded: Vec<_> = keys
            .into_par_iter()
            .map(|(path, space)| {
                let t = load(&path, space);
                ((path, space), t)
            })
            .collect();
        self.loaded.extend(loaded);
    }
}

/// The colour space of the texels of `file` (at `path`); when its name is unknown, `Err` with
/// the file type's default, which is read instead.
fn space_of(file: &FileValue, path: &Path) -> Result<ColorSpace, ColorSpace> {
    ColorSpace::of(&file.colorspace, path)
        .ok_or_else(|| ColorSpace::of("", path).unwrap_or(ColorSpace::Linear))
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
    let (width, height) = (tex.width(), tex.height());
    let mut texels = tex.into_texels();
    // In place, in parallel (each texel on its own: the same values in any order).
    use rayon::prelude::*;
    texels.par_iter_mut().for_each(|t| {
        let encoded = if float {
            [t[0], t[1], t[2]].map(f64::from)
        } else {
            [t[0], t[1], t[2]].map(|x| f64::from(linear_to_srgb(x)))
        };
        let c = decode_texel(space, encoded);
        *t = [c[0] as f32, c[1] as f32, c[2] as f32, t[3]];
    });
    Texture::from_texels(width, height, texels)
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

    /// An `image` node reading `file` (resolved to `path` when given) in `space`.
    fn image_node(authored: &str, path: Option<&Path>, space: &str) -> lux_usd::shading::GraphNode {
        use lux_usd::shading::{GraphInput, GraphNode, Source, Value, ValueType};
        let file = FileValue {
            asset: lux_usd::AssetRef {
                authored: authored.to_owned(),
                resolved: path.map(Path::to_path_buf),
            },
            colorspace: space.to_owned(),
        };
        GraphNode {
            name: format!("/M/{authored}"),
            category: "image".to_owned(),
            nodedef: "ND_image_color3".to_owned(),
            outputs: vec![("out".to_owned(), ValueType::Color3)],
            inputs: vec![GraphInput {
                name: "file".to_owned(),
                ty: ValueType::Filename,
                source: Source::Value(Value::File(file)),
            }],
        }
    }

    /// Prefetching holds what [`TextureCache::get`] would load lazily, once per file and
    /// colour space: the same texels (converted where the space asks), the same failure.
    #[test]
    fn prefetched_textures_are_those_get_loads() {
        let dir = std::env::temp_dir().join(format!("lux_prefetch_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let png = dir.join("a.png");
        let px = image::RgbaImage::from_fn(3, 2, |x, y| {
            image::Rgba([40 * x as u8, 90, 7 * y as u8, 255])
        });
        px.save(&png).unwrap();
        let missing = dir.join("gone.png");
        let nodes = vec![
            image_node("a.png", Some(&png), ""),
            image_node("a.png", Some(&png), "lin_rec709"),
            image_node("a.png", Some(&png), ""),
            image_node("gone.png", Some(&missing), ""),
            image_node("none.png", None, ""),
        ];
        let g = lux_usd::shading::ShadingGraph {
            nodes: nodes.clone(),
            ..Default::default()
        };
        let mut pre = TextureCache::new();
        pre.prefetch(&[&g]);
        assert_eq!(pre.loaded.len(), 3, "two spaces of a.png and the failure");
        let mut lazy = TextureCache::new();
        for n in &nodes {
            let Some(lux_usd::shading::Source::Value(lux_usd::shading::Value::File(f))) =
                n.input("file").map(|i| &i.source)
            else {
                unreachable!()
            };
            let (mut n1, mut n2) = (Vec::new(), Vec::new());
            let (a, b) = (pre.get(f, &mut n1), lazy.get(f, &mut n2));
            assert_eq!(n1, n2);
            match (a, b) {
                (Ok(a), Ok(b)) => assert_eq!(*a, *b),
                (Err(a), Err(b)) => assert_eq!(a, b),
                (a, b) => panic!("{a:?} against {b:?}"),
            }
        }
        assert_eq!(pre.loaded.len(), lazy.loaded.len());
        std::fs::remove_dir_all(&dir).unwrap();
    }

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
