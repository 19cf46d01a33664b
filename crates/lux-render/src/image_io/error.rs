//! The error type of the image module.

use std::path::{Path, PathBuf};

/// The pseudo file name used by errors that concern in-memory data rather than a file
/// ([`Texture::from_texels`](super::Texture::from_texels)).
pub const IN_MEMORY: &str = "<in-memory texels>";

/// An error while reading, writing or constructing an image.
///
/// Every variant names the file it concerns (the *target* path for writes, never the temporary
/// file) and its message says what was expected. Errors about in-memory texels name the pseudo
/// file [`IN_MEMORY`].
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImageError {
    /// The operating system refused an operation on the file (missing file or directory,
    /// permissions, disk full, …).
    #[error("cannot {action} {}: {source}", .path.display())]
    Io {
        /// The file concerned (for writes, the target path).
        path: PathBuf,
        /// What was being attempted, e.g. `"read"` or `"create a temporary file next to"`.
        action: &'static str,
        /// The underlying I/O error.
        source: std::io::Error,
    },

    /// The file name's extension is not one of the supported formats.
    #[error(
        "{}: unsupported image format (expected a file name ending in .exr, .png, .jpg, .jpeg, \
         .hdr, .tga or .bmp)",
        .path.display()
    )]
    UnsupportedFormat {
        /// The file concerned.
        path: PathBuf,
    },

    /// The file could not be decoded: truncated, corrupt, or lacking the expected content.
    #[error("{}: cannot decode (expected {expected}): {message}", .path.display())]
    Decode {
        /// The file concerned.
        path: PathBuf,
        /// What the file should have been, e.g. `"a PNG image"`.
        expected: &'static str,
        /// The decoder's description of the problem.
        message: String,
    },

    /// The encoder rejected the image.
    #[error("cannot encode {} as {format}: {message}", .path.display())]
    Encode {
        /// The target file.
        path: PathBuf,
        /// The output format, e.g. `"OpenEXR"`.
        format: &'static str,
        /// The encoder's description of the problem.
        message: String,
    },

    /// The image is empty or larger than the supported maximum (checked before any pixel
    /// storage is allocated).
    #[error(
        "{}: image size {width}×{height} is not supported (expected 1 to {max_dim} pixels per \
         side and at most {max_pixels} pixels)",
        .path.display(),
        max_dim = super::MAX_DIMENSION,
        max_pixels = super::MAX_PIXELS
    )]
    InvalidDimensions {
        /// The file concerned.
        path: PathBuf,
        /// The width found or given.
        width: u64,
        /// The height found or given.
        height: u64,
    },

    /// The pixel buffer's length does not match `width × height`.
    #[error(
        "{}: {len} pixels given for a {width}×{height} image (expected width × height = {})",
        .path.display(),
        (*.width as u128) * (*.height as u128)
    )]
    PixelCountMismatch {
        /// The file concerned.
        path: PathBuf,
        /// The declared width.
        width: usize,
        /// The declared height.
        height: usize,
        /// The actual number of pixels.
        len: usize,
    },

    /// The exposure passed to [`write_png`](super::write_png) is NaN or infinite.
    #[error(
        "{}: exposure {exposure_ev} EV is not finite (expected a finite number of stops)",
        .path.display()
    )]
    InvalidExposure {
        /// The target file.
        path: PathBuf,
        /// The exposure given.
        exposure_ev: f64,
    },
}

impl ImageError {
    /// The file this error concerns (the target path for writes; [`IN_MEMORY`] for
    /// in-memory texels).
    pub fn path(&self) -> &Path {
        match self {
            Self::Io { path, .. }
            | Self::UnsupportedFormat { path }
            | Self::Decode { path, .. }
            | Self::Encode { path, .. }
            | Self::InvalidDimensions { path, .. }
            | Self::PixelCountMismatch { path, .. }
            | Self::InvalidExposure { path, .. } => path,
        }
    }
}
