//! Tests of `lux_render::image_io` writing: sRGB, PNG encoding and exposure, bad input files,
//! writers rejecting bad images, atomic writes.

mod common;

use common::*;
use std::fs;

use lux_render::image_io::{
    ImageError, ImageRgba, MAX_DIMENSION, Texture, linear_to_srgb, srgb_to_linear,
    write_atomically, write_exr, write_png,
};

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
    for (i, (orig, back)) in pixels.iter().zip(tex.texels().iter()).enumerate() {
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
// Bad input files
// ---------------------------------------------------------------------------------------------

#[test]
fn unsupported_and_missing_files() {
    let dir = scratch("unsupported");
    for name in ["image.psd", "image", "image.exr.bak", "image.tiff"] {
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
        &*Texture::load(&dir.join("dot.exr")).unwrap().texels(),
        &[[1.0, 2.0, 3.0, 4.0]]
    );
    assert!(temp_files(&dir).is_empty());
    fs::remove_dir_all(&dir).unwrap();
}
