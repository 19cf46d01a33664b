//! EXR files holding rows of a frame with string attributes: the tiles of a render split over
//! processes (`lux render --tile`), and frames that record how they were rendered.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use exr::meta::attribute::{AttributeValue, IntegerBounds, Text};
use exr::meta::header::LayerAttributes;
use exr::prelude::{
    Encoding, Image, ImageAttributes, Layer, ReadChannels, ReadLayers, RgbaChannels,
    SpecificChannels, Vec2, WritableImage,
};

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
    // Positions are relative to the data window.
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
    let exr_image = Image::new(ImageAttributes::new(display), layer);
    stage_atomically(path, |writer| {
        exr_image.write().to_buffered(writer).map_err(|e| match e {
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
        })
    })
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
}
