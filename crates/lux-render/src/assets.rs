//! Reading the files a scene's asset paths resolve to — plain files, or entries of a `.usdz`
//! package (`pkg.usdz[textures/a.png]`, the package-relative form the loader produces for
//! assets inside a package).

use crate::image_io::{ImageError, Texture};
use openusd::ar::{
    DefaultResolver, ResolvedPath, Resolver, is_package_relative_path, join_package_relative_path,
    split_package_relative_path_outer,
};
use std::io::Read;
use std::path::Path;

/// Largest asset read into memory (IES profiles, packaged textures): 1 GiB.
pub const MAX_ASSET_BYTES: u64 = 1 << 30;

/// The bytes of the asset at resolved `path` (a file, or a package entry), at most
/// [`MAX_ASSET_BYTES`].
pub fn read_asset(path: &Path) -> std::io::Result<Vec<u8>> {
    let p = path.to_string_lossy();
    let reader: Box<dyn Read> = if is_package_relative_path(&p) {
        Box::new(DefaultResolver::new().open_asset(&ResolvedPath::new(path))?)
    } else {
        Box::new(std::fs::File::open(path)?)
    };
    let mut bytes = Vec::new();
    reader.take(MAX_ASSET_BYTES + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > MAX_ASSET_BYTES {
        return Err(std::io::Error::other(format!(
            "larger than {MAX_ASSET_BYTES} bytes"
        )));
    }
    Ok(bytes)
}

/// The asset named `name` next to the asset at resolved `path` (in the same package directory
/// for a package entry): what a `TILT=<file>` line of an IES profile refers to.
pub fn sibling(path: &Path, name: &str) -> std::path::PathBuf {
    let p = path.to_string_lossy();
    if let Some((package, inner)) = split_package_relative_path_outer(&p) {
        let inner_dir = Path::new(&inner).parent().unwrap_or(Path::new(""));
        let entry = inner_dir.join(name);
        return join_package_relative_path(&package, &entry.to_string_lossy()).into();
    }
    path.parent().unwrap_or(Path::new("")).join(name)
}

/// A texture at resolved `path`: decoded from the file directly, or from the package entry's
/// bytes (the entry name's extension gives the format).
pub fn load_texture(path: &Path) -> Result<Texture, ImageError> {
    if !is_package_relative_path(&path.to_string_lossy()) {
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
    fn siblings_stay_in_their_package() {
        assert_eq!(
            sibling(Path::new("/x/a.ies"), "t.dat"),
            Path::new("/x/t.dat")
        );
        assert_eq!(
            sibling(Path::new("/x/p.usdz[assets/a.ies]"), "t.dat").to_string_lossy(),
            "/x/p.usdz[assets/t.dat]"
        );
        assert!(read_asset(Path::new("/no/such/p.usdz[a.ies]")).is_err());
        assert!(load_texture(Path::new("/no/such/p.usdz[a.png]")).is_err());
    }
}
