//! `lux merge TILE.exr… -o OUT.exr`: assembles the tiles of `lux render --tile I/N` into the
//! frame, after checking they belong together; the output is written atomically.

use crate::cli::render::PngEncoding;
use crate::cli::tile::{
    ATTR_FRAME, ATTR_RESOLUTION, ATTR_ROWS, ATTR_SCENE, ATTR_SETTINGS, ATTR_TILE, FrameHeader,
    TileSpec, create_parent, parse_tile,
};
use clap::Args;
use lux_render::image_io::{ExrBand, ImageRgba, read_exr_band};
use std::path::{Path, PathBuf};

/// Arguments of `lux merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The tiles (EXR files of `lux render --tile I/N`), in any order.
    #[arg(required = true)]
    pub tiles: Vec<PathBuf>,
    /// Output EXR (RGBA float32, linear), equal bit for bit to the single-process render.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Also write an sRGB PNG (what `lux render --png` writes for the whole frame).
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// How the PNG is encoded (as `lux render`'s).
    #[command(flatten)]
    pub png_encoding: PngEncoding,
    /// Force the outputs to disk before they replace their targets (as `lux render --fsync`).
    #[arg(long)]
    pub fsync: bool,
}

/// The attributes every tile of a frame must share.
const SHARED: [&str; 4] = [ATTR_SCENE, ATTR_FRAME, ATTR_SETTINGS, ATTR_RESOLUTION];

/// One tile read and checked on its own.
struct Tile {
    path: PathBuf,
    spec: TileSpec,
    band: ExrBand,
}

fn attr<'a>(band: &'a ExrBand, path: &Path, name: &str) -> Result<&'a str, String> {
    band.attributes
        .get(name)
        .map(String::as_str)
        .ok_or_else(|| {
            format!(
                "{}: not a lux tile (no {name} attribute; render it with `lux render --tile I/N`)",
                path.display()
            )
        })
}

/// Reads `path` and checks it against itself: a tile attribute, rows and data window matching
/// band I of N of the recorded resolution.
fn read_tile(path: &Path) -> Result<Tile, String> {
    let band = read_exr_band(path).map_err(|e| e.to_string())?;
    for name in SHARED {
        attr(&band, path, name)?;
    }
    let spec = parse_tile(attr(&band, path, ATTR_TILE)?)
        .map_err(|e| format!("{}: {ATTR_TILE}: {e}", path.display()))?;
    let resolution = attr(&band, path, ATTR_RESOLUTION)?;
    let [w, h] = band.display;
    let [y0, y1] = spec.rows(h as u32);
    let rows = attr(&band, path, ATTR_ROWS)?;
    let expected_rows = format!("{y0}-{}", y1.saturating_sub(1));
    let consistent = resolution == format!("{w}x{h}")
        && rows == expected_rows
        && band.image.width == w
        && band.y0 == y0 as usize
        && band.image.height == (y1 - y0) as usize;
    if !consistent {
        return Err(format!(
            "{}: tile {spec} of a {resolution} frame should hold rows {expected_rows} of a \
             {w}×{h} display window, but holds {} rows from row {} ({ATTR_ROWS} {rows})",
            path.display(),
            band.image.height,
            band.y0
        ));
    }
    Ok(Tile {
        path: path.to_path_buf(),
        spec,
        band,
    })
}

/// Reads and checks `paths`: the same scene, frame, settings and resolution, tiles 0 to N − 1
/// each exactly once. Returns the frame and its header.
pub fn assemble(paths: &[PathBuf]) -> Result<(ImageRgba, FrameHeader), String> {
    let tiles = paths
        .iter()
        .map(|p| read_tile(p))
        .collect::<Result<Vec<_>, _>>()?;
    let first = tiles.first().ok_or("no tiles given")?;
    let count = first.spec.count;
    let mut seen: Vec<Option<&Path>> = vec![None; count as usize];
    for t in &tiles {
        for name in SHARED {
            let (a, b) = (&first.band.attributes[name], &t.band.attributes[name]);
            if a != b {
                return Err(format!(
                    "{}: {name} is {b:?}, but {} has {a:?}: the tiles are not of one render",
                    t.path.display(),
                    first.path.display()
                ));
            }
        }
        if t.spec.count != count {
            return Err(format!(
                "{}: tile {} is one of {} tiles, but {} is one of {count}",
                t.path.display(),
                t.spec,
                t.spec.count,
                first.path.display()
            ));
        }
        let slot = &mut seen[t.spec.index as usize];
        if let Some(other) = slot {
            return Err(format!(
                "{}: tile {} is given twice (also {})",
                t.path.display(),
                t.spec,
                other.display()
            ));
        }
        *slot = Some(&t.path);
    }
    let missing: Vec<String> = seen
        .iter()
        .enumerate()
        .filter(|(_, s)| s.is_none())
        .map(|(i, _)| format!("{i}/{count}"))
        .collect();
    if !missing.is_empty() {
        return Err(format!(
            "tile{} {} missing (given: {})",
            if missing.len() > 1 { "s" } else { "" },
            missing.join(", "),
            paths
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    let [w, h] = first.band.display;
    let mut pixels = vec![[0.0f32; 4]; w * h];
    for t in &tiles {
        let y0 = t.band.y0;
        pixels[y0 * w..(y0 + t.band.image.height) * w].copy_from_slice(&t.band.image.pixels);
    }
    let header = FrameHeader {
        attributes: SHARED
            .iter()
            .map(|&n| (n.to_owned(), first.band.attributes[n].clone()))
            .collect(),
    };
    Ok((
        ImageRgba {
            width: w,
            height: h,
            pixels,
        },
        header,
    ))
}

/// Merges according to `args`: the EXR (and PNG) appear together or not at all.
pub fn run(args: &MergeArgs) -> Result<(), String> {
    args.png_encoding.check()?;
    let (image, header) = assemble(&args.tiles)?;
    create_parent(&args.output)?;
    let exr = crate::cli::tile::stage_exr(&args.output, &image, &header, None)?;
    let png = match &args.png {
        Some(png) => {
            create_parent(png)?;
            Some(args.png_encoding.stage(png, &image)?)
        }
        None => None,
    };
    let commit = |file: lux_render::image_io::StagedFile| {
        if args.fsync {
            file.commit_durable()
        } else {
            file.commit()
        }
        .map_err(|e| e.to_string())
    };
    commit(exr)?;
    if let Some(png) = png {
        commit(png)?;
    }
    eprintln!(
        "lux: merged {} tiles into {}{}",
        args.tiles.len(),
        args.output.display(),
        args.png
            .as_ref()
            .map(|p| format!(" and {}", p.display()))
            .unwrap_or_default()
    );
    Ok(())
}
