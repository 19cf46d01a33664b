//! Running the `lux` binary in the CLI tests.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `name` in this test process's scratch directory under the system's temporary directory.
pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("lux-cli-tests-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// `lux args…` with `env` set; `$LUX_CONFORMANCE_PROFILE` and the user's config files (an
/// empty `XDG_CONFIG_HOME`) kept out.
pub fn lux(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_lux"));
    c.args(args).env_remove("LUX_CONFORMANCE_PROFILE");
    c.env("XDG_CONFIG_HOME", scratch("no-config"));
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().unwrap()
}

/// `lux render <scene> --spp 1 --resolution 8x8 -o <out> <extra…> --quiet` (a quick render).
pub fn render_small(scene: &Path, out: &Path, extra: &[&str], env: &[(&str, &str)]) -> Output {
    let mut a = vec![
        "render",
        scene.to_str().unwrap(),
        "--spp",
        "1",
        "--resolution",
        "8x8",
        "-o",
        out.to_str().unwrap(),
    ];
    a.extend_from_slice(extra);
    a.push("--quiet");
    lux(&a, env)
}
