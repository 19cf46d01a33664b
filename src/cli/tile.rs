//! `lux render --tile I/N`: one horizontal band of a frame, with the header attributes that let
//! `lux merge` check that tiles belong together (scene, frame, pixel-affecting settings,
//! resolution).

use crate::cli::render::RenderArgs;
use lux_render::image_io::{ImageRgba, StagedFile, stage_exr_band};
use lux_render::render::{RenderOptions, Renderer};
use std::path::Path;

/// Attribute: the scene (the canonical path of the root layer).
pub const ATTR_SCENE: &str = "lux:scene";
/// Attribute: the time code rendered.
pub const ATTR_FRAME: &str = "lux:frame";
/// Attribute: every option that affects pixels, canonically ([`settings_string`]).
pub const ATTR_SETTINGS: &str = "lux:settings";
/// Attribute: the frame's resolution `WxH`.
pub const ATTR_RESOLUTION: &str = "lux:resolution";
/// Attribute: the tile `I/N` (tiles only).
pub const ATTR_TILE: &str = "lux:tile";
/// Attribute: the tile's rows `y0-y1` (inclusive; tiles only).
pub const ATTR_ROWS: &str = "lux:rows";

/// `--tile I/N`: band `index` of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TileSpec {
    /// The band, `0..count`.
    pub index: u32,
    /// How many bands the frame is split into.
    pub count: u32,
}

impl TileSpec {
    /// Band `index` of `count` over `height` rows: rows ⌊I·H/N⌋ … ⌊(I+1)·H/N⌋ − 1, end exclusive.
    pub fn rows(&self, height: u32) -> [u32; 2] {
        let at = |i: u32| (u64::from(i) * u64::from(height) / u64::from(self.count)) as u32;
        [at(self.index), at(self.index + 1)]
    }
}

impl std::fmt::Display for TileSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// Parses `I/N` with `0 ≤ I < N`.
pub fn parse_tile(s: &str) -> Result<TileSpec, String> {
    let (i, n) = s
        .split_once('/')
        .ok_or_else(|| format!("tile {s:?}: expected I/N, e.g. 0/4"))?;
    let num = |p: &str| {
        p.trim()
            .parse::<u32>()
            .map_err(|_| format!("tile {s:?}: {p:?} is not a non-negative integer"))
    };
    let (index, count) = (num(i)?, num(n)?);
    if count == 0 || index >= count {
        return Err(format!("tile {s}: expected 0 ≤ I < N and N ≥ 1"));
    }
    Ok(TileSpec { index, count })
}

/// A canonical string of every option that affects pixels (and the lux version that made them):
/// tiles merge only when theirs are equal.
pub fn settings_string(options: &RenderOptions, camera_light: bool) -> String {
    let crop = options
        .crop
        .map_or("none".to_owned(), |[a, b, c, d]| format!("{a},{b},{c},{d}"));
    let resolution = options
        .resolution
        .map_or("default".to_owned(), |[w, h]| format!("{w}x{h}"));
    let lower = |d: &dyn std::fmt::Debug| format!("{d:?}").to_ascii_lowercase();
    let adaptive = match options.adaptive() {
        a if a.is_on() => format!(
            "{}x{}:{}:splits{}",
            a.threshold,
            a.max_factor,
            format!("{:?}", a.measure).to_ascii_lowercase(),
            a.max_splits
        ),
        _ => "off".to_owned(),
    };
    format!(
        "lux={};spp={};resolution={resolution};crop={crop};camera={};camera_light={camera_light};\
         profile={};sampling={};integrator={};max_depth={};path_splits={};surfaces={};light_selection={};\
         light_samples={};penumbra_samples={};shadow_rays={};adaptive={adaptive};cone_clipping={};visibility={};seed={};strict={}",
        env!("CARGO_PKG_VERSION"),
        options.spp,
        options.camera.as_deref().unwrap_or("default"),
        options.profile.profile,
        lower(&options.sampling),
        lower(&options.integrator),
        options.max_depth,
        options.path_splits,
        lower(&options.surfaces),
        lower(&options.selection),
        options.light_samples(),
        options.penumbra_samples,
        options.shadow_rays,
        options.cone_clipping,
        lower(&options.visibility),
        options.seed,
        options.strict,
    )
}

/// What a rendered frame records in its EXR header (tiles add `lux:tile` and `lux:rows`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FrameHeader {
    /// `lux:scene`, `lux:frame`, `lux:settings`, `lux:resolution`, in that order.
    pub attributes: Vec<(String, String)>,
}

impl FrameHeader {
    /// The header of a render of `scene` with `options` (resolution already resolved).
    pub fn new(args: &RenderArgs, scene: &lux_usd::Scene, options: &RenderOptions) -> Self {
        let scene_path = std::fs::canonicalize(&args.scene).unwrap_or_else(|_| args.scene.clone());
        let resolution = options
            .resolution
            .map_or("default".to_owned(), |[w, h]| format!("{w}x{h}"));
        FrameHeader {
            attributes: vec![
                (ATTR_SCENE.into(), scene_path.to_string_lossy().into_owned()),
                (ATTR_FRAME.into(), scene.frame.to_string()),
                (
                    ATTR_SETTINGS.into(),
                    settings_string(options, !args.disable_camera_light),
                ),
                (ATTR_RESOLUTION.into(), resolution),
            ],
        }
    }
}

/// Restricts `renderer` to the rows of `--tile` (if given); returns those rows `[y0, y1)`.
/// Errors when a tile is combined with `--png` or a non-EXR output, or has no rows.
pub fn restrict(
    renderer: &mut Renderer<'_>,
    args: &RenderArgs,
) -> Result<Option<[u32; 2]>, String> {
    let Some(tile) = args.tile else {
        return Ok(None);
    };
    if args.png.is_some() {
        return Err(format!(
            "--tile {tile}: tiles are EXR only; `lux merge --png` writes the PNG"
        ));
    }
    let exr = args
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if !exr {
        return Err(format!(
            "--tile {tile}: -o {}: a tile is written as .exr",
            args.output.display()
        ));
    }
    let [_, h] = renderer.resolution();
    if tile.count > h {
        return Err(format!(
            "--tile {tile}: {} tiles exceed the image height of {h} rows",
            tile.count
        ));
    }
    let rows = tile.rows(h);
    renderer.restrict_rows(rows);
    Ok(Some(rows))
}

/// Stages the EXR of a render: the whole frame, or the rows of a tile (with `lux:tile` and
/// `lux:rows`), its header recording `header`. A tile's output directory is created if missing.
pub fn stage_exr(
    path: &Path,
    image: &ImageRgba,
    header: &FrameHeader,
    tile: Option<(TileSpec, [u32; 2])>,
) -> Result<StagedFile, String> {
    let mut attributes = header.attributes.clone();
    let Some((spec, [y0, y1])) = tile else {
        return stage_exr_band(path, image, 0, image.height, &attributes)
            .map_err(|e| e.to_string());
    };
    attributes.push((ATTR_TILE.into(), spec.to_string()));
    attributes.push((ATTR_ROWS.into(), format!("{y0}-{}", y1 - 1)));
    let (y0, y1) = (y0 as usize, y1 as usize);
    let band = ImageRgba {
        width: image.width,
        height: y1 - y0,
        pixels: image.pixels[y0 * image.width..y1 * image.width].to_vec(),
    };
    create_parent(path)?;
    stage_exr_band(path, &band, y0, image.height, &attributes).map_err(|e| e.to_string())
}

/// Creates `path`'s directory if it does not exist (farm outputs go to fresh directories).
pub fn create_parent(path: &Path) -> Result<(), String> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() && !dir.exists() => std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create the directory {}: {e}", dir.display())),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_cover_the_rows_once() {
        for h in 1..40 {
            for n in 1..=h {
                let mut next = 0;
                for i in 0..n {
                    let [a, b] = TileSpec { index: i, count: n }.rows(h);
                    assert_eq!(a, next);
                    assert!(b > a);
                    next = b;
                }
                assert_eq!(next, h);
            }
        }
    }

    #[test]
    fn parses_tiles() {
        assert_eq!(parse_tile("2/3"), Ok(TileSpec { index: 2, count: 3 }));
        assert!(parse_tile("3/3").is_err());
        assert!(parse_tile("0/0").is_err());
        assert!(parse_tile("1").is_err());
        assert!(parse_tile("-1/3").is_err());
    }
}
