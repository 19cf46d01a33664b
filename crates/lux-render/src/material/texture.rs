//! `UsdUVTexture` feeding a UsdPreviewSurface input: the file, `st` lookup (through a
//! `UsdTransform2d` when authored) with `wrapS`/`wrapT`, `scale`, `bias`, `fallback`,
//! `sourceColorSpace` and the connected output.

use super::Param;
use crate::RenderError;
use crate::assets::{TextureFile, probe_texture};
use crate::image_io::linear_to_srgb;
use glam::{DVec2, DVec3, DVec4};
use lux_usd::{SourceColorSpace, TextureInput, Transform2d};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// How a texture coordinate outside \[0, 1\] is folded back (UsdUVTexture `wrapS`/`wrapT`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Wrap {
    Repeat,
    Mirror,
    Clamp,
    Black,
}

impl Wrap {
    /// The fold of a `UsdUVTexture` wrap mode; `useMetadata` without metadata in the file
    /// (lux's image readers carry none) repeats.
    fn of(mode: lux_usd::Wrap) -> Wrap {
        match mode {
            lux_usd::Wrap::Mirror => Wrap::Mirror,
            lux_usd::Wrap::Clamp => Wrap::Clamp,
            lux_usd::Wrap::Black => Wrap::Black,
            lux_usd::Wrap::Repeat | lux_usd::Wrap::UseMetadata => Wrap::Repeat,
        }
    }

    /// Folds `x` into \[0, 1\]; `None` for "black" outside the unit interval.
    #[inline]
    fn apply(self, x: f64) -> Option<f64> {
        if !x.is_finite() {
            return None;
        }
        Some(match self {
            Wrap::Repeat => x - x.floor(),
            Wrap::Clamp => x.clamp(0.0, 1.0),
            Wrap::Mirror => {
                let m = x.rem_euclid(2.0);
                if m > 1.0 { 2.0 - m } else { m }
            }
            Wrap::Black => {
                if (0.0..=1.0).contains(&x) {
                    x
                } else {
                    return None;
                }
            }
        })
    }
}

/// A prepared `UsdUVTexture` feeding a UsdPreviewSurface input.
#[derive(Clone, Debug)]
pub(super) struct TextureShader {
    tex: Arc<TextureFile>,
    /// The value of the input should the file fail to decode when first read (the texture's
    /// authored fallback, else the input's default, as [`texture_shader`] gives at once for a
    /// file that fails up front).
    on_failure: DVec3,
    /// A `UsdTransform2d` applied to the texture coordinates first.
    transform: Option<Transform2d>,
    scale: DVec4,
    bias: DVec4,
    fallback: DVec4,
    wrap: [Wrap; 2],
    /// `sourceColorSpace = "raw"` on an 8-bit file: undo the sRGB decode.
    raw: bool,
    /// Which output is connected: 0..=2 a single channel (r, g, b), 3 alpha, 4 rgb.
    output: u8,
}

impl TextureShader {
    /// The file it reads.
    #[cfg(test)]
    pub(super) fn file(&self) -> &TextureFile {
        &self.tex
    }

    /// The input's value at texture coordinates `st`.
    #[inline]
    pub(super) fn eval(&self, st: DVec2) -> DVec3 {
        let Some(tex) = self.tex.get() else {
            return self.on_failure;
        };
        let st = match &self.transform {
            Some(t) => t.apply(st),
            None => st,
        };
        let pick = |c: DVec4| -> DVec3 {
            match self.output {
                4 => c.truncate(),
                k => DVec3::splat(c[k as usize]),
            }
        };
        let (Some(u), Some(v)) = (self.wrap[0].apply(st.x), self.wrap[1].apply(st.y)) else {
            return pick(self.fallback);
        };
        // USD texture coordinates have (0, 0) at the image's bottom-left.
        let t = tex.bilinear(u, 1.0 - v);
        let mut c = DVec4::new(t[0] as f64, t[1] as f64, t[2] as f64, t[3] as f64);
        if self.raw {
            c = DVec4::new(
                linear_to_srgb(t[0]) as f64,
                linear_to_srgb(t[1]) as f64,
                linear_to_srgb(t[2]) as f64,
                c.w,
            );
        }
        pick(c * self.scale + self.bias)
    }
}

/// The texture files the materials read, each decoded once: all at once (what
/// `InputLoader::prefetch` decoded in parallel, else here), or on first use, their headers
/// checked now.
#[derive(Debug, Default)]
pub(super) struct TextureFiles {
    /// Every file opened, by resolved path.
    pub(super) files: HashMap<PathBuf, Arc<TextureFile>>,
    /// Decode a file when a lookup first needs it ([`TextureFile::get`]) rather than now.
    pub(super) on_first_use: bool,
    /// A file that cannot be read is an error rather than its fallback with a warning.
    pub(super) strict: bool,
    /// Each use a lookup reads of a file not yet decoded, with what its failure would mean
    /// ("material M uses … for input"): the warnings of files that fail when first read.
    pub(super) pending: Vec<(Arc<TextureFile>, String)>,
}

impl TextureFiles {
    /// The file at resolved `path`, opened once (its header checked), and decoded now unless
    /// files are decoded on first use or `read` is false (an input no lookup reads: a
    /// UsdPreviewSurface's USD-side `diffuseColor` where its graph shades, whose own image
    /// nodes read the file).
    fn open(&mut self, path: &Path, read: bool) -> Arc<TextureFile> {
        let tex = self
            .files
            .entry(path.to_path_buf())
            .or_insert_with(|| {
                let path = path.to_path_buf();
                Arc::new(match probe_texture(&path) {
                    Ok(()) => TextureFile::lazy(path),
                    Err(e) => TextureFile::decoded(path, Err(e.to_string())),
                })
            })
            .clone();
        if read && !self.on_first_use {
            // (what `InputLoader::prefetch` decoded already, or decoded here)
            tex.get();
        }
        tex
    }

    /// The warnings of the files that failed when first read during a render: the same
    /// words a file failing up front gives.
    pub(super) fn late_warnings(&self) -> impl Iterator<Item = String> + '_ {
        self.pending.iter().filter_map(|(f, consequence)| {
            f.failure()
                .map(|m| format!("{}: {m}; {consequence}", f.path().display()))
        })
    }
}

/// The input `input` of a material fed by a `UsdUVTexture`. A texture file that does not
/// resolve or cannot be read (missing, a format lux does not decode such as RenderMan `.tex`,
/// corrupt) is replaced, with a warning naming the material and the file (an error when
/// [`TextureFiles::strict`]), by the texture's `inputs:fallback` when authored, else by the
/// input's own default `default` (0.18 grey for `diffuseColor`): the surface stays visible and
/// lit, where the schema default (0, 0, 0, 1) would paint it black. A file decoded on first
/// use whose data then turns out corrupt gives the same value, its warning after the render
/// ([`TextureFiles::late_warnings`]). `read`: whether a lookup reads the input at all
/// ([`TextureFiles::open`]).
pub(super) fn texture_shader(
    material: &str,
    input: &str,
    default: DVec3,
    t: &TextureInput,
    files: &mut TextureFiles,
    read: bool,
    warnings: &mut Vec<String>,
) -> Result<Param, RenderError> {
    let Some(file) = &t.file else {
        return Ok(Param::Value(pick_output(t.fallback, &t.output)));
    };
    let (on_failure, what) = if t.fallback_authored {
        (
            pick_output(t.fallback, &t.output),
            "the texture's inputs:fallback".to_owned(),
        )
    } else {
        (default, format!("{input}'s default"))
    };
    let consequence = format!("material {material} uses {what} {on_failure} for {input}");
    let strict = files.strict;
    let failed = |file: &Path, message: &str, warnings: &mut Vec<String>| {
        if strict {
            return Err(RenderError::Asset {
                file: file.to_path_buf(),
                message: message.to_owned(),
            });
        }
        warnings.push(format!("{}: {message}; {consequence}", file.display()));
        Ok(Param::Value(on_failure))
    };
    let Some(path) = &file.resolved else {
        return failed(
            Path::new(&file.authored),
            &format!("texture of material {material} does not resolve to a file"),
            warnings,
        );
    };
    let tex = files.open(path, read);
    if let Some(message) = tex.failure() {
        return failed(path, message, warnings);
    }
    if read && !tex.is_decoded() {
        files.pending.push((tex.clone(), consequence.clone()));
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    Ok(Param::Texture(TextureShader {
        tex,
        on_failure,
        transform: t.transform,
        scale: t.scale,
        bias: t.bias,
        fallback: t.fallback,
        wrap: [Wrap::of(t.wrap_s), Wrap::of(t.wrap_t)],
        raw: t.source_color_space == SourceColorSpace::Raw
            && !matches!(ext.as_str(), "exr" | "hdr"),
        output: output_index(&t.output),
    }))
}

/// The connected output of a texel (or fallback) `c`: `rgb`, or one channel splatted.
fn pick_output(c: DVec4, output: &str) -> DVec3 {
    match output_index(output) {
        4 => c.truncate(),
        k => DVec3::splat(c[k as usize]),
    }
}

fn output_index(name: &str) -> u8 {
    match name {
        "r" => 0,
        "g" => 1,
        "b" => 2,
        "a" => 3,
        _ => 4,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_modes() {
        assert_eq!(Wrap::Repeat.apply(1.25), Some(0.25));
        assert_eq!(Wrap::Repeat.apply(-0.25), Some(0.75));
        assert_eq!(Wrap::Clamp.apply(1.5), Some(1.0));
        assert_eq!(Wrap::Mirror.apply(1.25), Some(0.75));
        assert_eq!(Wrap::Mirror.apply(-0.25), Some(0.25));
        assert_eq!(Wrap::Black.apply(1.5), None);
        assert_eq!(Wrap::Black.apply(0.5), Some(0.5));
        assert_eq!(Wrap::Repeat.apply(f64::NAN), None);
        assert_eq!(Wrap::of(lux_usd::Wrap::UseMetadata), Wrap::Repeat);
        assert_eq!(Wrap::of(lux_usd::Wrap::Mirror), Wrap::Mirror);
    }
}
