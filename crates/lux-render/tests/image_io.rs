//! Tests of `lux_render::image_io` reading: PNG, JPEG, TGA, BMP, HDR and EXR textures, the luxtest dome
//! texture, nearest and bilinear lookups, texture construction.

mod common;

use common::*;
use std::fs;
use std::path::Path;

use lux_render::image_io::{IN_MEMORY, ImageError, MAX_DIMENSION, MAX_PIXELS, Texture, write_exr};

// ---------------------------------------------------------------------------------------------
// PNG / JPEG / HDR reading
// ---------------------------------------------------------------------------------------------

#[test]
fn png_8bit_variants_decode_srgb() {
    let dir = scratch("png_8bit");
    let codes = [0u8, 1, 10, 11, 128, 188, 254, 255];
    let lin = |c: u8| eotf(f64::from(c) / 255.0) as f32;

    let grey = dir.join("grey.png");
    image::GrayImage::from_raw(4, 2, codes.to_vec())
        .unwrap()
        .save(&grey)
        .unwrap();
    let t = Texture::load(&grey).unwrap();
    assert_eq!((t.width(), t.height()), (4, 2));
    for (texel, &c) in t.texels().iter().zip(&codes) {
        assert_eq!(*texel, [lin(c), lin(c), lin(c), 1.0]);
    }

    let grey_alpha = dir.join("grey_alpha.png");
    image::GrayAlphaImage::from_raw(2, 1, vec![128, 0, 255, 51])
        .unwrap()
        .save(&grey_alpha)
        .unwrap();
    let t = Texture::load(&grey_alpha).unwrap();
    assert_eq!(t.texels()[0], [lin(128), lin(128), lin(128), 0.0]);
    assert_eq!(t.texels()[1], [1.0, 1.0, 1.0, 51.0 / 255.0]);

    let rgb = dir.join("rgb.PNG"); // extension matching is case-insensitive
    image::RgbImage::from_raw(1, 2, vec![255, 0, 128, 10, 20, 30])
        .unwrap()
        .save_with_format(&rgb, image::ImageFormat::Png)
        .unwrap();
    let t = Texture::load(&rgb).unwrap();
    assert_eq!(t.texels()[0], [1.0, 0.0, lin(128), 1.0]);
    assert_eq!(t.texels()[1], [lin(10), lin(20), lin(30), 1.0]); // bottom row second

    let rgba = dir.join("rgba.png");
    image::RgbaImage::from_raw(1, 1, vec![188, 11, 1, 128])
        .unwrap()
        .save(&rgba)
        .unwrap();
    let t = Texture::load(&rgba).unwrap();
    assert_eq!(t.texels()[0], [lin(188), lin(11), lin(1), 128.0 / 255.0]);
    // 188 is the code of linear 0.5: decoding lands within the half-step around it.
    assert!((lin(188) - 0.5).abs() < 0.003);
    // Held as their codes: 4 bytes a texel.
    assert!(t.is_8bit() && !t.is_half());
    assert_eq!(t.texel_bytes(), 4);
    fs::remove_dir_all(&dir).unwrap();
}

/// `a` and `b` answer the same bits to `average`, `texels_iter` and to bilinear and nearest lookups at 500
/// coordinates in and around the unit square (wrapping and clamping included).
fn same_lookups(a: &Texture, b: &Texture) {
    assert_eq!(a.average(), b.average());
    assert!(a.texels_iter().eq(b.texels_iter()));
    assert_eq!(a.texels_iter().collect::<Vec<_>>(), *a.texels());
    for i in 0..500 {
        let (u, v) = (i as f64 * 0.0173 - 2.1, (i % 41) as f64 * 0.027 - 0.05);
        let (x, y) = (a.bilinear(u, v), b.bilinear(u, v));
        assert_eq!(
            x.map(f32::to_bits),
            y.map(f32::to_bits),
            "bilinear at ({u}, {v})"
        );
        assert_eq!(a.nearest(u, v), b.nearest(u, v), "nearest at ({u}, {v})");
    }
}

/// An 8-bit texture (held as its codes) answers every lookup as the `f32` texture of its
/// decoded texels, bit for bit: every code of every channel, grey with alpha too.
#[test]
fn eight_bit_textures_look_up_as_their_f32_texels() {
    let dir = scratch("png_8bit_lookups");
    let (w, h) = (16u32, 16u32);
    let px = image::RgbaImage::from_fn(w, h, |x, y| {
        let i = (y * w + x) as u8;
        image::Rgba([i, i.wrapping_mul(7), 255 - i, i.wrapping_mul(13)])
    });
    let path = dir.join("codes.png");
    px.save(&path).unwrap();
    let grey_only = dir.join("grey.png");
    image::GrayImage::from_fn(256, 1, |x, _| image::Luma([x as u8]))
        .save(&grey_only)
        .unwrap();
    let grey = dir.join("grey_alpha.png");
    image::GrayAlphaImage::from_fn(5, 3, |x, y| {
        image::LumaA([(40 * x + y) as u8, (50 * y) as u8])
    })
    .save(&grey)
    .unwrap();
    // (bytes a texel: 4 for colour or grey with alpha, 1 for grey alone, against f32's 16)
    for (path, bytes) in [(path, 4), (grey, 4), (grey_only, 1)] {
        let t = Texture::load(&path).unwrap();
        assert!(t.is_8bit(), "{}", path.display());
        let (w, h) = (t.width(), t.height());
        let full = Texture::from_texels(w, h, t.texels().into_owned()).unwrap();
        assert!(!full.is_8bit());
        assert_eq!(t.texel_bytes() * 16, full.texel_bytes() * bytes);
        same_lookups(&t, &full);
    }
    // Every grey code reads back as the sRGB decoding of its code, alpha 1.
    let t = Texture::load(&dir.join("grey.png")).unwrap();
    for (x, texel) in t.texels_iter().enumerate() {
        let l = eotf(x as f64 / 255.0) as f32;
        assert_eq!(texel, [l, l, l, 1.0], "code {x}");
    }
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn png_16bit_decodes_srgb() {
    let dir = scratch("png_16bit");
    let lin = |c: u16| eotf(f64::from(c) / 65535.0) as f32;

    let rgb16 = dir.join("rgb16.png");
    image::ImageBuffer::<image::Rgb<u16>, _>::from_raw(
        2,
        1,
        vec![0u16, 32768, 65535, 1000, 2651, 40000],
    )
    .unwrap()
    .save(&rgb16)
    .unwrap();
    let t = Texture::load(&rgb16).unwrap();
    assert_eq!(t.texels()[0], [0.0, lin(32768), 1.0, 1.0]);
    assert_eq!(t.texels()[1], [lin(1000), lin(2651), lin(40000), 1.0]);
    // 2651/65535 = 0.040452… just above the 0.04045 breakpoint; 1000 is on the linear segment.
    assert_eq!(t.texels()[1][0], (1000.0 / 65535.0 / 12.92) as f32);

    let la16 = dir.join("la16.png");
    image::ImageBuffer::<image::LumaA<u16>, _>::from_raw(1, 1, vec![65535u16, 32768])
        .unwrap()
        .save(&la16)
        .unwrap();
    let t = Texture::load(&la16).unwrap();
    assert_eq!(t.texels()[0], [1.0, 1.0, 1.0, 32768.0 / 65535.0]);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn jpeg_decodes_srgb() {
    let dir = scratch("jpeg");
    let path = dir.join("grey.jpg");
    image::RgbImage::from_pixel(16, 16, image::Rgb([128, 128, 128]))
        .save(&path)
        .unwrap();
    let t = Texture::load(&path).unwrap();
    assert_eq!((t.width(), t.height()), (16, 16));
    // A flat JPEG decodes to within a code of its value; compare in linear with the codes'
    // neighbours as bounds.
    let (lo, hi) = (eotf(127.0 / 255.0) as f32, eotf(129.0 / 255.0) as f32);
    for texel in t.texels().iter() {
        for &c in &texel[..3] {
            assert!((lo..=hi).contains(&c), "{c}");
        }
        assert_eq!(texel[3], 1.0);
    }
    // Also via .jpeg.
    loads_the_same_as(&path, &dir.join("grey.jpeg"), &t);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn tga_and_bmp_decode_srgb() {
    // 8-bit formats real USD assets use for textures (usd-wg's RoughnessTest reads a .tga):
    // decoded as sRGB like PNG, exactly (lossless).
    let dir = scratch("tga_bmp");
    let lin = |c: u8| eotf(f64::from(c) / 255.0) as f32;
    for name in ["rgba.tga", "rgb.bmp"] {
        let path = dir.join(name);
        let px = [[10u8, 128, 255, 200], [0, 1, 254, 255]];
        if name.ends_with(".tga") {
            image::RgbaImage::from_fn(2, 1, |x, _| image::Rgba(px[x as usize]))
                .save(&path)
                .unwrap();
        } else {
            image::RgbImage::from_fn(2, 1, |x, _| {
                let p = px[x as usize];
                image::Rgb([p[0], p[1], p[2]])
            })
            .save(&path)
            .unwrap();
        }
        let t = Texture::load(&path).unwrap();
        assert_eq!((t.width(), t.height()), (2, 1), "{name}");
        for (texel, p) in t.texels().iter().zip(px) {
            assert_eq!(&texel[..3], &[lin(p[0]), lin(p[1]), lin(p[2])], "{name}");
            let alpha = if name.ends_with(".tga") {
                f32::from(p[3]) / 255.0
            } else {
                1.0
            };
            assert_eq!(texel[3], alpha, "{name}");
        }
    }
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn hdr_is_linear() {
    let dir = scratch("hdr");
    let path = dir.join("radiance.hdr");
    let values = [
        image::Rgb([0.5f32, 2.0, 100.0]),
        image::Rgb([0.0, 1.0, 0.25]),
    ];
    let file = fs::File::create(&path).unwrap();
    image::codecs::hdr::HdrEncoder::new(file)
        .encode(&values, 2, 1)
        .unwrap();
    let t = Texture::load(&path).unwrap();
    assert_eq!((t.width(), t.height()), (2, 1));
    // RGBE keeps 8 bits of mantissa per pixel (relative to the largest channel); powers of two
    // that share the exponent come back exactly, no sRGB curve applied.
    assert_eq!(t.texels()[1], [0.0, 1.0, 0.25, 1.0]);
    let t0 = t.texels()[0];
    assert!((t0[2] - 100.0).abs() < 1.0);
    assert!((t0[1] - 2.0).abs() < 0.5 && t0[0] < 1.0);
    assert_eq!(t0[3], 1.0);
    fs::remove_dir_all(&dir).unwrap();
}

// ---------------------------------------------------------------------------------------------
// EXR
// ---------------------------------------------------------------------------------------------

#[test]
fn exr_round_trip_is_bit_exact() {
    let dir = scratch("exr_round_trip");
    let path = dir.join("rt.exr");
    let (width, height) = (5, 3);
    let special = [
        0.0f32,
        -0.0,
        1.0,
        -2.5,
        1e-40, // subnormal
        f32::MIN_POSITIVE,
        65504.0,
        3.0e38,
        1.0 / 3.0,
        0.1,
    ];
    let pixels: Vec<[f32; 4]> = (0..width * height)
        .map(|i| {
            let s = special[i % special.len()];
            [s, i as f32, (i as f32).sqrt(), 1.0 - i as f32 / 16.0]
        })
        .collect();
    write_exr(&path, &image_of(width, height, &pixels)).unwrap();
    assert!(temp_files(&dir).is_empty());

    let tex = Texture::load(&path).unwrap();
    assert_eq!((tex.width(), tex.height()), (width, height));
    for (a, b) in pixels.iter().zip(tex.texels().iter()) {
        assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits));
    }

    // Read back with the exr crate's generic reader: f32 channels, row 0 = top.
    assert_exr_bits(&path, width, height, &pixels);

    // Case-insensitive extension.
    loads_the_same_as(&path, &dir.join("RT.EXR"), &tex);
    fs::remove_dir_all(&dir).unwrap();
}

/// lux writes the ZIP blocks itself (its own deflate level): 16-line blocks, the last one
/// partial, both the compressed form (smooth rows) and the raw fallback (rows of random bits,
/// which deflate cannot shrink) must read back bit for bit through the exr crate's decoder.
#[test]
fn exr_zip_blocks_round_trip_compressed_and_raw() {
    let dir = scratch("exr_zip_blocks");
    let path = dir.join("zip.exr");
    let (width, height) = (37, 50); // blocks of rows 0–15, 16–31, 32–47, 48–49
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut random_bits = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        f32::from_bits(state as u32)
    };
    let pixels: Vec<[f32; 4]> = (0..width * height)
        .map(|i| {
            let (x, y) = ((i % width) as f32, (i / width) as f32);
            if (16..32).contains(&(i / width)) {
                [random_bits(), random_bits(), random_bits(), random_bits()]
            } else {
                [x / 37.0, y / 50.0, 0.25, 1.0]
            }
        })
        .collect();
    write_exr(&path, &image_of(width, height, &pixels)).unwrap();
    let meta = exr::meta::MetaData::read_from_file(&path, false).unwrap();
    assert_eq!(
        meta.headers[0].compression,
        exr::compression::Compression::ZIP16
    );
    // Smaller than the raw data (3 of the 4 blocks compress).
    assert!(fs::metadata(&path).unwrap().len() < (width * height * 16) as u64);
    assert_exr_bits(&path, width, height, &pixels);
    fs::remove_dir_all(&dir).unwrap();
}

/// A copy of `path` at `copy` (another extension's spelling) loads as `texture`.
fn loads_the_same_as(path: &Path, copy: &Path, texture: &Texture) {
    fs::copy(path, copy).unwrap();
    assert_eq!(&Texture::load(copy).unwrap(), texture);
}

/// The EXR at `path`, read by the exr crate's generic reader, holds `pixels` (`width × height`,
/// row 0 = top) in four `f32` channels, bit for bit.
fn assert_exr_bits(path: &Path, width: usize, height: usize, pixels: &[[f32; 4]]) {
    let flat = exr::prelude::read_first_flat_layer_from_file(path).unwrap();
    assert_eq!(flat.layer_data.size.0, width);
    assert_eq!(flat.layer_data.size.1, height);
    let channels = &flat.layer_data.channel_data.list;
    assert_eq!(channels.len(), 4);
    for (k, name) in ["R", "G", "B", "A"].iter().enumerate() {
        let ch = channels
            .iter()
            .find(|c| c.name.to_string() == *name)
            .unwrap();
        assert!(matches!(ch.sample_data, exr::prelude::FlatSamples::F32(_)));
        for (i, px) in pixels.iter().enumerate() {
            let v = ch.sample_data.value_by_flat_index(i).to_f32();
            assert_eq!(v.to_bits(), px[k].to_bits(), "{name} at {i}");
        }
    }
}

#[test]
fn exr_non_finite_becomes_zero_on_load() {
    let dir = scratch("exr_non_finite");
    let path = dir.join("nan.exr");
    let image = row(&[
        [f32::NAN, 1.0, f32::INFINITY, 1.0],
        [2.0, f32::NEG_INFINITY, 3.0, f32::NAN],
    ]);
    write_exr(&path, &image).unwrap();
    // The file keeps the values as given…
    let flat = exr::prelude::read_first_flat_layer_from_file(&path).unwrap();
    let r = flat
        .layer_data
        .channel_data
        .list
        .iter()
        .find(|c| c.name.to_string() == "R")
        .unwrap();
    assert!(r.sample_data.value_by_flat_index(0).to_f32().is_nan());
    // …the texture replaces them by 0 and counts them.
    let tex = Texture::load(&path).unwrap();
    assert_eq!(
        &*tex.texels(),
        &[[0.0, 1.0, 0.0, 1.0], [2.0, 0.0, 3.0, 0.0]]
    );
    assert_eq!(tex.non_finite_count(), 4);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn exr_half_and_u32_channels_and_missing_alpha() {
    use exr::prelude::f16;
    let dir = scratch("exr_types");

    // RGB half floats, no alpha (alpha defaults to 1).
    let half = dir.join("half_rgb.exr");
    exr::prelude::write_rgb_file(&half, 3, 2, |x, y| {
        let v = (y * 3 + x) as f32;
        (
            f16::from_f32(v * 0.5),
            f16::from_f32(-v),
            f16::from_f32(1000.0 + v),
        )
    })
    .unwrap();
    let t = Texture::load(&half).unwrap();
    assert_eq!((t.width(), t.height()), (3, 2));
    for (i, texel) in t.texels().iter().enumerate() {
        let v = i as f32;
        assert_eq!(*texel, [v * 0.5, -v, 1000.0 + v, 1.0], "texel {i}");
    }
    // Kept as half floats, and without the alpha the file does not have: 6 bytes a texel,
    // not 16.
    assert!(t.is_half());
    assert_eq!(t.texel_bytes(), 6 * 6);

    // u32 channels convert to their numeric value.
    let uint = dir.join("uint.exr");
    exr::prelude::write_rgba_file(&uint, 2, 1, |x, _| (x as u32, 7u32, 1000u32, 1u32)).unwrap();
    let t = Texture::load(&uint).unwrap();
    assert_eq!(
        &*t.texels(),
        &[[0.0, 7.0, 1000.0, 1.0], [1.0, 7.0, 1000.0, 1.0]]
    );
    assert!(!t.is_half());
    fs::remove_dir_all(&dir).unwrap();
}

/// A half-float texture answers every lookup as the `f32` texture of the same (widened)
/// texels, bit for bit; its NaN and ±∞ texels become 0 and are counted as in `f32`; a file
/// with a half and a full-float colour channel is read in `f32`.
#[test]
fn half_float_textures_look_up_as_their_f32_texels() {
    use exr::prelude::f16;
    let dir = scratch("exr_half_lookups");
    let (w, h) = (7, 5);
    let value = |x: usize, y: usize, c: usize| -> f16 {
        match (x + 3 * y + c) % 11 {
            3 if c == 0 => f16::NAN,
            5 if c == 1 => f16::INFINITY,
            k => f16::from_f32((k as f32 - 4.0) * 0.37 + y as f32 * 1e-3),
        }
    };
    let path = dir.join("half.exr");
    exr::prelude::write_rgba_file(&path, w, h, |x, y| {
        (
            value(x, y, 0),
            value(x, y, 1),
            value(x, y, 2),
            value(x, y, 3),
        )
    })
    .unwrap();
    let half = Texture::load(&path).unwrap();
    assert!(half.is_half());
    let widened: Vec<[f32; 4]> = (0..w * h)
        .map(|i| [0, 1, 2, 3].map(|c| value(i % w, i / w, c).to_f32()))
        .collect();
    let full = Texture::from_texels(w, h, widened).unwrap();
    assert!(!full.is_half());
    assert_eq!(half.non_finite_count(), full.non_finite_count());
    assert!(half.non_finite_count() > 0);
    assert_eq!(&*half.texels(), &*full.texels());
    same_lookups(&half, &full);
    for (x, y) in [(0, 0), (6, 4), (9, 9), (3, 2)] {
        assert_eq!(half.texel(x, y), full.texel(x, y));
    }

    // R in half, G and B in f32: widened to f32, as before.
    use exr::prelude::{AnyChannel, AnyChannels, FlatSamples, Image, WritableImage};
    let n = 4;
    let mixed = Image::from_channels(
        (2, 2),
        AnyChannels::sort(
            vec![
                AnyChannel::new("R", FlatSamples::F16(vec![f16::from_f32(0.5); n])),
                AnyChannel::new("G", FlatSamples::F32(vec![0.25; n])),
                AnyChannel::new("B", FlatSamples::F32(vec![2.0; n])),
            ]
            .into(),
        ),
    );
    let mixed_path = dir.join("mixed.exr");
    mixed.write().to_file(&mixed_path).unwrap();
    let t = Texture::load(&mixed_path).unwrap();
    assert!(!t.is_half());
    assert_eq!(&*t.texels(), &[[0.5, 0.25, 2.0, 1.0]; 4]);
    fs::remove_dir_all(&dir).unwrap();
}

/// Half-float files of several blocks, read by the scan-line fast path (ZIP blocks of 16 rows,
/// the last one short, stored bottom-up, beside a channel the texture does not use, alpha or
/// none) and by the general reader (tiles, RLE), give the texels written, NaN and ±∞ as 0.
#[test]
fn half_float_files_of_many_blocks_read_as_written() {
    use exr::image::{Blocks, Encoding, Layer};
    use exr::meta::attribute::LineOrder;
    use exr::meta::header::LayerAttributes;
    use exr::prelude::{
        AnyChannel, AnyChannels, Compression, FlatSamples, Image, WritableImage, f16,
    };
    let dir = scratch("exr_half_blocks");
    let (w, h) = (37, 53);
    let value = |i: usize, c: usize| -> f16 {
        match (i * 7 + c * 3) % 101 {
            5 => f16::NAN,
            9 => f16::NEG_INFINITY,
            k => f16::from_f32((k as f32 - 50.0) * 0.173 + c as f32),
        }
    };
    let channel = |name: &str, c: usize| {
        AnyChannel::new(
            name,
            FlatSamples::F16((0..w * h).map(|i| value(i, c)).collect()),
        )
    };
    let encodings = [
        (Compression::ZIP16, Blocks::ScanLines, LineOrder::Decreasing),
        (Compression::ZIP1, Blocks::ScanLines, LineOrder::Increasing),
        (
            Compression::RLE,
            Blocks::Tiles(exr::math::Vec2(16, 8)),
            LineOrder::Increasing,
        ),
    ];
    for (compression, blocks, line_order) in encodings {
        for alpha in [false, true] {
            let mut channels = vec![
                channel("R", 0),
                channel("G", 1),
                channel("B", 2),
                AnyChannel::new("Z", FlatSamples::F32(vec![7.5; w * h])),
            ];
            if alpha {
                channels.push(channel("A", 3));
            }
            let encoding = Encoding {
                compression,
                blocks,
                line_order,
            };
            let layer = Layer::new(
                (w, h),
                LayerAttributes::default(),
                encoding,
                AnyChannels::sort(channels.into()),
            );
            let path = dir.join(format!("half_{compression:?}_{alpha}.exr"));
            Image::from_layer(layer).write().to_file(&path).unwrap();
            let t = Texture::load(&path).unwrap();
            let what = format!("{compression:?}, alpha {alpha}");
            assert!(t.is_half(), "{what}");
            assert_eq!((t.width(), t.height()), (w, h), "{what}");
            assert_eq!(t.texel_bytes(), w * h * if alpha { 8 } else { 6 }, "{what}");
            let finite = |v: f16| if v.is_finite() { v.to_f32() } else { 0.0 };
            let mut bad = 0;
            for (i, texel) in t.texels().iter().enumerate() {
                let want = [0, 1, 2, 3].map(|c| match c {
                    3 if !alpha => 1.0,
                    c => {
                        bad += !value(i, c).is_finite() as usize;
                        finite(value(i, c))
                    }
                });
                assert_eq!(*texel, want, "{what}: texel {i}");
            }
            assert!(bad > 0);
            assert_eq!(t.non_finite_count(), bad, "{what}");
        }
    }
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn exr_without_rgb_is_an_error() {
    use exr::prelude::{AnyChannel, AnyChannels, FlatSamples, Image, WritableImage};
    let dir = scratch("exr_luminance");
    let path = dir.join("luminance.exr");
    let channels =
        AnyChannels::sort(vec![AnyChannel::new("Y", FlatSamples::F32(vec![0.5; 4]))].into());
    Image::from_channels((2, 2), channels)
        .write()
        .to_file(&path)
        .unwrap();
    let err = Texture::load(&path).unwrap_err();
    assert!(matches!(err, ImageError::Decode { .. }), "{err}");
    assert_names(&err, &path);
    assert!(err.to_string().contains("R, G and B"), "{err}");
    // The header alone tells: probing refuses it too.
    let err = Texture::probe(&path).unwrap_err();
    assert!(matches!(err, ImageError::Decode { .. }), "{err}");
    assert!(err.to_string().contains("R, G and B"), "{err}");
    fs::remove_dir_all(&dir).unwrap();
}

/// `Texture::probe` refuses from the header what `Texture::load` refuses before it decodes (a
/// PNG whose header is cut short, garbage named `.exr`, a format lux does not read, a missing
/// file), and passes a file whose header is whole: a good one, and one cut short inside its
/// image data, which only decoding finds.
#[test]
fn probing_checks_the_header_alone() {
    let dir = scratch("probe");
    let good = dir.join("good.png");
    image::RgbImage::from_pixel(3, 2, image::Rgb([10, 20, 30]))
        .save(&good)
        .unwrap();
    let bytes = fs::read(&good).unwrap();
    let idat = bytes.windows(4).position(|w| w == b"IDAT").unwrap();
    let cut_data = dir.join("cut_data.png");
    fs::write(&cut_data, &bytes[..idat + 6]).unwrap();
    let cut_header = dir.join("cut_header.png");
    fs::write(&cut_header, &bytes[..20]).unwrap();
    let garbage = dir.join("garbage.exr");
    fs::write(&garbage, b"not an image at all").unwrap();
    let other = dir.join("texture.tex");
    fs::write(&other, &bytes).unwrap();
    assert!(Texture::probe(&good).is_ok() && Texture::load(&good).is_ok());
    assert!(Texture::probe(&cut_data).is_ok());
    assert!(Texture::load(&cut_data).is_err());
    for p in [&cut_header, &garbage, &other, &dir.join("missing.png")] {
        let (probe, load) = (Texture::probe(p), Texture::load(p));
        assert!(probe.is_err() && load.is_err(), "{}", p.display());
        assert_names(&probe.unwrap_err(), p);
    }
    assert!(matches!(
        Texture::probe(&other),
        Err(ImageError::UnsupportedFormat { .. })
    ));
    fs::remove_dir_all(&dir).unwrap();
}

/// Rewrites the `dataWindow` attribute of an EXR header to `[0, 0] – [xmax, ymax]`.
fn patch_data_window(bytes: &mut [u8], xmax: i32, ymax: i32) {
    let key = b"dataWindow\0box2i\0";
    let at = bytes
        .windows(key.len())
        .position(|w| w == key)
        .expect("dataWindow attribute");
    let value = at + key.len() + 4; // skip the attribute size
    bytes[value + 8..value + 12].copy_from_slice(&xmax.to_le_bytes());
    bytes[value + 12..value + 16].copy_from_slice(&ymax.to_le_bytes());
}

#[test]
fn exr_absurd_dimensions_are_rejected_before_allocating() {
    let dir = scratch("exr_absurd");
    let small = dir.join("small.exr");
    write_exr(&small, &row(&[[1.0; 4]; 2])).unwrap();
    let original = fs::read(&small).unwrap();

    for (name, xmax, ymax) in [
        ("huge.exr", 1_999_999, 1_999_999), // 2e6 × 2e6
        ("wide.exr", 40_000, 0),            // 40001 × 1: over the side limit
        ("many.exr", 30_000, 30_000),       // 30001²: over the pixel limit
    ] {
        let mut bytes = original.clone();
        patch_data_window(&mut bytes, xmax, ymax);
        let path = dir.join(name);
        fs::write(&path, &bytes).unwrap();
        let err = Texture::load(&path).unwrap_err();
        assert!(
            matches!(err, ImageError::InvalidDimensions { .. }),
            "{name}: {err}"
        );
        assert_names(&err, &path);
    }
    fs::remove_dir_all(&dir).unwrap();
}

// ---------------------------------------------------------------------------------------------
// The luxtest dome texture
// ---------------------------------------------------------------------------------------------

#[test]
fn luxtest_dome_exr() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/luxtest/dome_grid_2k.exr");
    let tex = Texture::load(&path).unwrap();
    assert_eq!((tex.width(), tex.height()), (2048, 1024));
    assert_eq!(tex.non_finite_count(), 0);
    for t in tex.texels().iter() {
        assert!(t.iter().all(|c| c.is_finite() && *c >= 0.0), "{t:?}");
    }

    // Second, independent read: the exr crate's generic flat-layer reader. Every R, G, B (and
    // A, if present) sample must equal the texture's, bit for bit, in the same row order.
    let flat = exr::prelude::read_first_flat_layer_from_file(&path).unwrap();
    let layer = &flat.layer_data;
    assert_eq!((layer.size.0, layer.size.1), (2048, 1024));
    let find = |name: &str| {
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == name)
    };
    let mut sums = [0.0f64; 4];
    for (k, name) in ["R", "G", "B", "A"].iter().enumerate() {
        match find(name) {
            Some(ch) => {
                for (i, t) in tex.texels().iter().enumerate() {
                    let v = ch.sample_data.value_by_flat_index(i).to_f32();
                    assert_eq!(v.to_bits(), t[k].to_bits(), "{name} at texel {i}");
                    sums[k] += f64::from(v);
                }
            }
            None => {
                assert!(k == 3, "channel {name} missing");
                assert!(tex.texels().iter().all(|t| t[3] == 1.0));
                sums[3] = tex.texels().len() as f64;
            }
        }
    }
    let n = tex.texels().len() as f64;
    let avg = tex.average();
    for k in 0..4 {
        let independent = sums[k] / n;
        assert!(
            (avg[k] - independent).abs() <= 1e-9 * independent.abs().max(1.0),
            "channel {k}: {} vs {independent}",
            avg[k]
        );
    }
    // The file is half-float RGB without alpha; its mean (pinned from the independent read
    // above, to catch a changed or corrupted fixture) is a warm grey.
    let pinned = [0.549_491_32, 0.438_376_57, 0.346_615_66, 1.0];
    for k in 0..4 {
        assert!((avg[k] - pinned[k]).abs() < 1e-6, "channel {k}: {}", avg[k]);
    }
    // A lit environment: positive mean in every colour channel, and not a constant image.
    assert!(avg[..3].iter().all(|&a| a > 0.0), "{avg:?}");
    let (min, max) = tex
        .texels()
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), t| {
            (lo.min(t[0]), hi.max(t[0]))
        });
    assert!(max > min, "constant image");

    // Lookups agree with direct indexing at texel centres.
    let (w, h) = (2048.0, 1024.0);
    for &(x, y) in &[(0usize, 0usize), (1023, 511), (2047, 1023), (517, 900)] {
        let (u, v) = ((x as f64 + 0.5) / w, (y as f64 + 0.5) / h);
        let direct = tex.texels()[y * 2048 + x];
        assert_eq!(tex.nearest(u, v), direct);
        assert_eq!(tex.bilinear(u, v), direct);
    }
}

// ---------------------------------------------------------------------------------------------
// Lookups
// ---------------------------------------------------------------------------------------------

/// 2×2: top row a b, bottom row c d.
fn tex2x2() -> Texture {
    Texture::from_texels(
        2,
        2,
        vec![
            [1.0, 0.0, 0.0, 1.0],
            [0.0, 1.0, 0.0, 0.5],
            [0.0, 0.0, 1.0, 0.0],
            [1.0, 1.0, 1.0, 1.0],
        ],
    )
    .unwrap()
}

#[test]
fn nearest_on_2x2() {
    let t = tex2x2();
    let [a, b, c, d] = [t.texels()[0], t.texels()[1], t.texels()[2], t.texels()[3]];
    assert_eq!(t.nearest(0.25, 0.25), a);
    assert_eq!(t.nearest(0.75, 0.25), b);
    assert_eq!(t.nearest(0.25, 0.75), c); // v grows downwards
    assert_eq!(t.nearest(0.75, 0.75), d);
    // Edges: texel x covers [x/w, (x+1)/w).
    assert_eq!(t.nearest(0.0, 0.0), a);
    assert_eq!(t.nearest(0.5, 0.5), d);
    assert_eq!(t.nearest(0.499_999, 0.499_999), a);
    // u wraps, v clamps.
    assert_eq!(t.nearest(1.0, 0.25), a);
    assert_eq!(t.nearest(1.75, 0.25), b);
    assert_eq!(t.nearest(-0.25, 0.25), b);
    assert_eq!(t.nearest(-3.75, 0.75), c);
    assert_eq!(t.nearest(0.25, 1.0), c);
    assert_eq!(t.nearest(0.25, 7.0), c);
    assert_eq!(t.nearest(0.75, -7.0), b);
    // NaN → texel (0, 0); infinities behave.
    assert_eq!(t.nearest(f64::NAN, f64::NAN), a);
    assert_eq!(t.nearest(f64::NAN, 0.75), c);
    assert_eq!(t.nearest(0.75, f64::NAN), b);
    assert_eq!(t.nearest(f64::INFINITY, f64::NEG_INFINITY), a);
    assert_eq!(t.nearest(0.75, f64::INFINITY), d);
}

#[test]
fn bilinear_on_2x2() {
    let t = tex2x2();
    let [a, b, c, d] = [t.texels()[0], t.texels()[1], t.texels()[2], t.texels()[3]];
    // Texel centres return the texel exactly.
    assert_eq!(t.bilinear(0.25, 0.25), a);
    assert_eq!(t.bilinear(0.75, 0.25), b);
    assert_eq!(t.bilinear(0.25, 0.75), c);
    assert_eq!(t.bilinear(0.75, 0.75), d);
    // Centre of the image: the mean of all four.
    assert_eq!(t.bilinear(0.5, 0.5), [0.5, 0.5, 0.5, 0.625]);
    // Between a and b on the top row's centre line.
    assert_eq!(t.bilinear(0.5, 0.25), [0.5, 0.5, 0.0, 0.75]);
    // u = 0 lies halfway between the last column and the first (wrap): (b + a) / 2.
    assert_eq!(t.bilinear(0.0, 0.25), [0.5, 0.5, 0.0, 0.75]);
    assert_eq!(t.bilinear(1.0, 0.25), [0.5, 0.5, 0.0, 0.75]);
    // v clamps: above the first row's centre, the first row alone.
    assert_eq!(t.bilinear(0.25, 0.0), a);
    assert_eq!(t.bilinear(0.25, -3.0), a);
    assert_eq!(t.bilinear(0.75, 1.0), d);
    // Quarter way from a's centre towards b: u = 0.25 + 0.125 → 3/4 a + 1/4 b.
    assert_eq!(t.bilinear(0.375, 0.25), [0.75, 0.25, 0.0, 0.875]);
    // u = 0.125 (left of a's centre): 3/4 a + 1/4 b (b is the wrap-around neighbour).
    assert_eq!(t.bilinear(0.125, 0.25), [0.75, 0.25, 0.0, 0.875]);
    // NaN → texel (0, 0).
    assert_eq!(t.bilinear(f64::NAN, f64::NAN), a);
    assert_eq!(t.bilinear(f64::INFINITY, 0.75), c);
}

#[test]
fn lookups_on_3x2() {
    // Top row 0 1 2, bottom row 10 20 30 (red channel; others 0, alpha 1).
    let v = [0.0f32, 1.0, 2.0, 10.0, 20.0, 30.0];
    let t = Texture::from_texels(3, 2, v.iter().map(|&r| [r, 0.0, 0.0, 1.0]).collect()).unwrap();
    let r = |p: [f32; 4]| p[0];
    // Columns cover [0, 1/3), [1/3, 2/3), [2/3, 1).
    assert_eq!(r(t.nearest(0.3, 0.0)), 0.0);
    assert_eq!(r(t.nearest(0.34, 0.0)), 1.0);
    assert_eq!(r(t.nearest(0.67, 0.6)), 30.0);
    assert_eq!(r(t.nearest(1.2, 0.6)), 10.0);
    // Centres at 1/6, 1/2, 5/6 (u) and 1/4, 3/4 (v).
    let close = |a: f32, b: f32| (a - b).abs() < 1e-5;
    assert!(close(r(t.bilinear(1.0 / 6.0, 0.25)), 0.0));
    assert!(close(r(t.bilinear(0.5, 0.75)), 20.0));
    assert!(close(r(t.bilinear(5.0 / 6.0, 0.75)), 30.0));
    // Halfway between columns 0 and 1, halfway between rows: (0 + 1 + 10 + 20) / 4.
    assert!(close(r(t.bilinear(1.0 / 3.0, 0.5)), 7.75));
    // u = 0 wraps between column 2 and column 0: bottom row (30 + 10) / 2.
    assert!(close(r(t.bilinear(0.0, 0.75)), 20.0));
    // One third of the way from column 2's centre (5/6) to column 0's (7/6 ≡ 1/6) is u = 17/18 …
    assert!(close(r(t.bilinear(17.0 / 18.0, 0.25)), 2.0 * 2.0 / 3.0));
    // … and v = 0.375 is one quarter from row 0's centre to row 1's.
    assert!(close(r(t.bilinear(0.5, 0.375)), 0.75 * 1.0 + 0.25 * 20.0));
    assert_eq!(t.average(), [10.5, 0.0, 0.0, 1.0]);
}

// ---------------------------------------------------------------------------------------------
// Texture construction
// ---------------------------------------------------------------------------------------------

#[test]
fn from_texels_validates() {
    let err = Texture::from_texels(0, 0, vec![]).unwrap_err();
    assert!(matches!(err, ImageError::InvalidDimensions { .. }));
    assert_eq!(err.path(), Path::new(IN_MEMORY));
    assert!(err.to_string().contains(IN_MEMORY));
    let err = Texture::from_texels(3, 0, vec![]).unwrap_err();
    assert!(matches!(err, ImageError::InvalidDimensions { .. }));
    let err = Texture::from_texels(2, 2, vec![[0.0; 4]; 3]).unwrap_err();
    assert!(
        matches!(err, ImageError::PixelCountMismatch { len: 3, .. }),
        "{err}"
    );
    // Absurd sizes fail on the size check (no multiplication overflow, no allocation).
    let err = Texture::from_texels(usize::MAX, usize::MAX, vec![]).unwrap_err();
    assert!(matches!(err, ImageError::InvalidDimensions { .. }));
    let err = Texture::from_texels(MAX_DIMENSION + 1, 1, vec![]).unwrap_err();
    assert!(matches!(err, ImageError::InvalidDimensions { .. }));
    let err =
        Texture::from_texels(MAX_DIMENSION, MAX_PIXELS / MAX_DIMENSION + 1, vec![]).unwrap_err();
    assert!(matches!(err, ImageError::InvalidDimensions { .. }));

    let t = Texture::from_texels(1, 1, vec![[f32::NAN, 2.0, f32::NEG_INFINITY, 1.0]]).unwrap();
    assert_eq!(&*t.texels(), &[[0.0, 2.0, 0.0, 1.0]]);
    assert_eq!(t.non_finite_count(), 2);
    assert_eq!(t.texel(5, 5), [0.0, 2.0, 0.0, 1.0]);
}
