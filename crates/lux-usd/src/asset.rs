//! Reading the files a scene's asset paths resolve to — plain files, or entries of a `.usdz`
//! package (`pkg.usdz[textures/a.png]`, the package-relative form the loader produces for
//! assets inside a package).

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

/// Whether a resolved path names an entry inside a package (`pkg.usdz[inner/path]`).
pub fn is_package_relative(path: &Path) -> bool {
    is_package_relative_path(&path.to_string_lossy())
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
    }
}
