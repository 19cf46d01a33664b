//! The asset resolver the loader hands to `openusd`: the crate's `DefaultResolver` plus the
//! compatibility rewrites of [`crate::compat`] applied when a layer is opened (the `.usda` pass
//! of [`crate::compat::usda`], the crate time-sample fix of [`crate::compat::usdc`]), and the
//! refusal of layers holding paths that would hang composition ([`crate::path_guard`]).

use crate::path_guard::{first_unwalkable_path, usda_may_hold_unwalkable_path};
use openusd::ar::{self, Asset, DefaultResolver, ResolvedPath, Resolver};
use std::io;

/// `DefaultResolver` (filesystem paths relative to the authoring layer, `.usdz` packages) that
/// serves `openusd` each layer rewritten by [`crate::compat`] (text layers by its `.usda` pass,
/// crate layers older than 0.7.0 by its time-sample fix).
///
/// It can also serve one in-memory `.usda` layer under a fixed identifier (for loading a stage
/// from a string).
#[derive(Default)]
pub struct LuxResolver {
    inner: DefaultResolver,
    memory: Option<(String, Vec<u8>)>,
    /// The last text layer served (its resolved path and rewritten bytes): `openusd` 0.6
    /// opens a stage's root layer twice (once for its expression variables, once to compose
    /// it), and the second time is served from here rather than read and rewritten again.
    last_text: std::sync::Mutex<Option<(String, Vec<u8>)>>,
}

impl LuxResolver {
    /// A resolver with no search paths.
    pub fn new() -> LuxResolver {
        LuxResolver {
            inner: DefaultResolver::new(),
            memory: None,
            last_text: Default::default(),
        }
    }

    /// A resolver that also serves `bytes` as the layer `identifier` (which must end in
    /// `.usda`).
    pub fn with_memory_layer(identifier: &str, bytes: Vec<u8>) -> LuxResolver {
        LuxResolver {
            inner: DefaultResolver::new(),
            memory: Some((identifier.to_owned(), bytes)),
            last_text: Default::default(),
        }
    }

    fn memory(&self, path: &str) -> Option<&[u8]> {
        match &self.memory {
            Some((id, bytes)) if id == path => Some(bytes),
            _ => None,
        }
    }
}

/// The error for a layer holding a path `openusd` cannot walk ([`crate::path_guard`]).
fn unwalkable(layer: &str, path: &str) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidData,
        format!(
            "{layer}: malformed prim path <{path}> (a prim path may end in `}}` only after a \
             variant selection `{{set=sel}}`)"
        ),
    )
}

/// The scheme of a URI-like asset path (`http` in `http://host/a.usda`): letters, digits, `+`,
/// `-`, `.` before `://`, at least two characters (so `C:/…` stays a Windows path).
pub(crate) fn uri_scheme(path: &str) -> Option<&str> {
    let (scheme, _) = path.split_once("://")?;
    let ok = scheme.len() >= 2
        && scheme.starts_with(|c: char| c.is_ascii_alphabetic())
        && scheme
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'));
    ok.then_some(scheme)
}

/// Whether a resolved path names a text layer, including a `.usda` inside a package
/// (`pkg.usdz[inner.usda]`).
fn is_text_layer(path: &str) -> bool {
    let p = path.trim_end_matches(']');
    p.rsplit('.')
        .next()
        .is_some_and(|ext| ext.eq_ignore_ascii_case("usda"))
}

/// The `#usda` magic a text layer starts with (a `.usd` file may hold text, and `openusd`
/// reads such a file as text when it does not start with the crate magic).
const USDA_MAGIC: &[u8] = b"#usda";

impl Resolver for LuxResolver {
    fn create_identifier(&self, asset_path: &str, anchor: Option<&ResolvedPath>) -> String {
        if anchor.is_none() && self.memory(asset_path).is_some() {
            return asset_path.to_owned();
        }
        // A URI (`http://…`, `omniverse://…`) is an identifier of its own: anchoring it at a
        // layer's directory would mangle it into a local path (`dir/http:/host/…`).
        if uri_scheme(asset_path).is_some() {
            return asset_path.to_owned();
        }
        self.inner.create_identifier(asset_path, anchor)
    }

    fn resolve(&self, asset_path: &str) -> Option<ResolvedPath> {
        if self.memory(asset_path).is_some() {
            return Some(ResolvedPath::new(asset_path));
        }
        // lux resolves files and package entries only: a URI does not resolve (the arc is
        // reported unresolved, naming the URI as written).
        if uri_scheme(asset_path).is_some() {
            return None;
        }
        let resolved = self.inner.resolve(asset_path)?;
        // A MaterialX document resolves to a `.usda` stand-in (openusd picks a layer's format
        // by the resolved path's extension), served as its usdMtlx translation below.
        Some(crate::mtlx::usdmtlx::stand_in(resolved))
    }

    fn resolve_for_new_asset(&self, asset_path: &str) -> Option<ResolvedPath> {
        self.inner.resolve_for_new_asset(asset_path)
    }

    fn open_asset(&self, resolved_path: &ResolvedPath) -> io::Result<Box<dyn Asset>> {
        let name = resolved_path.to_string_lossy();
        if let Ok(last) = self.last_text.lock()
            && let Some((id, bytes)) = last.as_ref()
            && *id == name
        {
            return Ok(Box::new(io::Cursor::new(bytes.clone())));
        }
        let bytes = if let Some(b) = self.memory(&name) {
            b.to_vec()
        } else {
            let mtlx = crate::mtlx::usdmtlx::stand_in_source(&name);
            let source = mtlx
                .as_deref()
                .map_or_else(|| resolved_path.clone(), ResolvedPath::new);
            let mut asset = self.inner.open_asset(&source)?;
            let mut bytes = asset.read_all()?;
            if let Some(doc) = &mtlx {
                bytes = crate::mtlx::usdmtlx::layer_bytes(doc, &bytes)
                    .map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e.to_string()))?;
            }
            if !is_text_layer(&name) && !bytes.starts_with(USDA_MAGIC) {
                if bytes.starts_with(openusd::usdc::MAGIC) {
                    // a crate layer: times of old crate versions in the layout openusd reads,
                    // then the same path screen as for text, on its own parse
                    crate::compat::usdc::fix_time_samples(&mut bytes);
                    let screened =
                        crate::compat::usdc::read_crate(&bytes, |d| first_unwalkable_path(d))
                            .map_err(|why| {
                                io::Error::new(
                                    io::ErrorKind::InvalidData,
                                    format!("{name}: malformed crate layer ({why})"),
                                )
                            })?;
                    if let Some(p) = screened.flatten() {
                        return Err(unwalkable(&name, &p));
                    }
                }
                return Ok(Box::new(io::Cursor::new(bytes)));
            }
            bytes
        };
        let fixed = std::str::from_utf8(&bytes)
            .ok()
            .and_then(crate::compat::usda::rewrite);
        let bytes = match fixed {
            Some(r) => r.text.into_bytes(),
            None => bytes,
        };
        if let Ok(text) = std::str::from_utf8(&bytes)
            && usda_may_hold_unwalkable_path(text)
            && let Ok(data) = openusd::usda::parse(text)
            && let Some(p) = first_unwalkable_path(&data)
        {
            return Err(unwalkable(&name, &p));
        }
        if let Ok(mut last) = self.last_text.lock() {
            *last = Some((name.into_owned(), bytes.clone()));
        }
        Ok(Box::new(io::Cursor::new(bytes)))
    }

    fn get_extension<'a>(&self, asset_path: &'a str) -> &'a str {
        self.inner.get_extension(asset_path)
    }

    fn get_asset_info(&self, asset_path: &str, resolved_path: &ResolvedPath) -> ar::AssetInfo {
        if self.memory(asset_path).is_some() {
            return ar::AssetInfo::default();
        }
        self.inner.get_asset_info(asset_path, resolved_path)
    }

    fn get_modification_timestamp(
        &self,
        asset_path: &str,
        resolved_path: &ResolvedPath,
    ) -> Option<std::time::SystemTime> {
        if self.memory(asset_path).is_some() {
            return None;
        }
        self.inner
            .get_modification_timestamp(asset_path, resolved_path)
    }

    fn identity(&self) -> String {
        match &self.memory {
            Some((id, _)) => format!("lux:{}:memory:{id}", self.inner.identity()),
            None => format!("lux:{}", self.inner.identity()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A text layer opened twice in a row (as `openusd` opens a stage's root layer) is read
    /// and rewritten once: the second open is served the same bytes though the file is gone.
    #[test]
    fn a_text_layer_opened_twice_is_read_once() {
        let dir = std::env::temp_dir().join(format!("lux-resolver-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("twice.usda");
        std::fs::write(&path, "#usda 1.0\ndef Xform \"A\"\n{\n}\n").unwrap();
        let r = LuxResolver::new();
        let resolved = r.resolve(path.to_str().unwrap()).unwrap();
        let first = r.open_asset(&resolved).unwrap().read_all().unwrap();
        std::fs::remove_file(&path).unwrap();
        let second = r.open_asset(&resolved).unwrap().read_all().unwrap();
        assert_eq!(first, second);
        assert!(first.starts_with(b"#usda 1.0"));
        // Another resolver reads the disk: the file is gone.
        assert!(LuxResolver::new().open_asset(&resolved).is_err());
        std::fs::remove_dir_all(&dir).ok();
    }
}
