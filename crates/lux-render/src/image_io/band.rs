//! EXR files holding rows of a frame with string attributes: the tiles of a render split over
//! processes (`lux render --tile`), and frames that record how they were rendered.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use exr::block::BlockIndex;
use exr::block::chunk::{Chunk, CompressedBlock, CompressedScanLineBlock};
use exr::block::writer::ChunksWriter;
use exr::image::write::layers::WritableLayers;
use exr::meta::attribute::{AttributeValue, IntegerBounds, Text};
use exr::meta::header::LayerAttributes;
use exr::prelude::{
    Encoding, ImageAttributes, Layer, ReadChannels, ReadLayers, RgbaChannels, SpecificChannels,
    Vec2,
};
use rayon::prelude::*;

use super::read::exr_error;
use super::{ImageError, ImageRgba, StagedFile, check_buffer, check_dimensions, stage_atomically};

/// Rows `y0 .. y0 + image.height` of a frame `display` = `[width, height]` pixels, with string
/// attributes: what [`stage_exr_band`] writes and [`read_exr_band`] reads.
#[derive(Clone, Debug, PartialEq)]
pub struct ExrBand {
    /// The rows' pixels (`image.width` = the frame's width).
    pub image: ImageRgba,
    /// The frame row of the band's first row (the EXR data window's top).
    pub y0: usize,
    /// The whole frame's `[width, height]` (the EXR display window).
    pub display: [usize; 2],
    /// The header's string attributes, by name.
    pub attributes: BTreeMap<String, String>,
}

/// Stages (see [`StagedFile`]) an RGBA float32 EXR like [`super::stage_exr`] of `image`, the rows
/// from `y0` of a frame `frame_height` rows high: the data window is those rows, the display
/// window the frame. `attributes` are written as string header attributes (UTF-8 bytes).
pub fn stage_exr_band(
    path: &Path,
    image: &ImageRgba,
    y0: usize,
    frame_height: usize,
    attributes: &[(String, String)],
) -> Result<StagedFile, ImageError> {
    check_buffer(path, image.width, image.height, image.pixels.len())?;
    // (no read-side size limit: what the renderer made, it can write)
    if y0 + image.height > frame_height {
        return Err(ImageError::InvalidDimensions {
            path: path.to_path_buf(),
            width: image.width as u64,
            height: (y0 + image.height) as u64,
        });
    }
    let width = image.width;
    let pixels = &image.pixels;
    // The layer describes the header (channels, ZIP16 scan-line blocks, attributes); the
    // blocks themselves are assembled below straight from `pixels`.
    let channels = SpecificChannels::rgba(|pos: Vec2<usize>| {
        let p = pixels[pos.y() * width + pos.x()];
        (p[0], p[1], p[2], p[3])
    });
    let mut layer_attributes = LayerAttributes {
        layer_position: Vec2(0, y0 as i32),
        ..LayerAttributes::default()
    };
    for (name, value) in attributes {
        layer_attributes.other.insert(
            Text::from_slice_unchecked(name.as_bytes()),
            AttributeValue::Text(Text::from_slice_unchecked(value.as_bytes())),
        );
    }
    let layer = Layer::new(
        (image.width, image.height),
        layer_attributes,
        Encoding::SMALL_LOSSLESS,
        channels,
    );
    let display = IntegerBounds::new(Vec2(0, 0), Vec2(image.width, frame_height));
    let headers = layer.infer_headers(&ImageAttributes::new(display));
    let encode_error = |e: exr::error::Error| match e {
        exr::error::Error::Io(source) => ImageError::Io {
            path: path.to_path_buf(),
            action: "write",
            source,
        },
        other => ImageError::Encode {
            path: path.to_path_buf(),
            format: "OpenEXR",
            message: other.to_string(),
        },
    };
    // Which of our RGBA components each of the header's channels (sorted by name) holds.
    let order: Vec<usize> = headers[0]
        .channels
        .list
        .iter()
        .map(|c| match c.name.to_string().as_str() {
            "R" => 0,
            "G" => 1,
            "B" => 2,
            _ => 3,
        })
        .collect();
    // Encoded in memory first: the exr crate writes the string attributes last, in the order
    // of a hash map, which changes from run to run; they are put in name order before the
    // bytes are staged, so that one render always writes the same file.
    let mut file = std::io::Cursor::new(Vec::new());
    exr::block::write(&mut file, headers, true, |meta, chunks| {
        let blocks: Vec<(usize, BlockIndex)> =
            meta.enumerate_ordered_header_block_indices().collect();
        // Each block encoded on the current rayon pool; written in file order. One scratch
        // per worker (about 1 MB: deflate's state and the block's buffers), whichever blocks
        // it takes (`map_init` would make one per split of the work, more as work is stolen).
        let scratches: Vec<std::sync::Mutex<ZipScratch>> = (0..rayon::current_num_threads())
            .map(|_| Default::default())
            .collect();
        let encoded: Vec<(usize, Chunk)> = blocks
            .into_par_iter()
            .map(|(i, index)| {
                let y = (y0 + index.pixel_position.y()) as i32;
                let own = rayon::current_thread_index().and_then(|t| scratches.get(t));
                let chunk = match own.map(|m| m.lock()) {
                    // (a poisoned lock only means another block's job panicked)
                    Some(guard) => guard
                        .unwrap_or_else(|e| e.into_inner())
                        .chunk(pixels, width, &order, &index, y),
                    None => ZipScratch::default().chunk(pixels, width, &order, &index, y),
                };
                (i, chunk)
            })
            .collect();
        for (i, chunk) in encoded {
            chunks.write_chunk(i, chunk)?;
        }
        Ok(())
    })
    .map_err(encode_error)?;
    let mut bytes = file.into_inner();
    if !sort_last_attributes(&mut bytes, attributes.len()) {
        return Err(ImageError::Encode {
            path: path.to_path_buf(),
            format: "OpenEXR",
            message: "the header's attributes could not be put in order".into(),
        });
    }
    stage_atomically(path, |writer| {
        std::io::Write::write_all(writer, &bytes).map_err(|source| ImageError::Io {
            path: path.to_path_buf(),
            action: "write",
            source,
        })
    })
}

/// Puts the last `n` attributes of the single-part EXR header in `bytes` in name order, in
/// place (the same bytes in another order: the offset table after the header does not move).
/// An attribute is `name\0 type\0 size value` (`size` a little-endian `i32`); the list ends at
/// an empty name. False when the header does not parse that way.
fn sort_last_attributes(bytes: &mut [u8], n: usize) -> bool {
    let mut spans = Vec::new();
    let mut at = 8; // magic number and version
    loop {
        let Some(name_len) = bytes.get(at..).and_then(|b| b.iter().position(|&c| c == 0)) else {
            return false;
        };
        if name_len == 0 {
            break;
        }
        let Some(type_len) = bytes
            .get(at + name_len + 1..)
            .and_then(|b| b.iter().position(|&c| c == 0))
        else {
            return false;
        };
        let size_at = at + name_len + 1 + type_len + 1;
        let Some(size) = bytes.get(size_at..size_at + 4) else {
            return false;
        };
        let size = i32::from_le_bytes([size[0], size[1], size[2], size[3]]);
        let end = size_at + 4 + size.max(0) as usize;
        if size < 0 || end > bytes.len() {
            return false;
        }
        spans.push((at, name_len, end));
        at = end;
    }
    if spans.len() < n {
        return false;
    }
    let last = &spans[spans.len() - n..];
    let Some(&(start, ..)) = last.first() else {
        return true;
    };
    let mut sorted: Vec<&(usize, usize, usize)> = last.iter().collect();
    sorted.sort_by_key(|&&(a, len, _)| &bytes[a..a + len]);
    let reordered: Vec<u8> = sorted
        .iter()
        .flat_map(|&&(a, _, e)| bytes[a..e].iter().copied())
        .collect();
    bytes[start..start + reordered.len()].copy_from_slice(&reordered);
    true
}

/// deflate level of the ZIP blocks: zlib-ng's fastest (1, its "quick" strategy), as zlib-rs
/// implements it. The luxtest sphere frame's 512² render (32 blocks, 2 threads) encodes in
/// 5 ms instead of 7–8 ms with miniz_oxide at its level 1, for 4.5 % more bytes.
const ZIP_LEVEL: i32 = 1;

/// A worker's buffers for ZIP-compressing scan-line blocks (OpenEXR `ZIP_COMPRESSION`, 16
/// lines), reused from block to block. The OpenEXR scheme: the block's little-endian bytes
/// `b`, even-indexed ones first, then odd-indexed (`s`); each replaced by its difference to the
/// previous one plus 128 (mod 256; `s[0]` kept); zlib. Kept raw when that is not smaller (the
/// format's rule: a block of the uncompressed size is read as uncompressed). Written here,
/// rather than by `UncompressedBlock::compress_to_chunk`, for speed: the exr crate uses
/// miniz_oxide at level 4 and a fresh compressor per block.
#[derive(Default)]
struct ZipScratch {
    /// The block's values in file order ([`block_values`]).
    values: Vec<f32>,
    /// `s`: the even-indexed bytes of the block, then the odd-indexed ones.
    split: Vec<u8>,
    /// The predicted bytes: differences (+128) of `s`.
    delta: Vec<u8>,
    /// Deflate's output.
    out: Vec<u8>,
    /// The deflate stream, reset per block.
    deflate: Option<zlib_rs::Deflate>,
}

impl ZipScratch {
    /// The chunk of the block `index` of `pixels` (rows of `width`, channels in file `order`),
    /// its first line at frame row `y`.
    fn chunk(
        &mut self,
        pixels: &[[f32; 4]],
        width: usize,
        order: &[usize],
        index: &BlockIndex,
        y: i32,
    ) -> Chunk {
        let Self {
            values,
            split,
            delta,
            out,
            deflate,
        } = self;
        block_values(pixels, width, order, index, values);
        split_bytes(values, split);
        predict(split, delta);
        out.resize(zlib_rs::compress_bound(delta.len()), 0);
        let deflate = deflate.get_or_insert_with(|| zlib_rs::Deflate::new(ZIP_LEVEL, true, 15));
        deflate.reset();
        let done = deflate.compress(delta, out, zlib_rs::DeflateFlush::Finish);
        let n = deflate.total_out() as usize;
        let compressed = matches!(done, Ok(zlib_rs::Status::StreamEnd)) && n < split.len();
        Chunk {
            layer_index: 0,
            compressed_block: CompressedBlock::ScanLine(CompressedScanLineBlock {
                y_coordinate: y,
                compressed_pixels_le: if compressed {
                    out[..n].to_vec()
                } else {
                    values.iter().flat_map(|v| v.to_le_bytes()).collect()
                },
            }),
        }
    }
}

/// The little-endian bytes of the `values`, even-indexed ones first, then odd-indexed:
/// value `j`'s bytes `b0 b1 b2 b3` go to `2j`, `2j + 1` of the first half (`b0`, `b2`) and of
/// the second (`b1`, `b3`).
fn split_bytes(values: &[f32], split: &mut Vec<u8>) {
    let n = values.len();
    split.resize(4 * n, 0);
    let (even, odd) = split.split_at_mut(2 * n);
    for ((v, e), o) in values
        .iter()
        .zip(even.chunks_exact_mut(2))
        .zip(odd.chunks_exact_mut(2))
    {
        let [b0, b1, b2, b3] = v.to_le_bytes();
        e.copy_from_slice(&[b0, b2]);
        o.copy_from_slice(&[b1, b3]);
    }
}

/// OpenEXR's ZIP predictor of the split bytes `s` into `delta`: `delta[0] = s[0]`,
/// `delta[i] = s[i] − s[i−1] + 128` (mod 256).
fn predict(s: &[u8], delta: &mut Vec<u8>) {
    delta.clear();
    delta.extend(s.first());
    let rest = s.get(1..).unwrap_or_default();
    delta.extend(
        rest.iter()
            .zip(s)
            .map(|(&x, &prev)| x.wrapping_sub(prev).wrapping_add(128)),
    );
}

/// A scan-line block's values as OpenEXR lays them out, into `out`: for each line, each
/// channel's row of `f32` values, channels in the header's order.
fn block_values(
    pixels: &[[f32; 4]],
    width: usize,
    order: &[usize],
    index: &BlockIndex,
    out: &mut Vec<f32>,
) {
    let (x0, y0) = (index.pixel_position.x(), index.pixel_position.y());
    let (w, h) = (index.pixel_size.width(), index.pixel_size.height());
    out.clear();
    for y in y0..y0 + h {
        let row = &pixels[y * width + x0..y * width + x0 + w];
        for &c in order {
            out.extend(row.iter().map(|p| p[c]));
        }
    }
}

/// Reads an EXR's first RGBA layer exactly (`f32` bits unchanged), its data window's top row,
/// display window size and string attributes (image and layer ones).
pub fn read_exr_band(path: &Path) -> Result<ExrBand, ImageError> {
    let io = |source| ImageError::Io {
        path: path.to_path_buf(),
        action: "read",
        source,
    };
    let mut file = BufReader::new(File::open(path).map_err(io)?);
    let meta = exr::meta::MetaData::read_from_buffered(&mut file, false)
        .map_err(|e| exr_error(path, e))?;
    for header in meta.headers.iter() {
        check_dimensions(path, header.layer_size.0 as u64, header.layer_size.1 as u64)?;
    }
    let file = File::open(path).map_err(io)?;
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |size: Vec2<usize>, _: &RgbaChannels| ImageRgba {
                width: size.width(),
                height: size.height(),
                pixels: vec![[0.0, 0.0, 0.0, 1.0]; size.area()],
            },
            |image: &mut ImageRgba, pos: Vec2<usize>, (r, g, b, a): (f32, f32, f32, f32)| {
                let i = pos.y() * image.width + pos.x();
                if let Some(p) = image.pixels.get_mut(i) {
                    *p = [r, g, b, a];
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(BufReader::new(file))
        .map_err(|e| exr_error(path, e))?;
    let layer = image.layer_data;
    let text = |map: &std::collections::HashMap<Text, AttributeValue>| {
        map.iter()
            .filter_map(|(k, v)| match v {
                AttributeValue::Text(t) => Some((
                    String::from_utf8_lossy(k.as_slice()).into_owned(),
                    String::from_utf8_lossy(t.as_slice()).into_owned(),
                )),
                _ => None,
            })
            .collect::<Vec<_>>()
    };
    let mut attributes: BTreeMap<String, String> =
        text(&image.attributes.other).into_iter().collect();
    attributes.extend(text(&layer.attributes.other));
    let display = image.attributes.display_window;
    Ok(ExrBand {
        image: layer.channel_data.pixels,
        y0: usize::try_from(
            i64::from(layer.attributes.layer_position.y()) - i64::from(display.position.y()),
        )
        .unwrap_or(usize::MAX),
        display: [display.size.width(), display.size.height()],
        attributes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn band_round_trips_bits_window_and_attributes() {
        let dir = std::env::temp_dir().join(format!("lux-band-unit-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("band.exr");
        let pixels: Vec<[f32; 4]> = (0..3 * 2)
            .map(|i| [i as f32, f32::NAN, -0.0, f32::from_bits(0x7f80_0001 + i)])
            .collect();
        let image = ImageRgba {
            width: 3,
            height: 2,
            pixels,
        };
        let attrs = vec![
            ("lux:tile".to_string(), "1/3".to_string()),
            ("lux:scene".to_string(), "/tmp/szène.usda".to_string()),
        ];
        stage_exr_band(&path, &image, 4, 7, &attrs)
            .unwrap()
            .commit()
            .unwrap();
        let band = read_exr_band(&path).unwrap();
        assert_eq!(band.y0, 4);
        assert_eq!(band.display, [3, 7]);
        assert_eq!(band.attributes["lux:tile"], "1/3");
        assert_eq!(band.attributes["lux:scene"], "/tmp/szène.usda");
        let bits = |im: &ImageRgba| -> Vec<u32> {
            im.pixels.iter().flatten().map(|v| v.to_bits()).collect()
        };
        assert_eq!(bits(&band.image), bits(&image));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The exr crate writes string attributes in a hash map's order, new for every map: the
    /// same band staged ten times is the same file, its attributes in name order.
    #[test]
    fn the_same_band_is_the_same_file() {
        let dir = std::env::temp_dir().join(format!("lux-band-same-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let image = ImageRgba {
            width: 5,
            height: 3,
            pixels: (0..15).map(|i| [i as f32, 0.5, 0.25, 1.0]).collect(),
        };
        let attrs: Vec<(String, String)> =
            ["lux:scene", "lux:frame", "lux:rows", "lux:tile", "a", "zz"]
                .iter()
                .map(|&k| (k.to_string(), format!("value of {k}")))
                .collect();
        let files: Vec<Vec<u8>> = (0..10)
            .map(|i| {
                let path = dir.join(format!("b{i}.exr"));
                stage_exr_band(&path, &image, 0, 3, &attrs)
                    .unwrap()
                    .commit()
                    .unwrap();
                std::fs::read(&path).unwrap()
            })
            .collect();
        assert!(files.iter().all(|f| f == &files[0]));
        let text = String::from_utf8_lossy(&files[0]);
        let order: Vec<usize> = [
            "a\0",
            "lux:frame\0",
            "lux:rows\0",
            "lux:scene\0",
            "lux:tile\0",
            "zz\0",
        ]
        .iter()
        .map(|k| text.find(k).unwrap())
        .collect();
        assert!(order.windows(2).all(|w| w[0] < w[1]), "{order:?}");
        let band = read_exr_band(&dir.join("b3.exr")).unwrap();
        assert_eq!(band.attributes["lux:rows"], "value of lux:rows");
        assert_eq!(band.attributes.len(), 6);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
