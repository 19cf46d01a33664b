//! Helpers shared by the image tests: scratch directories, independent sRGB curves, PNG
//! decoding and crafted PNG headers.

#![allow(dead_code)]

use std::fs;
use std::path::{Path, PathBuf};

use lux_render::image_io::{ImageError, ImageRgba};

/// A fresh, empty scratch directory for one test (under Cargo's per-target temp directory).
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("image_io")
        .join(format!("{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

/// Names of `*.tmp` files left in `dir`.
pub fn temp_files(dir: &Path) -> Vec<String> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

/// Asserts that `err` names `path` both in its `path()` and in its message.
pub fn assert_names(err: &ImageError, path: &Path) {
    assert_eq!(err.path(), path, "{err}");
    let msg = err.to_string();
    assert!(
        msg.contains(&path.display().to_string()),
        "message does not name {}: {msg}",
        path.display()
    );
}

/// A deterministic pseudo-random generator (64-bit LCG), values in [0, 1).
pub struct Lcg(pub u64);
impl Lcg {
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The sRGB EOTF in f64, written out independently of the crate.
pub fn eotf(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The sRGB OETF in f64, written out independently of the crate.
pub fn oetf(x: f64) -> f64 {
    if x <= 0.0031308 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// Decodes a PNG's raw 8-bit RGBA bytes with the image crate (independently of `Texture`).
pub fn png_bytes(path: &Path) -> (u32, u32, Vec<u8>) {
    let img = image::ImageReader::open(path).unwrap().decode().unwrap();
    assert!(
        matches!(img, image::DynamicImage::ImageRgba8(_)),
        "write_png must write 8-bit RGBA"
    );
    let rgba = img.into_rgba8();
    (rgba.width(), rgba.height(), rgba.into_raw())
}

/// A `width × height` image of `pixels` (row 0 = top).
pub fn image_of(width: usize, height: usize, pixels: &[[f32; 4]]) -> ImageRgba {
    ImageRgba {
        width,
        height,
        pixels: pixels.to_vec(),
    }
}

pub fn row(values: &[[f32; 4]]) -> ImageRgba {
    ImageRgba {
        width: values.len(),
        height: 1,
        pixels: values.to_vec(),
    }
}

/// The standard CRC-32 (PNG chunk checksums), bitwise.
pub fn crc32(bytes: &[u8]) -> u32 {
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
pub fn png_header_only(width: u32, height: u32) -> Vec<u8> {
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
