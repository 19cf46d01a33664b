//! The asset resolver the loader hands to `openusd`: the crate's `DefaultResolver` plus the
//! `.usda` text fix of [`crate::usda_fix`] applied when a layer is opened, and the refusal of
//! layers holding paths that would hang composition ([`crate::path_guard`]).

use crate::path_guard::{first_unwalkable_path, usda_may_hold_unwalkable_path};
use openusd::ar::{self, Asset, DefaultResolver, ResolvedPath, Resolver};
use openusd::usdc::CrateData;
use std::io;

/// `DefaultResolver` (filesystem paths relative to the authoring layer, `.usdz` packages) that
/// rewrites scalar asset time samples in `.usda` layers before `openusd` parses them.
///
/// It can also serve one in-memory `.usda` layer under a fixed identifier (for loading a stage
/// from a string).
#[derive(Default)]
pub struct LuxResolver {
    inner: DefaultResolver,
    memory: Option<(String, Vec<u8>)>,
}

impl LuxResolver {
    /// A resolver with no search paths.
    pub fn new() -> LuxResolver {
        LuxResolver {
            inner: DefaultResolver::new(),
            memory: None,
        }
    }

    /// A resolver that also serves `bytes` as the layer `identifier` (which must end in
    /// `.usda`).
    pub fn with_memory_layer(identifier: &str, bytes: Vec<u8>) -> LuxResolver {
        LuxResolver {
            inner: DefaultResolver::new(),
            memory: Some((identifier.to_owned(), bytes)),
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

/// Whether a resolved path names a text layer, including a `.usda` inside a package
/// (`pkg.usdz[inner.usda]`).
fn is_text_layer(path: &str) -> bool {
    let p = path.trim_end_matches(']');
    p.rsplit('.')
        .next()
        .is_some_and(|ext| ext.eq_ignore_ascii_case("usda"))
}

impl Resolver for LuxResolver {
    fn create_identifier(&self, asset_path: &str, anchor: Option<&ResolvedPath>) -> String {
        if anchor.is_none() && self.memory(asset_path).is_some() {
            return asset_path.to_owned();
        }
        self.inner.create_identifier(asset_path, anchor)
    }

    fn resolve(&self, asset_path: &str) -> Option<ResolvedPath> {
        if self.memory(asset_path).is_some() {
            return Some(ResolvedPath::new(asset_path));
        }
        self.inner.resolve(asset_path)
    }

    fn resolve_for_new_asset(&self, asset_path: &str) -> Option<ResolvedPath> {
        self.inner.resolve_for_new_asset(asset_path)
    }

    fn open_asset(&self, resolved_path: &ResolvedPath) -> io::Result<Box<dyn Asset>> {
        let name = resolved_path.to_string_lossy();
        let bytes = if let Some(b) = self.memory(&name) {
            b.to_vec()
        } else {
            let mut asset = self.inner.open_asset(resolved_path)?;
            let bytes = asset.read_all()?;
            if !is_text_layer(&name) {
                if bytes.starts_with(b"PXR-USDC") {
                    // a crate layer: the same path screen as for text, on its own parse
                    let data = CrateData::open(io::Cursor::new(&bytes[..]), true);
                    if let Some(p) = data.ok().and_then(|d| first_unwalkable_path(&d)) {
                        return Err(unwalkable(&name, &p));
                    }
                }
                return Ok(Box::new(io::Cursor::new(bytes)));
            }
            bytes
        };
        let fixed = std::str::from_utf8(&bytes)
            .ok()
            .and_then(crate::usda_fix::rewrite_asset_time_samples);
        let bytes = match fixed {
            Some(text) => text.into_bytes(),
            None => bytes,
        };
        if let Ok(text) = std::str::from_utf8(&bytes)
            && usda_may_hold_unwalkable_path(text)
            && let Ok(data) = openusd::usda::parse(text)
            && let Some(p) = first_unwalkable_path(&data)
        {
            return Err(unwalkable(&name, &p));
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
