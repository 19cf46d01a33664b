//! Tests of `lux_render::image_io`: texture loading, EXR / PNG writing, sRGB, lookups,
//! atomic writes and bad input.

use std::fs;
use std::path::{Path, PathBuf};

use lux_render::image_io::{
    IN_MEMORY, ImageError, ImageRgba, MAX_DIMENSION, MAX_PIXELS, Texture, linear_to_srgb,
    srgb_to_linear, write_atomically, write_exr, write_png,
};

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

/// A fresh, empty scratch directory for one test (under Cargo's per-target temp directory).
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("image_io")
        .join(format!("{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

/// Names of `*.tmp` files left in `dir`.
fn temp_files(dir: &Path) -> Vec<String> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

/// Asserts that `err` names `path` both in its `path()` and in its message.
fn assert_names(err: &ImageError, path: &Path) {
    assert_eq!(err.path(), path, "{err}");
    let msg = err.to_string();
    assert!(
        msg.contains(&path.display().to_string()),
        "message does not name {}: {msg}",
        path.display()
    );
}

/// A deterministic pseudo-random generator (64-bit LCG), values in [0, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The sRGB EOTF in f64, written out independently of the crate.
fn eotf(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The sRGB OETF in f64, written out independently of the crate.
fn oetf(x: f64) -> f64 {
    if x <= 0.0031308 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// Decodes a PNG's raw 8-bit RGBA bytes with the image crate (independently of `Texture`).
fn png_bytes(path: &Path) -> (u32, u32, Vec<u8>) {
    let img = image::ImageReader::open(path).unwrap().decode().unwrap();
    assert!(
        matches!(img, image::DynamicImage::ImageRgba8(_)),
        "write_png must write 8-bit RGBA"
    );
    let rgba = img.into_rgba8();
    (rgba.width(), rgba.height(), rgba.into_raw())
}

fn row(values: &[[f32; 4]]) -> ImageRgba {
    ImageRgba {
        width: values.len(),
        height: 1,
        pixels: values.to_vec(),
    }
}

/// The standard CRC-32 (PNG chunk checksums), bitwise.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFFu32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A PNG consisting of a valid IHDR claiming `width × height` (8-bit RGBA) and an IEND.
fn png_header_only(width: u32, height: u32) -> Vec<u8> {
    let mut out = vec![0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];
    let mut chunk = |kind: &[u8; 4], data: &[u8]| {
        out.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let mut body = kind.to_vec();
        body.extend_from_slice(data);
        out.extend_from_slice(&body);
        out.extend_from_slice(&crc32(&body).to_be_bytes());
    };
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&width.to_be_bytes());
    ihdr.extend_from_slice(&height.to_be_bytes());
    ihdr.extend_from_slice(&[8, 6, 0, 0, 0]);
    chunk(b"IHDR", &ihdr);
    chunk(b"IEND", &[]);
    out
}

// ---------------------------------------------------------------------------------------------
// sRGB
// ---------------------------------------------------------------------------------------------

#[test]
fn srgb_known_values() {
    assert_eq!(srgb_to_linear(0.0), 0.0);
    assert_eq!(srgb_to_linear(1.0), 1.0);
    assert_eq!(linear_to_srgb(0.0), 0.0);
    assert_eq!(linear_to_srgb(1.0), 1.0);
    // Hand-computed: ((0.5 + 0.055) / 1.055)^2.4 = 0.214041140…, 1.055·0.5^(1/2.4) − 0.055 =
    // 0.735356983…
    assert!((f64::from(srgb_to_linear(0.5)) - 0.214_041_140_482).abs() < 1e-7);
    assert!((f64::from(linear_to_srgb(0.5)) - 0.735_356_983_052).abs() < 1e-7);
    // Linear segments.
    assert_eq!(srgb_to_linear(0.04045), (0.04045f64 / 12.92) as f32);
    assert_eq!(linear_to_srgb(0.001), (12.92f64 * 0.001f32 as f64) as f32);
    assert_eq!(linear_to_srgb(-0.5), (12.92f64 * -0.5) as f32);
    // Boundary 0.0031308 ↔ 0.04045 (to within the standard's rounding of the constants).
    assert!((linear_to_srgb(0.003_130_8) - 0.040_45).abs() < 1e-6);
    assert!((srgb_to_linear(0.040_45) - 0.003_130_8).abs() < 1e-6);
    assert!(srgb_to_linear(f32::NAN).is_nan());
    assert!(linear_to_srgb(f32::NAN).is_nan());
    // Inverse of each other over [0, 1].
    for i in 0..=255 {
        let c = i as f32 / 255.0;
        assert!((linear_to_srgb(srgb_to_linear(c)) - c).abs() < 1e-6, "{c}");
    }
}

// ---------------------------------------------------------------------------------------------
// PNG writing
// ---------------------------------------------------------------------------------------------

#[test]
fn png_known_codes() {
    let dir = scratch("png_known_codes");
    let path = dir.join("codes.png");
    let values = [
        0.0,           // 0
        1.0,           // 255
        0.5,           // 1.055·0.5^(1/2.4) − 0.055 = 0.735357 → 187.516 → 188
        0.003_130_8,   // boundary: 12.92·x = 0.0404500 → 10.31 → 10
        0.001,         // 12.92·0.001·255 = 3.29 → 3
        0.002,         // 6.59 → 7 (rounds up)
        0.18,          // 0.461356 → 117.65 → 118
        0.214,         // 0.499956 → 127.49 → 127
        -0.5,          // negative → 0
        f32::NAN,      // NaN → 0
        2.0,           // > 1 → 255
        f32::INFINITY, // → 255
        f32::NEG_INFINITY,
    ];
    let expected = [0u8, 255, 188, 10, 3, 7, 118, 127, 0, 0, 255, 255, 0];
    // Alpha is only clamped and quantised: 0.5 → 127.5 → 128 (halves round up).
    let alphas = [
        1.0,
        0.0,
        0.5,
        0.25,
        2.0,
        -1.0,
        f32::NAN,
        1.0,
        1.0,
        1.0,
        1.0,
        1.0,
        1.0,
    ];
    let alpha_codes = [255u8, 0, 128, 64, 255, 0, 0, 255, 255, 255, 255, 255, 255];
    let pixels: Vec<[f32; 4]> = values
        .iter()
        .zip(alphas)
        .map(|(&v, a)| [v, v, v, a])
        .collect();
    write_png(&path, &row(&pixels), 0.0).unwrap();
    let (w, h, bytes) = png_bytes(&path);
    assert_eq!((w, h), (values.len() as u32, 1));
    for (i, px) in bytes.chunks_exact(4).enumerate() {
        assert_eq!(&px[..3], &[expected[i]; 3], "value {}", values[i]);
        assert_eq!(px[3], alpha_codes[i], "alpha {}", alphas[i]);
    }
    // The expected codes agree with the independent formula.
    for (&v, &e) in values.iter().zip(&expected).take(8) {
        assert_eq!((oetf(f64::from(v)) * 255.0).round() as u8, e);
    }
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn png_exposure_scales_before_encoding() {
    let dir = scratch("png_exposure");
    let path = dir.join("ev.png");
    let image = row(&[[0.25, 0.5, 0.125, 0.5], [1.0, 0.75, 0.0, 1.0]]);

    write_png(&path, &image, 1.0).unwrap();
    let (_, _, plus_one) = png_bytes(&path);
    // +1 EV doubles: 0.25 → 0.5 → 188, 0.5 → 1 → 255, 0.125 → 0.25 → sRGB 0.537099 → 137;
    // alpha untouched (0.5 → 128); 1.0 → 2 → 255, 0.75 → 1.5 → 255.
    assert_eq!(plus_one, [188, 255, 137, 128, 255, 255, 0, 255]);

    write_png(&path, &image, -1.0).unwrap();
    let (_, _, minus_one) = png_bytes(&path);
    // −1 EV halves: 0.25 → 0.125, 0.5 → 0.25, 0.125 → 0.0625 (sRGB 0.2794 → 71),
    // 1.0 → 0.5 → 188, 0.75 → 0.375 (sRGB 0.6461 → 165); alpha untouched.
    let code = |x: f64| (oetf(x) * 255.0).round() as u8;
    assert_eq!(code(0.0625), 71);
    assert_eq!(code(0.375), 165);
    assert_eq!(
        minus_one,
        [code(0.125), code(0.25), 71, 128, 188, 165, 0, 255]
    );

    // Non-finite exposure is an error naming the file; nothing is written.
    let other = dir.join("nan.png");
    let err = write_png(&other, &image, f64::NAN).unwrap_err();
    assert!(matches!(err, ImageError::InvalidExposure { .. }));
    assert_names(&err, &other);
    assert!(!other.exists());
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn png_round_trip_within_quantisation() {
    let dir = scratch("png_round_trip");
    let path = dir.join("rt.png");
    let (width, height) = (37, 23);
    let mut rng = Lcg(7);
    let pixels: Vec<[f32; 4]> = (0..width * height)
        .map(|_| {
            // Mostly [0, 1], some out of range on both sides.
            let mut c = || (rng.next() * 1.4 - 0.2) as f32;
            [c(), c(), c(), c()]
        })
        .collect();
    let image = ImageRgba {
        width,
        height,
        pixels: pixels.clone(),
    };
    write_png(&path, &image, 0.0).unwrap();
    let tex = Texture::load(&path).unwrap();
    assert_eq!((tex.width(), tex.height()), (width, height));
    assert_eq!(tex.non_finite_count(), 0);
    for (i, (orig, back)) in pixels.iter().zip(tex.texels()).enumerate() {
        for c in 0..4 {
            let clamped = f64::from(orig[c]).clamp(0.0, 1.0);
            let got = f64::from(back[c]);
            if c < 3 {
                // The quantisation step is in the sRGB domain: at most half a code there…
                let ds = (oetf(got) - oetf(clamped)).abs();
                assert!(
                    ds <= 0.5 / 255.0 + 1e-6,
                    "pixel {i} ch {c}: {orig:?} vs {back:?}"
                );
                // …which in linear is at most 0.5/255 · max slope of the EOTF (2.275 at 1).
                assert!((got - clamped).abs() <= 1.14 / 255.0, "pixel {i} ch {c}");
            } else {
                assert!(
                    (got - clamped).abs() <= 0.5 / 255.0 + 1e-6,
                    "pixel {i} alpha"
                );
            }
        }
    }
    // Row order survives: the top-left pixel of the file is pixels[0].
    let (_, _, bytes) = png_bytes(&path);
    let c0 = f64::from(pixels[0][0]).clamp(0.0, 1.0);
    assert_eq!(bytes[0], (oetf(c0) * 255.0).round() as u8);
    fs::remove_dir_all(&dir).unwrap();
}

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
    for texel in t.texels() {
        for &c in &texel[..3] {
            assert!((lo..=hi).contains(&c), "{c}");
        }
        assert_eq!(texel[3], 1.0);
    }
    // Also via .jpeg.
    let alt = dir.join("grey.jpeg");
    fs::copy(&path, &alt).unwrap();
    assert_eq!(Texture::load(&alt).unwrap(), t);
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
    let image = ImageRgba {
        width,
        height,
        pixels: pixels.clone(),
    };
    write_exr(&path, &image).unwrap();
    assert!(temp_files(&dir).is_empty());

    let tex = Texture::load(&path).unwrap();
    assert_eq!((tex.width(), tex.height()), (width, height));
    for (a, b) in pixels.iter().zip(tex.texels()) {
        assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits));
    }

    // Read back with the exr crate's generic reader: f32 channels, row 0 = top.
    let flat = exr::prelude::read_first_flat_layer_from_file(&path).unwrap();
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

    // Case-insensitive extension.
    let upper = dir.join("RT.EXR");
    fs::copy(&path, &upper).unwrap();
    assert_eq!(Texture::load(&upper).unwrap(), tex);
    fs::remove_dir_all(&dir).unwrap();
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
    assert_eq!(tex.texels(), &[[0.0, 1.0, 0.0, 1.0], [2.0, 0.0, 3.0, 0.0]]);
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

    // u32 channels convert to their numeric value.
    let uint = dir.join("uint.exr");
    exr::prelude::write_rgba_file(&uint, 2, 1, |x, _| (x as u32, 7u32, 1000u32, 1u32)).unwrap();
    let t = Texture::load(&uint).unwrap();
    assert_eq!(
        t.texels(),
        &[[0.0, 7.0, 1000.0, 1.0], [1.0, 7.0, 1000.0, 1.0]]
    );
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
    for t in tex.texels() {
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
    assert_eq!(t.texels(), &[[0.0, 2.0, 0.0, 1.0]]);
    assert_eq!(t.non_finite_count(), 2);
    assert_eq!(t.texel(5, 5), [0.0, 2.0, 0.0, 1.0]);
}

// ---------------------------------------------------------------------------------------------
// Bad input files
// ---------------------------------------------------------------------------------------------

#[test]
fn unsupported_and_missing_files() {
    let dir = scratch("unsupported");
    for name in ["image.tga", "image", "image.exr.bak", "image.tiff"] {
        let path = dir.join(name);
        fs::write(&path, b"whatever").unwrap();
        let err = Texture::load(&path).unwrap_err();
        assert!(
            matches!(err, ImageError::UnsupportedFormat { .. }),
            "{name}: {err}"
        );
        assert_names(&err, &path);
        assert!(
            err.to_string().contains(".exr"),
            "says what was expected: {err}"
        );
    }
    for name in ["missing.exr", "missing.png", "missing.hdr"] {
        let path = dir.join(name);
        let err = Texture::load(&path).unwrap_err();
        assert!(matches!(err, ImageError::Io { .. }), "{name}: {err}");
        assert_names(&err, &path);
    }
    // A directory with an image name.
    let sub = dir.join("folder.png");
    fs::create_dir(&sub).unwrap();
    let err = Texture::load(&sub).unwrap_err();
    assert_names(&err, &sub);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn garbage_and_truncated_files_are_errors() {
    let dir = scratch("garbage");

    // Valid files to truncate.
    let exr_ok = dir.join("ok.exr");
    let png_ok = dir.join("ok.png");
    let mut rng = Lcg(3);
    let pixels: Vec<[f32; 4]> = (0..64 * 64)
        .map(|_| [rng.next() as f32, rng.next() as f32, rng.next() as f32, 1.0])
        .collect();
    let image = ImageRgba {
        width: 64,
        height: 64,
        pixels,
    };
    write_exr(&exr_ok, &image).unwrap();
    write_png(&png_ok, &image, 0.0).unwrap();
    let exr_bytes = fs::read(&exr_ok).unwrap();
    let png_bytes = fs::read(&png_ok).unwrap();

    let mut garbage = vec![0u8; 300];
    for (i, b) in garbage.iter_mut().enumerate() {
        *b = (i * 37 + 11) as u8;
    }
    let mut cases: Vec<(String, Vec<u8>)> = Vec::new();
    for ext in ["exr", "png", "jpg", "jpeg", "hdr"] {
        cases.push((format!("empty.{ext}"), Vec::new()));
        cases.push((format!("garbage.{ext}"), garbage.clone()));
    }
    for frac in [1, 4, 8, 10, 20, 50, 90, 99] {
        let n = exr_bytes.len() * frac / 100;
        cases.push((format!("truncated{frac}.exr"), exr_bytes[..n].to_vec()));
        let n = png_bytes.len() * frac / 100;
        cases.push((format!("truncated{frac}.png"), png_bytes[..n].to_vec()));
    }
    // Magic numbers followed by garbage.
    let mut fake_exr = vec![0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0];
    fake_exr.extend_from_slice(&garbage);
    cases.push(("magic.exr".into(), fake_exr));
    let mut fake_png = png_bytes[..8].to_vec();
    fake_png.extend_from_slice(&garbage);
    cases.push(("magic.png".into(), fake_png));
    cases.push((
        "magic.hdr".into(),
        b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 5 +X 99999999\n".to_vec(),
    ));
    // A PNG whose header says 0 × 0.
    cases.push(("zero.png".into(), png_header_only(0, 0)));

    for (name, bytes) in &cases {
        let path = dir.join(name);
        fs::write(&path, bytes).unwrap();
        let err = Texture::load(&path).expect_err(name);
        assert!(
            matches!(
                err,
                ImageError::Decode { .. } | ImageError::InvalidDimensions { .. }
            ),
            "{name}: {err}"
        );
        assert_names(&err, &path);
    }
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn png_absurd_dimensions_are_rejected_before_allocating() {
    let dir = scratch("png_absurd");
    for (name, w, h) in [
        ("huge.png", 2_000_000_000, 2_000_000_000),
        ("wide.png", 40_000, 1),
        ("many.png", 20_000, 20_000), // 4·10⁸ > 2²⁸
    ] {
        let path = dir.join(name);
        fs::write(&path, png_header_only(w, h)).unwrap();
        let err = Texture::load(&path).unwrap_err();
        assert!(
            matches!(err, ImageError::InvalidDimensions { width, height, .. }
                if width == u64::from(w) && height == u64::from(h)),
            "{name}: {err}"
        );
        assert_names(&err, &path);
    }
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn writers_reject_bad_images() {
    let dir = scratch("bad_images");
    let empty = ImageRgba {
        width: 0,
        height: 0,
        pixels: vec![],
    };
    let zero_height = ImageRgba {
        width: 5,
        height: 0,
        pixels: vec![],
    };
    let short = ImageRgba {
        width: 2,
        height: 2,
        pixels: vec![[0.0; 4]; 3],
    };
    let huge = ImageRgba {
        width: MAX_DIMENSION + 1,
        height: 1,
        pixels: vec![],
    };
    for (label, image) in [
        ("empty", &empty),
        ("zero_height", &zero_height),
        ("short", &short),
        ("huge", &huge),
    ] {
        let exr = dir.join(format!("{label}.exr"));
        let png = dir.join(format!("{label}.png"));
        let e1 = write_exr(&exr, image).unwrap_err();
        let e2 = write_png(&png, image, 0.0).unwrap_err();
        for (err, path) in [(&e1, &exr), (&e2, &png)] {
            assert!(
                matches!(
                    err,
                    ImageError::InvalidDimensions { .. } | ImageError::PixelCountMismatch { .. }
                ),
                "{label}: {err}"
            );
            assert_names(err, path);
            assert!(!path.exists());
        }
    }
    assert!(matches!(
        write_exr(&dir.join("s.exr"), &short),
        Err(ImageError::PixelCountMismatch { len: 3, .. })
    ));
    assert!(
        fs::read_dir(&dir).unwrap().next().is_none(),
        "nothing written"
    );
    fs::remove_dir_all(&dir).unwrap();
}

// ---------------------------------------------------------------------------------------------
// Atomic writes
// ---------------------------------------------------------------------------------------------

#[test]
fn write_into_missing_directory_fails_cleanly() {
    let dir = scratch("missing_dir");
    let image = row(&[[0.5; 4]]);
    for name in ["out.exr", "out.png"] {
        let path = dir.join("no").join("such").join(name);
        let err = if name.ends_with("exr") {
            write_exr(&path, &image)
        } else {
            write_png(&path, &image, 0.0)
        }
        .unwrap_err();
        assert!(matches!(err, ImageError::Io { .. }), "{err}");
        assert_names(&err, &path);
        assert!(!path.exists());
        assert!(!dir.join("no").exists());
    }
    assert!(fs::read_dir(&dir).unwrap().next().is_none());
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn failing_write_keeps_existing_file() {
    let dir = scratch("failing_write");
    let target = dir.join("render.png");
    let first = row(&[[0.5, 0.25, 1.0, 1.0]]);
    write_png(&target, &first, 0.0).unwrap();
    let before = fs::read(&target).unwrap();

    // 1. The encoder step fails after writing part of the file.
    let err = write_atomically(&target, |w| {
        use std::io::Write;
        w.write_all(b"\x89PNG partial garbage").unwrap();
        w.flush().unwrap(); // make sure bytes reach the temporary file
        Err(ImageError::Encode {
            path: target.clone(),
            format: "PNG",
            message: "simulated failure".into(),
        })
    })
    .unwrap_err();
    assert_names(&err, &target);
    assert_eq!(fs::read(&target).unwrap(), before);
    assert!(temp_files(&dir).is_empty(), "{:?}", temp_files(&dir));

    // 2. The writer panics: the temporary file is still removed.
    let panicked = std::panic::catch_unwind(|| {
        let _ = write_atomically(&target, |w| {
            use std::io::Write;
            w.write_all(b"x").unwrap();
            panic!("simulated panic");
        });
    });
    assert!(panicked.is_err());
    assert_eq!(fs::read(&target).unwrap(), before);
    assert!(temp_files(&dir).is_empty());

    // 3. Invalid input to the real writers leaves the file alone.
    assert!(write_png(&target, &first, f64::INFINITY).is_err());
    assert!(
        write_png(
            &target,
            &ImageRgba {
                width: 3,
                height: 1,
                pixels: vec![]
            },
            0.0
        )
        .is_err()
    );
    assert_eq!(fs::read(&target).unwrap(), before);

    // 4. The final rename fails (the target is a non-empty directory): no temporary file left.
    let blocked = dir.join("blocked.exr");
    fs::create_dir(&blocked).unwrap();
    fs::write(blocked.join("keep"), b"k").unwrap();
    let err = write_exr(&blocked, &first).unwrap_err();
    assert!(matches!(err, ImageError::Io { .. }), "{err}");
    assert_names(&err, &blocked);
    assert_eq!(fs::read(blocked.join("keep")).unwrap(), b"k");
    assert!(temp_files(&dir).is_empty(), "{:?}", temp_files(&dir));

    // 5. A successful write replaces the file completely.
    let second = row(&[[0.0, 0.0, 0.0, 1.0], [1.0; 4]]);
    write_png(&target, &second, 0.0).unwrap();
    let (w, h, bytes) = png_bytes(&target);
    assert_eq!((w, h), (2, 1));
    assert_eq!(bytes, [0, 0, 0, 255, 255, 255, 255, 255]);
    assert!(temp_files(&dir).is_empty());
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn relative_target_path_works() {
    // A bare file name has an empty parent: the temporary file goes into ".". Use the
    // scratch directory through an absolute path but check the parent logic with a name whose
    // parent is the directory itself.
    let dir = scratch("relative");
    let path = dir.join(".").join("dot.exr");
    write_exr(&path, &row(&[[1.0, 2.0, 3.0, 4.0]])).unwrap();
    assert_eq!(
        Texture::load(&dir.join("dot.exr")).unwrap().texels(),
        &[[1.0, 2.0, 3.0, 4.0]]
    );
    assert!(temp_files(&dir).is_empty());
    fs::remove_dir_all(&dir).unwrap();
}
