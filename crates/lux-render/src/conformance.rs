//! Which conformance profile a render uses, and which source decided it.
//!
//! The chain follows the compatibility switch of the UsdLux quantities proposal (spec README
//! §5), with lux's command-line flag in front:
//! 1. the `--profile` flag;
//! 2. the custom attribute `lux:conformanceProfile` on the stage's (first) RenderSettings prim;
//! 3. the environment variable [`PROFILE_ENV`] (`LUX_CONFORMANCE_PROFILE`);
//! 4. the config files, first `$XDG_CONFIG_HOME/lux/config.toml` (`$HOME/.config/...` when
//!    `XDG_CONFIG_HOME` is unset), then `/etc/lux/config.toml`, key
//!    `conformance_profile = "hdembree"`;
//! 5. the default, `spec`.
//!
//! A value that is present but not `spec`/`hdembree` is an error naming where it came from
//! (never a silent fallback); a config file that does not exist is skipped, one that exists but
//! cannot be read or parsed is an error naming the file.

use lux_math::Profile;
use lux_usd::Scene;
use std::fmt;
use std::path::{Path, PathBuf};

/// The environment variable of step 3.
pub const PROFILE_ENV: &str = "LUX_CONFORMANCE_PROFILE";

/// The config-file key of step 4.
pub const CONFIG_KEY: &str = "conformance_profile";

/// Where the profile came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ProfileSource {
    /// The `--profile` command-line flag.
    CommandLine,
    /// `lux:conformanceProfile` on this RenderSettings prim.
    RenderSettings(String),
    /// The environment variable [`PROFILE_ENV`].
    Environment,
    /// This config file.
    ConfigFile(PathBuf),
    /// Nothing set it: the `spec` default.
    Default,
}

impl fmt::Display for ProfileSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ProfileSource::CommandLine => f.write_str("--profile flag"),
            ProfileSource::RenderSettings(p) => write!(f, "lux:conformanceProfile on <{p}>"),
            ProfileSource::Environment => write!(f, "environment variable {PROFILE_ENV}"),
            ProfileSource::ConfigFile(p) => write!(f, "config file {}", p.display()),
            ProfileSource::Default => f.write_str("default"),
        }
    }
}

/// A profile and the source that decided it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ResolvedProfile {
    /// The profile.
    pub profile: Profile,
    /// Who chose it.
    pub source: ProfileSource,
}

/// A present but invalid profile setting.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("conformance profile from {origin}: {message}")]
pub struct ProfileError {
    /// Where the bad value was found.
    pub origin: ProfileSource,
    /// What is wrong and what was expected.
    pub message: String,
}

/// The config files of step 4, in order: `$XDG_CONFIG_HOME/lux/config.toml` (or
/// `$HOME/.config/lux/config.toml`), then `/etc/lux/config.toml`.
pub fn default_config_paths() -> Vec<PathBuf> {
    let mut out = Vec::new();
    match std::env::var_os("XDG_CONFIG_HOME").filter(|v| !v.is_empty()) {
        Some(x) => out.push(PathBuf::from(x).join("lux/config.toml")),
        None => {
            if let Some(h) = std::env::var_os("HOME").filter(|v| !v.is_empty()) {
                out.push(PathBuf::from(h).join(".config/lux/config.toml"));
            }
        }
    }
    out.push(PathBuf::from("/etc/lux/config.toml"));
    out
}

fn parse(value: &str, source: ProfileSource) -> Result<ResolvedProfile, ProfileError> {
    value
        .parse::<Profile>()
        .map(|profile| ResolvedProfile {
            profile,
            source: source.clone(),
        })
        .map_err(|e| ProfileError {
            origin: source,
            message: e.to_string(),
        })
}

/// The `conformance_profile` of a TOML config file: `Ok(None)` when the file does not exist or
/// does not set the key.
pub fn read_config(path: &Path) -> Result<Option<String>, ProfileError> {
    let src = ProfileSource::ConfigFile(path.to_path_buf());
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => {
            return Err(ProfileError {
                origin: src,
                message: format!("cannot read the file: {e}"),
            });
        }
    };
    let table: toml::Table = text.parse().map_err(|e: toml::de::Error| ProfileError {
        origin: src.clone(),
        message: format!("not valid TOML: {}", e.to_string().trim_end()),
    })?;
    match table.get(CONFIG_KEY) {
        None => Ok(None),
        Some(toml::Value::String(s)) => Ok(Some(s.clone())),
        Some(other) => Err(ProfileError {
            origin: src,
            message: format!(
                "{CONFIG_KEY} must be a string (\"spec\" or \"hdembree\"), found {}",
                other.type_str()
            ),
        }),
    }
}

/// Resolves the profile through the chain. `env` is the value of [`PROFILE_ENV`] (passed in so
/// that callers and tests control it); an empty value counts as unset.
pub fn resolve_profile(
    flag: Option<Profile>,
    scene: &Scene,
    env: Option<&str>,
    config_paths: &[PathBuf],
) -> Result<ResolvedProfile, ProfileError> {
    if let Some(profile) = flag {
        return Ok(ResolvedProfile {
            profile,
            source: ProfileSource::CommandLine,
        });
    }
    if let Some(s) = scene.render_settings.first()
        && let Some(v) = &s.conformance_profile
    {
        return parse(v, ProfileSource::RenderSettings(s.path.clone()));
    }
    if let Some(v) = env.filter(|v| !v.trim().is_empty()) {
        return parse(v, ProfileSource::Environment);
    }
    for p in config_paths {
        if let Some(v) = read_config(p)? {
            return parse(&v, ProfileSource::ConfigFile(p.clone()));
        }
    }
    Ok(ResolvedProfile {
        profile: Profile::Spec,
        source: ProfileSource::Default,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use lux_usd::{RenderBase, RenderSettings, Scene};

    fn scene(attr: Option<&str>) -> Scene {
        Scene {
            render_settings: vec![RenderSettings {
                path: "/Render/Settings".into(),
                base: RenderBase::default(),
                included_purposes: vec![],
                products: vec![],
                conformance_profile: attr.map(str::to_owned),
            }],
            ..Scene::empty("s.usda")
        }
    }

    fn tmp(name: &str, text: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("lux-conf-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("config.toml");
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn chain_order() {
        let cfg = tmp("order", "conformance_profile = \"hdembree\"\n");
        let none = scene(None);
        let attr = scene(Some("hdembree"));
        // Flag beats everything.
        let r = resolve_profile(
            Some(Profile::Spec),
            &attr,
            Some("hdembree"),
            std::slice::from_ref(&cfg),
        )
        .unwrap();
        assert_eq!(
            (r.profile, r.source),
            (Profile::Spec, ProfileSource::CommandLine)
        );
        // Then the RenderSettings attribute.
        let r = resolve_profile(None, &attr, Some("spec"), std::slice::from_ref(&cfg)).unwrap();
        assert_eq!(r.profile, Profile::HdEmbree);
        assert_eq!(
            r.source,
            ProfileSource::RenderSettings("/Render/Settings".into())
        );
        // Then the environment.
        let r = resolve_profile(None, &none, Some("spec"), std::slice::from_ref(&cfg)).unwrap();
        assert_eq!(
            (r.profile, r.source),
            (Profile::Spec, ProfileSource::Environment)
        );
        // Then the first config file that sets the key (a missing one is skipped).
        let missing = cfg.with_file_name("absent.toml");
        let r = resolve_profile(None, &none, Some("  "), &[missing, cfg.clone()]).unwrap();
        assert_eq!(
            (r.profile, r.source),
            (Profile::HdEmbree, ProfileSource::ConfigFile(cfg))
        );
        // Else the default.
        let r = resolve_profile(None, &none, None, &[]).unwrap();
        assert_eq!(
            (r.profile, r.source),
            (Profile::Spec, ProfileSource::Default)
        );
    }

    #[test]
    fn bad_values_are_errors_naming_their_source() {
        let e = resolve_profile(None, &scene(Some("embree")), None, &[]).unwrap_err();
        assert!(
            e.to_string().contains("/Render/Settings") && e.to_string().contains("embree"),
            "{e}"
        );
        let e = resolve_profile(None, &scene(None), Some("fast"), &[]).unwrap_err();
        assert_eq!(e.origin, ProfileSource::Environment);
        let cfg = tmp("bad", "conformance_profile = 3\n");
        let e = resolve_profile(None, &scene(None), None, std::slice::from_ref(&cfg)).unwrap_err();
        assert!(e.to_string().contains("must be a string"), "{e}");
        let cfg = tmp("garbage", "conformance_profile = \n[[");
        let e = resolve_profile(None, &scene(None), None, std::slice::from_ref(&cfg)).unwrap_err();
        assert!(
            e.to_string().contains("not valid TOML") && e.to_string().contains("config.toml"),
            "{e}"
        );
        // A file without the key falls through.
        let cfg = tmp("other", "[render]\nspp = 4\n");
        let r = resolve_profile(None, &scene(None), None, &[cfg]).unwrap();
        assert_eq!(r.source, ProfileSource::Default);
    }
}
