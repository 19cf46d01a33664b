//! Decoding image files into linear RGBA `f32` texels (row 0 = top).

use std::fs::File;
use std::io::{Cursor, Read, Seek, SeekFrom};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use exr::block::samples::FromNativeSample;
use exr::prelude::{ReadChannels, ReadLayers, RgbaChannels, Vec2, f16};
use image::{DynamicImage, ImageFormat, ImageReader, Limits};

use super::{ImageError, MAX_DIMENSION, MAX_PIXELS, check_dimensions, srgb_to_linear_f64};

/// What an OpenEXR texture file must contain.
const EXPECTED_EXR: &str =
    "an OpenEXR file with a flat layer holding R, G and B channels (A optional)";

/// A readable, seekable, sendable byte stream (what both decoders accept).
pub(crate) trait ReadSeek: Read + Seek + Send {}
impl<T: Read + Seek + Send> ReadSeek for T {}

/// Where an image's bytes come from: a file, or memory (an entry of a `.usdz` package). `path`
/// names it in errors and gives the format by its extension.
#[derive(Clone, Copy)]
pub(crate) struct Source<'a> {
    path: &'a Path,
    bytes: Option<&'a [u8]>,
}

impl<'a> Source<'a> {
    /// The file at `path`.
    pub(crate) fn file(path: &'a Path) -> Self {
        Source { path, bytes: None }
    }

    /// In-memory `bytes`, named `path`.
    pub(crate) fn memory(path: &'a Path, bytes: &'a [u8]) -> Self {
        Source {
            path,
            bytes: Some(bytes),
        }
    }

    fn open(&self) -> std::io::Result<Box<dyn ReadSeek + 'a>> {
        Ok(match self.bytes {
            Some(b) => Box::new(Cursor::new(b)),
            None => Box::new(File::open(self.path)?),
        })
    }
}

/// Decoded texels with their `width` and `height`: `f32`, or the `f16` of an OpenEXR file
/// whose R, G, B (and A) channels are half floats, as stored. Non-finite values are left to
/// the caller.
pub(crate) enum Decoded {
    F32(usize, usize, Vec<[f32; 4]>),
    /// A half-float file's RGBA as stored (`f16` bits); `Some(n)`: its non-finite values
    /// already replaced by 0, `n` of them.
    F16(usize, usize, Vec<[u16; 4]>, Option<usize>),
    /// A half-float file's RGB without alpha (alpha 1), as [`Decoded::F16`].
    F16Rgb(usize, usize, Vec<[u16; 3]>, Option<usize>),
    /// 8-bit sRGB codes (grey expanded to RGB, alpha 255 where there is none): colour decodes
    /// through [`srgb8_table`], alpha is `a / 255`.
    Srgb8(usize, usize, Vec<[u8; 4]>),
    /// 8-bit grey sRGB codes, no alpha: the texel `[l, l, l, 1]` of each code's value `l`.
    Grey8(usize, usize, Vec<u8>),
}

/// How a file is decoded, by its (case-insensitive) extension.
enum Format {
    Exr,
    /// An `image` crate format and what such a file must be.
    Image(ImageFormat, &'static str),
}

/// The decoder of `path` by extension; [`ImageError::UnsupportedFormat`] for others.
fn format_of(path: &Path) -> Result<Format, ImageError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    Ok(match ext.as_deref() {
        Some("exr") => Format::Exr,
        Some("png") => Format::Image(ImageFormat::Png, "a PNG image"),
        Some("jpg" | "jpeg") => Format::Image(ImageFormat::Jpeg, "a JPEG image"),
        Some("hdr") => Format::Image(ImageFormat::Hdr, "a Radiance HDR (RGBE) image"),
        Some("tga") => Format::Image(ImageFormat::Tga, "a Truevision TGA image"),
        Some("bmp") => Format::Image(ImageFormat::Bmp, "a BMP image"),
        _ => {
            return Err(ImageError::UnsupportedFormat {
                path: path.to_path_buf(),
            });
        }
    })
}

/// Loads the image of `src` by extension.
pub(crate) fn load_texels(src: Source<'_>) -> Result<Decoded, ImageError> {
    let path = src.path;
    match format_of(path)? {
        Format::Exr => guarded(path, EXPECTED_EXR, || load_exr(src)),
        Format::Image(format, expected) => {
            guarded(path, expected, || load_with_image(src, format, expected))
        }
    }
}

/// Checks what [`load_texels`] checks before it decodes `src`: a format lux decodes (by
/// extension), a header that parses, dimensions within the limits (and, for OpenEXR, a layer
/// with R, G and B channels). Reads the header only: the pixel data may still turn out corrupt
/// when decoded.
pub(crate) fn probe_texels(src: Source<'_>) -> Result<(), ImageError> {
    let path = src.path;
    match format_of(path)? {
        Format::Exr => guarded(path, EXPECTED_EXR, || {
            let mut file = src.open().map_err(|e| io_read_error(path, e))?;
            let meta = exr_header(path, &mut file)?;
            // (the layer the readers take: the first with R, G and B)
            let rgb = |h: &exr::meta::header::Header| {
                ["R", "G", "B"]
                    .iter()
                    .all(|n| h.channels.list.iter().any(|c| c.name.eq(n)))
            };
            if !meta.headers.iter().any(rgb) {
                return Err(ImageError::Decode {
                    path: path.to_path_buf(),
                    expected: EXPECTED_EXR,
                    message: "no layer holds R, G and B channels".to_string(),
                });
            }
            Ok(())
        }),
        Format::Image(format, expected) => {
            guarded(path, expected, || image_header(src, format, expected))
        }
    }
}

/// Runs a decoder, turning a panic inside it into [`ImageError::Decode`].
fn guarded<T>(
    path: &Path,
    expected: &'static str,
    f: impl FnOnce() -> Result<T, ImageError>,
) -> Result<T, ImageError> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(result) => result,
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_string());
            Err(ImageError::Decode {
                path: path.to_path_buf(),
                expected,
                message: format!("the decoder panicked: {what}"),
            })
        }
    }
}

fn io_read_error(path: &Path, source: std::io::Error) -> ImageError {
    ImageError::Io {
        path: path.to_path_buf(),
        action: "read",
        source,
    }
}

// ---------------------------------------------------------------------------------------------
// OpenEXR
// ---------------------------------------------------------------------------------------------

/// Pixel storage filled by the `exr` reader's callbacks.
struct ExrPixels<T, const N: usize> {
    width: usize,
    texels: Vec<[T; N]>,
    /// How many pixels the file actually delivered (to detect missing blocks).
    written: usize,
}

pub(crate) fn exr_error(path: &Path, error: exr::error::Error) -> ImageError {
    use exr::error::Error;
    match error {
        // A short read means a truncated file: a decoding problem, not an OS one.
        Error::Io(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => ImageError::Decode {
            path: path.to_path_buf(),
            expected: EXPECTED_EXR,
            message: "unexpected end of file (truncated?)".to_string(),
        },
        Error::Io(e) => io_read_error(path, e),
        other => ImageError::Decode {
            path: path.to_path_buf(),
            expected: EXPECTED_EXR,
            message: other.to_string(),
        },
    }
}

fn load_exr(src: Source<'_>) -> Result<Decoded, ImageError> {
    let path = src.path;
    let mut file = src.open().map_err(|e| io_read_error(path, e))?;
    let meta = exr_header(path, &mut file)?;
    file.seek(SeekFrom::Start(0))
        .map_err(|e| io_read_error(path, e))?;
    // The layer the reader takes, the first with R, G and B: kept in `f16` when those (and A)
    // are half floats (three a texel without A), else widened to `f32` as every other format.
    let half = meta.headers.iter().find_map(|h| {
        let ch = |n: &str| h.channels.list.iter().find(|c| c.name.eq(n));
        let rgb = [ch("R")?, ch("G")?, ch("B")?];
        let f16 = exr::meta::attribute::SampleType::F16;
        let alpha = ch("A");
        let half = rgb
            .iter()
            .chain(alpha.as_ref())
            .all(|c| c.sample_type == f16);
        Some((half, alpha.is_some()))
    });
    match half {
        Some((true, true)) => {
            let (w, h, t, bad) = read_half::<4>(src, &meta, file)?;
            return Ok(Decoded::F16(w, h, t, bad));
        }
        Some((true, false)) => {
            let (w, h, t, bad) = read_half::<3>(src, &meta, file)?;
            return Ok(Decoded::F16Rgb(w, h, t, bad));
        }
        _ => {}
    }
    let (w, h, t) = read_exr::<f32, 4>(path, file)?;
    Ok(Decoded::F32(w, h, t))
}

/// The header of the OpenEXR file `file` (at `path`), every layer's size checked before a
/// reader allocates anything.
fn exr_header(
    path: &Path,
    file: &mut Box<dyn ReadSeek + '_>,
) -> Result<exr::meta::MetaData, ImageError> {
    let meta =
        exr::meta::MetaData::read_from_unbuffered(file, false).map_err(|e| exr_error(path, e))?;
    if meta.headers.is_empty() {
        return Err(ImageError::Decode {
            path: path.to_path_buf(),
            expected: EXPECTED_EXR,
            message: "the file has no layers".to_string(),
        });
    }
    for header in meta.headers.iter() {
        check_dimensions(path, header.layer_size.0 as u64, header.layer_size.1 as u64)?;
    }
    Ok(meta)
}

/// A half-float file's texels (`N` channels, R G B [A]) as bits: by [`half_scanlines`], else
/// by the general reader (opening `src` again), its non-finite values then left in place
/// (`None`) for the caller.
#[allow(clippy::type_complexity)]
fn read_half<const N: usize>(
    src: Source<'_>,
    meta: &exr::meta::MetaData,
    file: Box<dyn ReadSeek + '_>,
) -> Result<(usize, usize, Vec<[u16; N]>, Option<usize>), ImageError> {
    if let Some((w, h, t, bad)) = half_scanlines::<N>(meta, file) {
        return Ok((w, h, t, Some(bad)));
    }
    let file = src.open().map_err(|e| io_read_error(src.path, e))?;
    let (w, h, t) = read_exr::<f16, N>(src.path, file)?;
    // (`f16` to its bits in place: same size and alignment, no copy)
    Ok((
        w,
        h,
        t.into_iter().map(|p| p.map(f16::to_bits)).collect(),
        None,
    ))
}

/// The fast path of the common half-float texture: a single flat layer of scan-line blocks
/// (one resolution level) whose R, G, B (and, with `N` = 4, A) channels are `f16` at full
/// resolution. Its blocks are decompressed in parallel (`exr`'s block API, on rayon's
/// threads), each straight into the rows it covers, instead of `exr`'s per-pixel callbacks
/// and a thread pool of its own for every file (a third of the StandardShaderBall's load).
/// The texels are the values' bits, NaN and ±∞ replaced by 0 as they are written (how many:
/// the last element). `None` when the file is of another kind or anything in it is amiss: the
/// general reader then reads it (and names what is wrong).
fn half_scanlines<const N: usize>(
    meta: &exr::meta::MetaData,
    file: Box<dyn ReadSeek + '_>,
) -> Option<(usize, usize, Vec<[u16; N]>, usize)> {
    use exr::block::UncompressedBlock;
    use exr::block::chunk::CompressedBlock;
    use exr::meta::BlockDescription;
    use exr::meta::attribute::SampleType;
    use rayon::prelude::*;

    let [header] = meta.headers.as_slice() else {
        return None;
    };
    if header.deep || !matches!(header.blocks, BlockDescription::ScanLines) {
        return None;
    }
    // Each channel's slot in a texel (R, G, B, A), or none (other channels are skipped).
    let slot: Vec<Option<usize>> = header
        .channels
        .list
        .iter()
        .map(|c| ["R", "G", "B", "A"][..N].iter().position(|n| c.name.eq(n)))
        .collect();
    let full = |c: &exr::meta::attribute::ChannelDescription| c.sampling == Vec2(1, 1);
    if !header.channels.list.iter().all(full)
        || (0..N).any(|k| {
            header
                .channels
                .list
                .iter()
                .zip(&slot)
                .filter(|(c, s)| **s == Some(k) && c.sample_type == SampleType::F16)
                .count()
                != 1
        })
    {
        return None;
    }
    let (w, h) = (header.layer_size.width(), header.layer_size.height());
    let rows = header.compression.scan_lines_per_block();
    if w == 0 || h == 0 || w > MAX_DIMENSION || h > MAX_DIMENSION || w * h > MAX_PIXELS {
        return None;
    }
    let y0 = header.own_attributes.layer_position.y();
    // The compressed blocks, each at its place (every block once, or the general reader).
    let reader = exr::block::read(std::io::BufReader::new(file), false).ok()?;
    let mut chunks: Vec<Option<exr::block::chunk::Chunk>> = vec![None; h.div_ceil(rows)];
    for chunk in reader.all_chunks(false).ok()? {
        let chunk = chunk.ok()?;
        let CompressedBlock::ScanLine(b) = &chunk.compressed_block else {
            return None;
        };
        let dy = usize::try_from(i64::from(b.y_coordinate) - i64::from(y0)).ok()?;
        let at = chunks
            .get_mut(dy / rows)
            .filter(|c| dy % rows == 0 && c.is_none())?;
        *at = Some(chunk);
    }
    if chunks.iter().any(Option::is_none) {
        return None;
    }
    // (zeros: pages the allocator hands over already zeroed, first touched by the decoding)
    let mut texels = vec![[0u16; N]; w * h];
    let bad = texels
        .par_chunks_mut(w * rows)
        .zip(chunks.into_par_iter())
        .map(|(out, chunk)| {
            let block = UncompressedBlock::decompress_chunk(chunk?, meta, false).ok()?;
            let by = block.index.pixel_position.y();
            let mut line_samples = vec![f16::ZERO; w];
            let (mut filled, mut bad) = (0, 0);
            for line in block.lines(&header.channels) {
                let at = line.location;
                let Some(k) = slot.get(at.channel).copied().flatten() else {
                    continue;
                };
                let row = at.position.y().checked_sub(by)?;
                if at.position.x() != 0 || at.sample_count != w || (row + 1) * w > out.len() {
                    return None;
                }
                if line.read_samples_into_slice(&mut line_samples).is_err() {
                    return None;
                }
                for (t, v) in out[row * w..(row + 1) * w].iter_mut().zip(&line_samples) {
                    let b = v.to_bits();
                    let finite = super::half_finite(b);
                    bad += usize::from(!finite);
                    t[k] = if finite { b } else { 0 };
                }
                filled += w;
            }
            (filled == out.len() * N).then_some(bad)
        })
        .try_reduce(|| 0, |a, b| Some(a + b))?;
    Some((w, h, texels, bad))
}

/// Reads the first layer of `file` with R, G and B channels (A optional, 1 without) at its
/// largest resolution level, as samples of type `T`: RGBA (`N` = 4) or RGB (3).
fn read_exr<T: FromNativeSample + Send + Sync, const N: usize>(
    path: &Path,
    file: Box<dyn ReadSeek + '_>,
) -> Result<(usize, usize, Vec<[T; N]>), ImageError> {
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |size: Vec2<usize>, _channels: &RgbaChannels| {
                let (w, h) = (size.width(), size.height());
                // Already checked against the header; stay defensive anyway.
                let ok = w <= MAX_DIMENSION && h <= MAX_DIMENSION && w * h <= MAX_PIXELS;
                ExrPixels {
                    width: w,
                    // Zeros (pages the allocator hands over already zeroed): the reader sets
                    // every pixel, alpha 1 where the file has none, or the file is refused.
                    texels: if ok {
                        vec![[T::default(); N]; w * h]
                    } else {
                        Vec::new()
                    },
                    written: 0,
                }
            },
            |pixels: &mut ExrPixels<T, N>, pos: Vec2<usize>, (r, g, b, a): (T, T, T, T)| {
                let index = pos.y() * pixels.width + pos.x();
                if pos.x() < pixels.width
                    && let Some(texel) = pixels.texels.get_mut(index)
                {
                    let rgba = [r, g, b, a];
                    *texel = std::array::from_fn(|i| rgba[i]);
                    pixels.written += 1;
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_unbuffered(file)
        .map_err(|e| exr_error(path, e))?;

    let layer = image.layer_data;
    let (width, height) = (layer.size.width(), layer.size.height());
    check_dimensions(path, width as u64, height as u64)?;
    let pixels = layer.channel_data.pixels;
    if pixels.texels.len() != width * height || pixels.written != width * height {
        return Err(ImageError::Decode {
            path: path.to_path_buf(),
            expected: EXPECTED_EXR,
            message: format!(
                "only {} of the {}×{} pixels are present in the file",
                pixels.written, width, height
            ),
        });
    }
    Ok((width, height, pixels.texels))
}

// ---------------------------------------------------------------------------------------------
// PNG, JPEG, Radiance HDR (image crate)
// ---------------------------------------------------------------------------------------------

fn image_error(path: &Path, expected: &'static str, error: image::ImageError) -> ImageError {
    match error {
        image::ImageError::IoError(e) if e.kind() != std::io::ErrorKind::UnexpectedEof => {
            io_read_error(path, e)
        }
        image::ImageError::IoError(_) => ImageError::Decode {
            path: path.to_path_buf(),
            expected,
            message: "unexpected end of file (truncated?)".to_string(),
        },
        other => ImageError::Decode {
            path: path.to_path_buf(),
            expected,
            message: other.to_string(),
        },
    }
}

/// The width and height in a PNG's IHDR chunk, or `None` if the file does not start with a PNG
/// signature followed by an IHDR chunk (the decoder then reports the problem).
fn png_ihdr_dimensions(src: Source<'_>) -> Result<Option<(u32, u32)>, ImageError> {
    const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];
    let path = src.path;
    let file = src.open().map_err(|e| io_read_error(path, e))?;
    let mut head = Vec::with_capacity(24);
    file.take(24)
        .read_to_end(&mut head)
        .map_err(|e| io_read_error(path, e))?;
    if head.len() < 24 || head[..8] != SIGNATURE || &head[12..16] != b"IHDR" {
        return Ok(None);
    }
    let be = |b: &[u8]| u32::from_be_bytes([b[0], b[1], b[2], b[3]]);
    Ok(Some((be(&head[16..20]), be(&head[20..24]))))
}

/// Opens `path` for decoding as `format`; with `limits`, the decoder refuses images beyond
/// the size limits (without them it is only fit for reading the header).
fn open_reader<'a>(
    src: Source<'a>,
    format: ImageFormat,
    limits: bool,
) -> Result<ImageReader<std::io::BufReader<Box<dyn ReadSeek + 'a>>>, ImageError> {
    let path = src.path;
    let mut reader = ImageReader::new(std::io::BufReader::new(
        src.open().map_err(|e| io_read_error(path, e))?,
    ));
    reader.set_format(format);
    if !limits {
        reader.no_limits();
        return Ok(reader);
    }
    let mut limits = Limits::default();
    limits.max_image_width = Some(MAX_DIMENSION as u32);
    limits.max_image_height = Some(MAX_DIMENSION as u32);
    // Room for the largest allowed image at 16 bits × 4 channels, plus decoder overhead.
    limits.max_alloc = Some(MAX_PIXELS as u64 * 8 + (256 << 20));
    reader.limits(limits);
    Ok(reader)
}

/// Checks the header of an `image` crate file: absurd sizes are rejected (with lux's own
/// error) before a decoder allocates the pixel buffer. PNG's IHDR is read directly, since the
/// decoder refuses (with a less specific error) sizes it deems too large even for reading the
/// header.
fn image_header(
    src: Source<'_>,
    format: ImageFormat,
    expected: &'static str,
) -> Result<(), ImageError> {
    let path = src.path;
    if format == ImageFormat::Png
        && let Some((w, h)) = png_ihdr_dimensions(src)?
    {
        check_dimensions(path, u64::from(w), u64::from(h))?;
    }
    let (w, h) = open_reader(src, format, false)?
        .into_dimensions()
        .map_err(|e| image_error(path, expected, e))?;
    check_dimensions(path, u64::from(w), u64::from(h))
}

fn load_with_image(
    src: Source<'_>,
    format: ImageFormat,
    expected: &'static str,
) -> Result<Decoded, ImageError> {
    let path = src.path;
    image_header(src, format, expected)?;
    let image = open_reader(src, format, true)?
        .decode()
        .map_err(|e| image_error(path, expected, e))?;
    let (width, height) = (image.width() as usize, image.height() as usize);
    check_dimensions(path, width as u64, height as u64)?;
    if format != ImageFormat::Hdr {
        if let DynamicImage::ImageLuma8(img) = image {
            return Ok(Decoded::Grey8(width, height, img.into_raw()));
        }
        if let Some(codes) = srgb8_codes(&image) {
            return Ok(Decoded::Srgb8(width, height, codes));
        }
    }
    // (an 8-bit image of a float format, which no decoder gives, is normalised as linear
    // by `into_rgba32f`)
    let texels = dynamic_to_linear(image, format != ImageFormat::Hdr);
    Ok(Decoded::F32(width, height, texels))
}

/// The codes of an 8-bit colour or grey + alpha image as RGBA (grey expanded, alpha 255 where
/// there is none); `None` for other images (grey alone is kept as [`Decoded::Grey8`]).
fn srgb8_codes(image: &DynamicImage) -> Option<Vec<[u8; 4]>> {
    Some(match image {
        DynamicImage::ImageLumaA8(img) => img
            .pixels()
            .map(|p| [p.0[0], p.0[0], p.0[0], p.0[1]])
            .collect(),
        DynamicImage::ImageRgb8(img) => img
            .pixels()
            .map(|p| [p.0[0], p.0[1], p.0[2], 255])
            .collect(),
        DynamicImage::ImageRgba8(img) => img.pixels().map(|p| p.0).collect(),
        _ => return None,
    })
}

/// The linear value of every 8-bit sRGB code.
pub(crate) fn srgb8_table() -> [f32; 256] {
    std::array::from_fn(|i| srgb_to_linear_f64(i as f64 / 255.0) as f32)
}

/// The linear value of every 16-bit sRGB code.
fn srgb16_table() -> Vec<f32> {
    (0..=u16::MAX)
        .map(|i| srgb_to_linear_f64(f64::from(i) / 65535.0) as f32)
        .collect()
}

/// Converts a decoded image other than the 8-bit ones of an sRGB format (kept as their codes,
/// [`srgb8_codes`]) to linear RGBA, expanding grey to RGB and adding alpha = 1. 16-bit colour
/// channels are sRGB-decoded; float images (HDR) are taken as linear. When `srgb` is false,
/// integer channels are only normalised.
fn dynamic_to_linear(image: DynamicImage, srgb: bool) -> Vec<[f32; 4]> {
    let a16 = |a: u16| f32::from(a) / 65535.0;
    match image {
        DynamicImage::ImageLuma16(_)
        | DynamicImage::ImageLumaA16(_)
        | DynamicImage::ImageRgb16(_)
        | DynamicImage::ImageRgba16(_) => {
            let lut: Vec<f32> = if srgb {
                srgb16_table()
            } else {
                (0..=u16::MAX).map(a16).collect()
            };
            let c = |v: u16| lut[usize::from(v)];
            match image {
                DynamicImage::ImageLuma16(img) => img
                    .pixels()
                    .map(|p| {
                        let l = c(p.0[0]);
                        [l, l, l, 1.0]
                    })
                    .collect(),
                DynamicImage::ImageLumaA16(img) => img
                    .pixels()
                    .map(|p| {
                        let l = c(p.0[0]);
                        [l, l, l, a16(p.0[1])]
                    })
                    .collect(),
                DynamicImage::ImageRgb16(img) => img
                    .pixels()
                    .map(|p| [c(p.0[0]), c(p.0[1]), c(p.0[2]), 1.0])
                    .collect(),
                other => other
                    .into_rgba16()
                    .pixels()
                    .map(|p| [c(p.0[0]), c(p.0[1]), c(p.0[2]), a16(p.0[3])])
                    .collect(),
            }
        }
        DynamicImage::ImageRgb32F(img) => img
            .pixels()
            .map(|p| [p.0[0], p.0[1], p.0[2], 1.0])
            .collect(),
        // RGBA float, and any future variant: as float, linear.
        other => other.into_rgba32f().pixels().map(|p| p.0).collect(),
    }
}
