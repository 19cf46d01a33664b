//! Decoding textures a scene's asset paths resolve to — plain files, or entries of a `.usdz`
//! package (`pkg.usdz[textures/a.png]`); the bytes come from [`lux_usd::asset::read_asset`] —
//! at once ([`load_texture`]) or on first use ([`TextureFile`]).

use crate::image_io::{ImageError, Texture};
use lux_usd::asset::{is_package_relative, read_asset};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// A texture at resolved `path`: decoded from the file directly, or from the package entry's
/// bytes (the entry name's extension gives the format).
pub fn load_texture(path: &Path) -> Result<Texture, ImageError> {
    read_either(path, Texture::load, Texture::from_bytes)
}

/// Checks from its header alone that [`load_texture`] could start decoding `path`
/// ([`Texture::probe`]): the file or package entry exists, its format is one lux reads, its
/// header parses and its size is within the limits.
pub fn probe_texture(path: &Path) -> Result<(), ImageError> {
    read_either(path, Texture::probe, Texture::probe_bytes)
}

/// `file(path)` for a plain file; for a package entry, `bytes(entry name, entry bytes)`.
fn read_either<T>(
    path: &Path,
    file: impl FnOnce(&Path) -> Result<T, ImageError>,
    bytes: impl FnOnce(&Path, &[u8]) -> Result<T, ImageError>,
) -> Result<T, ImageError> {
    if !is_package_relative(path) {
        return file(path);
    }
    let data = read_asset(path).map_err(|source| ImageError::Io {
        path: path.to_path_buf(),
        action: "read",
        source,
    })?;
    // `pkg.usdz[dir/tex.png]`: the format is the entry's extension.
    let name = path.to_string_lossy();
    let entry = name.trim_end_matches(']');
    bytes(Path::new(entry), &data).map_err(|e| match e {
        ImageError::UnsupportedFormat { .. } => ImageError::UnsupportedFormat {
            path: path.to_path_buf(),
        },
        other => other,
    })
}

/// A texture file decoded once: up front ([`TextureFile::decoded`]) or by the first lookup
/// that needs it ([`TextureFile::get`]), so that a render never decodes a file no ray reads
/// (a direct-lit frame shades only what the camera sees). The texels are the same either
/// way; a file that fails to decode keeps its error message.
#[derive(Debug)]
pub struct TextureFile {
    path: PathBuf,
    texture: OnceLock<Result<Texture, String>>,
}

impl TextureFile {
    /// The file at `path`, decoded on first use.
    pub fn lazy(path: PathBuf) -> TextureFile {
        TextureFile {
            path,
            texture: OnceLock::new(),
        }
    }

    /// The file at `path` with what decoding it gave.
    pub fn decoded(path: PathBuf, texture: Result<Texture, String>) -> TextureFile {
        TextureFile {
            path,
            texture: OnceLock::from(texture),
        }
    }

    /// The resolved path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The texels, decoding the file on the first call; `None` if it cannot be decoded.
    ///
    /// The first caller decodes on threads of a rayon pool of its own, started from a thread
    /// outside the caller's pool, while any other caller waits: a render worker blocked here
    /// must not be handed render work by its pool's work stealing (which could come back to
    /// the same file), and the waiting workers must not be what the decode waits for.
    #[inline]
    pub fn get(&self) -> Option<&Texture> {
        self.texture
            .get_or_init(|| decode_apart(&self.path))
            .as_ref()
            .ok()
    }

    /// Whether the file has been decoded (or its decoding failed).
    pub fn is_decoded(&self) -> bool {
        self.texture.get().is_some()
    }

    /// Why the file could not be decoded, once that is known.
    pub fn failure(&self) -> Option<&str> {
        self.texture.get()?.as_ref().err().map(String::as_str)
    }
}

/// [`load_texture`] of `path` on a thread pool of its own (as many threads as the calling
/// pool), entered from a new thread outside every pool (see [`TextureFile::get`]).
fn decode_apart(path: &Path) -> Result<Texture, String> {
    let threads = rayon::current_num_threads();
    std::thread::scope(|s| {
        let decode = || {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|e| format!("cannot start threads to decode it: {e}"))?;
            pool.install(|| load_texture(path))
                .map_err(|e| e.to_string())
        };
        match std::thread::Builder::new().spawn_scoped(s, decode) {
            Ok(thread) => thread
                .join()
                .unwrap_or_else(|_| Err("the decoding thread panicked".to_owned())),
            Err(e) => Err(format!("cannot start a thread to decode it: {e}")),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_package_entries_are_errors() {
        assert!(load_texture(Path::new("/no/such/p.usdz[a.png]")).is_err());
        assert!(probe_texture(Path::new("/no/such/p.usdz[a.png]")).is_err());
    }
}
