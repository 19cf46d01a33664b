//! Atomic EXR and PNG output.

use std::ffi::OsString;
use std::fs::{self, File, OpenOptions};
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use image::ImageEncoder;
use rayon::prelude::*;

use super::{ImageError, ImageRgba, check_buffer, linear_to_srgb_f64};

/// Distinguishes temporary files of concurrent writes within one process.
static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Removes the temporary file on drop unless the write succeeded.
struct TempFile {
    path: PathBuf,
    keep: bool,
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if !self.keep {
            let _ = fs::remove_file(&self.path);
        }
    }
}

/// Writes a file atomically: `write` fills a temporary file in the target's directory, which
/// is then flushed and renamed over `path`. Readers see the old file or the whole new one,
/// never a part; the data is left to the operating system's write-back, as image writers do
/// (OpenEXR, OpenImageIO, Blender, Mitsuba): [`StagedFile::commit_durable`] also forces it to
/// disk first, so that it survives a power loss.
///
/// The temporary file is named `.<file name>.<pid>.<counter>.tmp`, next to the target so the
/// final `rename` stays within one file system. If `write` fails (or panics), or flushing or
/// renaming fails, the temporary file is removed and `path` is left as it was — a pre-existing
/// target keeps its old contents. All errors name `path` (not the temporary file).
///
/// `write` receives a buffered writer (which is also `Seek`); I/O errors it reports should name
/// `path` too.
pub fn write_atomically<F>(path: &Path, write: F) -> Result<(), ImageError>
where
    F: FnOnce(&mut BufWriter<File>) -> Result<(), ImageError>,
{
    stage_atomically(path, write)?.commit()
}

/// A complete temporary file waiting to replace its target: the first half of
/// [`write_atomically`], for outputs that must appear together (the CLI's EXR and PNG are both
/// staged before either is renamed, so a failed encode leaves neither). Dropping it without
/// [`commit`](Self::commit) removes the temporary file.
#[must_use = "a staged file is removed unless committed"]
pub struct StagedFile {
    temp: TempFile,
    path: PathBuf,
}

impl StagedFile {
    /// The target path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Renames the temporary file over the target. On failure the temporary file is removed
    /// and the target is left as it was; the error names the target.
    pub fn commit(mut self) -> Result<(), ImageError> {
        fs::rename(&self.temp.path, &self.path).map_err(|source| ImageError::Io {
            path: self.path.clone(),
            action: "replace",
            source,
        })?;
        self.temp.keep = true;
        Ok(())
    }

    /// [`commit`](Self::commit) after forcing the file's data and metadata to disk (`fsync`),
    /// so that after a power loss or kernel crash the target holds the old file or the whole
    /// new one. The cost is the wait for the file system's journal: 2–8 ms on an idle disk,
    /// tens of milliseconds while other writes are pending. On failure the temporary file is
    /// removed and the target is left as it was.
    pub fn commit_durable(self) -> Result<(), ImageError> {
        // (opened for writing: some systems flush only a writable handle)
        let synced = OpenOptions::new()
            .write(true)
            .open(&self.temp.path)
            .and_then(|f| f.sync_all());
        synced.map_err(|source| ImageError::Io {
            path: self.path.clone(),
            action: "write",
            source,
        })?;
        self.commit()
    }
}

/// Writes the temporary file of [`write_atomically`] (named, filled and flushed as described
/// there) without renaming it: see [`StagedFile`].
pub fn stage_atomically<F>(path: &Path, write: F) -> Result<StagedFile, ImageError>
where
    F: FnOnce(&mut BufWriter<File>) -> Result<(), ImageError>,
{
    let io_error = |action: &'static str, source: std::io::Error| ImageError::Io {
        path: path.to_path_buf(),
        action,
        source,
    };
    let Some(file_name) = path.file_name() else {
        return Err(io_error(
            "write",
            std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "the path has no file name",
            ),
        ));
    };
    let dir = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let mut temp_name = OsString::from(".");
    temp_name.push(file_name);
    temp_name.push(format!(
        ".{}.{}.tmp",
        std::process::id(),
        TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
    ));

    let mut temp = TempFile {
        path: dir.join(temp_name),
        keep: true, // nothing to remove until the file exists
    };
    let file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temp.path)
        .map_err(|e| io_error("create a temporary file next to", e))?;
    temp.keep = false;

    let mut writer = BufWriter::new(file);
    write(&mut writer)?;
    let file = writer
        .into_inner()
        .map_err(|e| io_error("write", e.into_error()))?;
    drop(file);
    Ok(StagedFile {
        temp,
        path: path.to_path_buf(),
    })
}

/// Writes `image` as an OpenEXR file: one layer, `R`, `G`, `B`, `A` channels of 32-bit float,
/// linear values written unchanged (bit-exact, including NaN and ±∞), ZIP compression
/// (lossless), scan lines in increasing-y order (row 0 = top, the EXR default). The write is
/// atomic ([`write_atomically`]).
///
/// Errors if the size is empty or too large ([`ImageError::InvalidDimensions`]), if
/// `pixels.len() != width * height` ([`ImageError::PixelCountMismatch`]), or on I/O failure.
pub fn write_exr(path: &Path, image: &ImageRgba) -> Result<(), ImageError> {
    stage_exr(path, image)?.commit()
}

/// [`write_exr`] up to the rename: the encoded file, staged ([`StagedFile`]) — a band of all
/// the frame's rows without attributes ([`super::stage_exr_band`]).
pub fn stage_exr(path: &Path, image: &ImageRgba) -> Result<StagedFile, ImageError> {
    super::stage_exr_band(path, image, 0, image.height, &[])
}

/// Encodes a linear value (already scaled by the exposure) as an 8-bit sRGB code:
/// NaN and negatives → 0, clamp to 1, sRGB OETF, `round(255 · s)` (halves round up).
#[inline]
fn encode_srgb8(linear: f64) -> u8 {
    if linear.is_nan() || linear <= 0.0 {
        return 0;
    }
    let s = linear_to_srgb_f64(linear.min(1.0));
    (s * 255.0).round() as u8
}

/// Quantises alpha (not colour-encoded): NaN and negatives → 0, clamp to 1, `round(255 · a)`.
#[inline]
fn encode_alpha8(alpha: f64) -> u8 {
    if alpha.is_nan() || alpha <= 0.0 {
        return 0;
    }
    (alpha.min(1.0) * 255.0).round() as u8
}

/// Writes `image` as an 8-bit RGBA sRGB PNG. The write is atomic ([`write_atomically`]).
///
/// Each colour channel `c` becomes `round(255 · oetf(clamp(c · 2^exposure_ev, 0, 1)))` where
/// `oetf` is the sRGB OETF ([`linear_to_srgb`](super::linear_to_srgb): `12.92·x` for
/// `x ≤ 0.0031308`, else `1.055·x^(1/2.4) − 0.055`), computed in `f64`; NaN becomes 0 and
/// halves round up. Alpha is kept, not exposed and not colour-encoded:
/// `round(255 · clamp(a, 0, 1))`. The file is always RGBA (alpha 255 where the image is
/// opaque).
///
/// [`stage_png_opaque`] writes the same colours as an RGB PNG without alpha.
///
/// Errors if `exposure_ev` is not finite ([`ImageError::InvalidExposure`]), if the size is
/// empty or too large, if `pixels.len() != width * height`, or on I/O failure.
pub fn write_png(path: &Path, image: &ImageRgba, exposure_ev: f64) -> Result<(), ImageError> {
    stage_png(path, image, exposure_ev)?.commit()
}

/// [`write_png`] up to the rename: the encoded file, staged ([`StagedFile`]).
pub fn stage_png(
    path: &Path,
    image: &ImageRgba,
    exposure_ev: f64,
) -> Result<StagedFile, ImageError> {
    stage_png_channels(path, image, exposure_ev, true)
}

/// As [`stage_png`] but an 8-bit RGB PNG: the colours of [`write_png`], alpha dropped, so
/// viewers show the image opaque (an empty background black, not checkered).
pub fn stage_png_opaque(
    path: &Path,
    image: &ImageRgba,
    exposure_ev: f64,
) -> Result<StagedFile, ImageError> {
    stage_png_channels(path, image, exposure_ev, false)
}

/// The PNG encoder of [`stage_png`] (`alpha`: RGBA) and [`stage_png_opaque`] (RGB).
fn stage_png_channels(
    path: &Path,
    image: &ImageRgba,
    exposure_ev: f64,
    alpha: bool,
) -> Result<StagedFile, ImageError> {
    if !exposure_ev.is_finite() {
        return Err(ImageError::InvalidExposure {
            path: path.to_path_buf(),
            exposure_ev,
        });
    }
    check_buffer(path, image.width, image.height, image.pixels.len())?;
    let scale = exposure_ev.exp2();

    let channels = if alpha { 4 } else { 3 };
    let mut bytes = vec![0u8; image.pixels.len() * channels];
    bytes
        .par_chunks_mut(image.width * channels)
        .zip(image.pixels.par_chunks(image.width))
        .for_each(|(out, row)| {
            for (o, p) in out.chunks_exact_mut(channels).zip(row) {
                o[0] = encode_srgb8(f64::from(p[0]) * scale);
                o[1] = encode_srgb8(f64::from(p[1]) * scale);
                o[2] = encode_srgb8(f64::from(p[2]) * scale);
                if alpha {
                    o[3] = encode_alpha8(f64::from(p[3]));
                }
            }
        });

    stage_atomically(path, |writer| {
        image::codecs::png::PngEncoder::new(writer)
            .write_image(
                &bytes,
                image.width as u32,
                image.height as u32,
                if alpha {
                    image::ExtendedColorType::Rgba8
                } else {
                    image::ExtendedColorType::Rgb8
                },
            )
            .map_err(|e| match e {
                image::ImageError::IoError(source) => ImageError::Io {
                    path: path.to_path_buf(),
                    action: "write",
                    source,
                },
                other => ImageError::Encode {
                    path: path.to_path_buf(),
                    format: "PNG",
                    message: other.to_string(),
                },
            })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb8_known_codes() {
        assert_eq!(encode_srgb8(0.0), 0);
        assert_eq!(encode_srgb8(1.0), 255);
        assert_eq!(encode_srgb8(0.5), 188);
        assert_eq!(encode_srgb8(-1.0), 0);
        assert_eq!(encode_srgb8(f64::NAN), 0);
        assert_eq!(encode_srgb8(7.0), 255);
        assert_eq!(encode_srgb8(f64::INFINITY), 255);
        assert_eq!(encode_alpha8(0.5), 128);
        assert_eq!(encode_alpha8(f64::NAN), 0);
    }

    #[test]
    fn failed_write_removes_temp_and_keeps_target() {
        let dir = std::env::temp_dir().join(format!("lux-image-io-unit-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let target = dir.join("keep.bin");
        fs::write(&target, b"old").unwrap();
        let err = write_atomically(&target, |w| {
            use std::io::Write;
            w.write_all(b"partial").unwrap();
            Err(ImageError::Encode {
                path: target.clone(),
                format: "test",
                message: "injected".into(),
            })
        })
        .unwrap_err();
        assert!(matches!(err, ImageError::Encode { .. }));
        assert_eq!(fs::read(&target).unwrap(), b"old");
        let leftovers: Vec<_> = fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .filter(|n| n.to_string_lossy().ends_with(".tmp"))
            .collect();
        assert!(leftovers.is_empty(), "{leftovers:?}");
        fs::remove_dir_all(&dir).unwrap();
    }

    /// `commit` and `commit_durable` both replace the target with the staged bytes and leave
    /// no temporary file; a durable commit whose temporary file is gone fails naming the
    /// target, which keeps its contents.
    #[test]
    fn durable_and_plain_commits_replace_the_target() {
        let dir = std::env::temp_dir().join(format!("lux-image-io-sync-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let target = dir.join("out.bin");
        let stage = |bytes: &'static [u8]| {
            stage_atomically(&target, |w| {
                use std::io::Write;
                w.write_all(bytes).map_err(|source| ImageError::Io {
                    path: target.clone(),
                    action: "write",
                    source,
                })
            })
            .unwrap()
        };
        stage(b"plain").commit().unwrap();
        assert_eq!(fs::read(&target).unwrap(), b"plain");
        stage(b"durable").commit_durable().unwrap();
        assert_eq!(fs::read(&target).unwrap(), b"durable");
        let staged = stage(b"lost");
        fs::remove_file(&staged.temp.path).unwrap();
        match staged.commit_durable().unwrap_err() {
            ImageError::Io { path, .. } => assert_eq!(path, target),
            other => panic!("{other:?}"),
        }
        assert_eq!(fs::read(&target).unwrap(), b"durable");
        let names: Vec<_> = fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, [std::ffi::OsString::from("out.bin")]);
        fs::remove_dir_all(&dir).unwrap();
    }
}
