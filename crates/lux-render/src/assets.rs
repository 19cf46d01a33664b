//! Decoding textures a scene's asset paths resolve to — plain files, or entries of a `.usdz`
//! package (`pkg.usdz[textures/a.png]`); the bytes come from [`lux_usd::asset::read_asset`].

use crate::image_io::{ImageError, Texture};
use lux_usd::asset::{is_package_relative, read_asset};
use std::path::Path;

/// A texture at resolved `path`: decoded from the file directly, or from the package entry's
/// bytes (the entry name's extension gives the format).
pub fn load_texture(path: &Path) -> Result<Texture, ImageError> {
    if !is_package_relative(path) {
        return Texture::load(path);
    }
    let bytes = read_asset(path).map_err(|source| ImageError::Io {
        path: path.to_path_buf(),
        action: "read",
        source,
    })?;
    // `pkg.usdz[dir/tex.png]`: the format is the entry's extension.
    let name = path.to_string_lossy();
    let entry = name.trim_end_matches(']');
    Texture::from_bytes(Path::new(entry), &bytes).map_err(|e| match e {
        ImageError::UnsupportedFormat { .. } => ImageError::UnsupportedFormat {
            path: path.to_path_buf(),
        },
        other => other,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_package_entries_are_errors() {
        assert!(load_texture(Path::new("/no/such/p.usdz[a.png]")).is_err());
    }
}
