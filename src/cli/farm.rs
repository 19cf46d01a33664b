//! `lux farm SCENE --frames A-B --tiles N -o job.yaml [-- render options]`: writes an Open Job
//! Description job template (`jobtemplate-2023-09`) that renders every frame as N tiles
//! (`lux render --tile`) and merges each frame's tiles (`lux merge`) once they are done. lux
//! schedules nothing itself: any OpenJD runner (`openjd run`, AWS Deadline Cloud, …) does.

use crate::cli::render::RenderArgs;
use clap::{Args, Parser};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Arguments of `lux farm`.
#[derive(Debug, Args)]
pub struct FarmArgs {
    /// The USD stage (the default of the job parameter ScenePath).
    pub scene: PathBuf,
    /// Frames to render, `A-B` (inclusive) or `A`: integer time codes.
    #[arg(long, value_parser = parse_frames, allow_hyphen_values = true)]
    pub frames: [i64; 2],
    /// Tiles (horizontal bands) per frame, each rendered by its own task.
    #[arg(long, default_value_t = 1)]
    pub tiles: u32,
    /// The job template to write (YAML).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Where the tasks write tiles and frames (the default of the job parameter OutputDir).
    #[arg(long, default_value = "frames")]
    pub output_dir: PathBuf,
    /// The lux executable on the workers (the default of the job parameter Lux).
    #[arg(long, default_value = "lux")]
    pub lux: String,
    /// Base name of the output files `<name>.<frame>.exr` (default: the scene's file stem).
    #[arg(long)]
    pub name: Option<String>,
    /// The merge step also writes `<name>.<frame>.png`.
    #[arg(long)]
    pub png: bool,
    /// `lux render` options for every tile (--spp, --resolution, --camera, --seed, …), after
    /// the other arguments or after `--`.
    #[arg(trailing_var_arg = true, allow_hyphen_values = true, num_args = 0..)]
    pub render_args: Vec<String>,
}

/// Parses `A-B` or `A` (integers, `A ≤ B`; negative frames allowed: `-2-3`, `-5--1`).
pub fn parse_frames(s: &str) -> Result<[i64; 2], String> {
    let t = s.trim();
    let bad = || format!("frames {s:?}: expected A-B or A, integers with A ≤ B");
    // The separator is the first '-' after the first character.
    let (a, b) = match t.char_indices().skip(1).find(|&(_, c)| c == '-') {
        Some((i, _)) => (&t[..i], &t[i + 1..]),
        None => (t, t),
    };
    let a: i64 = a.parse().map_err(|_| bad())?;
    let b: i64 = b.parse().map_err(|_| bad())?;
    if a > b {
        return Err(bad());
    }
    Ok([a, b])
}

/// Render options the template sets itself, refused among the passed-through ones.
const OWN_OPTIONS: [&str; 7] = [
    "--frame",
    "--tile",
    "-o",
    "--output",
    "--png",
    "--exposure",
    "--quiet",
];

/// Checks the passed-through render options: none the template sets, no `{{` (an OpenJD format
/// string), and `lux render` accepts them.
fn check_render_args(args: &[String]) -> Result<(), String> {
    #[derive(Parser)]
    #[command(name = "lux render")]
    struct Probe {
        #[command(flatten)]
        render: RenderArgs,
    }
    let own = args.iter().find(|a| {
        OWN_OPTIONS
            .iter()
            .any(|o| a.as_str() == *o || a.starts_with(&format!("{o}=")))
            || (a.starts_with("-o") && !a.starts_with("--"))
    });
    if let Some(a) = own {
        return Err(format!(
            "render option {a}: the job template sets --frame, --tile, --quiet and the output \
             itself (see --output-dir, --name, --png)"
        ));
    }
    if let Some(a) = args.iter().find(|a| a.contains("{{")) {
        return Err(format!(
            "render option {a:?}: '{{{{' starts an OpenJD format string"
        ));
    }
    let mut argv = vec!["lux render".to_owned(), "scene.usda".to_owned()];
    argv.extend(args.iter().cloned());
    argv.extend(["-o".to_owned(), "out.exr".to_owned()]);
    Probe::try_parse_from(argv)
        .map(|_| ())
        .map_err(|e| format!("render options {args:?}: {}", e.render().to_string().trim()))
}

/// A YAML double-quoted scalar (JSON string syntax, which YAML 1.2 reads alike).
fn q(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_else(|_| "\"\"".to_owned())
}

/// A YAML flow sequence of quoted strings.
fn seq(items: &[String]) -> String {
    let quoted: Vec<String> = items.iter().map(|s| q(s)).collect();
    format!("[{}]", quoted.join(", "))
}

/// An absolute version of `p` (relative to the current directory), unresolved.
fn absolute(p: &Path) -> PathBuf {
    std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf())
}

/// `path` relative to the directory `base` (both made absolute), e.g. `../scenes/a.usda`; `None`
/// when they share no root (another drive).
fn relative_to(base: &Path, path: &Path) -> Option<PathBuf> {
    use std::path::Component;
    let (base, path) = (absolute(base), absolute(path));
    fn norm(p: &Path) -> Vec<Component<'_>> {
        p.components().filter(|c| *c != Component::CurDir).collect()
    }
    let (b, p) = (norm(&base), norm(&path));
    if b.first() != p.first() {
        return None;
    }
    let common = b.iter().zip(&p).take_while(|(x, y)| x == y).count();
    if b[common..].contains(&Component::ParentDir) {
        return None;
    }
    let mut out: PathBuf = b[common..].iter().map(|_| Component::ParentDir).collect();
    out.extend(&p[common..]);
    Some(if out.as_os_str().is_empty() {
        PathBuf::from(".")
    } else {
        out
    })
}

/// The job template of `args` (render options already checked).
pub fn template(args: &FarmArgs) -> Result<String, String> {
    if args.tiles == 0 {
        return Err("--tiles 0: expected at least 1".into());
    }
    let name = match &args.name {
        Some(n) => n.clone(),
        None => args
            .scene
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .ok_or_else(|| format!("{}: no file name", args.scene.display()))?,
    };
    if name.is_empty() || name.contains(['/', '\\']) || name.contains("{{") {
        return Err(format!(
            "--name {name:?}: expected a file name without separators or '{{{{'"
        ));
    }
    let [a, b] = args.frames;
    let n = args.tiles;
    // An INT range expression; negative frames as a list (a range expression reads '-' as the
    // separator).
    let frames = if a >= 0 {
        q(&format!("{a}-{b}"))
    } else {
        format!(
            "[{}]",
            (a..=b)
                .map(|f| f.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        )
    };
    let out =
        |suffix: &str| format!("{{{{Param.OutputDir}}}}/{name}.{{{{Task.Param.Frame}}}}{suffix}");
    let mut render = vec![
        "render".to_owned(),
        "{{Param.ScenePath}}".to_owned(),
        "--frame".to_owned(),
        "{{Task.Param.Frame}}".to_owned(),
        "--tile".to_owned(),
        format!("{{{{Task.Param.Tile}}}}/{n}"),
    ];
    render.extend(args.render_args.iter().cloned());
    render.extend([
        "--quiet".to_owned(),
        "-o".to_owned(),
        out(".tile{{Task.Param.Tile}}.exr"),
    ]);
    let mut merge = vec!["merge".to_owned()];
    merge.extend((0..n).map(|i| out(&format!(".tile{i}.exr"))));
    merge.extend(["-o".to_owned(), out(".exr")]);
    if args.png {
        merge.extend(["--png".to_owned(), out(".png")]);
        // `--alpha` among the render options is for the PNG, which the merge writes.
        if args.render_args.iter().any(|a| a == "--alpha") {
            merge.push("--alpha".to_owned());
        }
    }
    // OpenJD joins default paths to the template's directory and refuses absolute ones and
    // ones outside it: a path elsewhere has no default (the job must give it).
    let job_dir = absolute(&args.output)
        .parent()
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let default = |p: &Path| match relative_to(&job_dir, p) {
        Some(r) if !r.starts_with("..") => {
            format!("  default: {}", q(&r.to_string_lossy().replace('\\', "/")))
        }
        _ => format!(
            "  # (no default: {} is outside the template's directory)",
            p.display()
        ),
    };
    let job_name = format!("lux {name} {a}-{b}");
    let mut y = String::new();
    let w = &mut y;
    // (writing to a String cannot fail)
    let _ = writeln!(
        w,
        "# Open Job Description job template written by `lux farm`:"
    );
    let _ = writeln!(
        w,
        "# {n} tiles per frame, rendered in parallel, then merged per frame."
    );
    let _ = writeln!(w, "specificationVersion: jobtemplate-2023-09");
    let _ = writeln!(w, "name: {}", q(&job_name));
    let _ = writeln!(w, "parameterDefinitions:");
    let _ = writeln!(w, "- name: ScenePath");
    let _ = writeln!(w, "  type: PATH");
    let _ = writeln!(w, "  objectType: FILE");
    let _ = writeln!(w, "  dataFlow: IN");
    let _ = writeln!(w, "  description: The USD stage to render.");
    let _ = writeln!(w, "{}", default(&args.scene));
    let _ = writeln!(w, "- name: OutputDir");
    let _ = writeln!(w, "  type: PATH");
    let _ = writeln!(w, "  objectType: DIRECTORY");
    let _ = writeln!(w, "  dataFlow: OUT");
    let _ = writeln!(
        w,
        "  description: Where the tiles and the merged frames are written."
    );
    let _ = writeln!(w, "{}", default(&args.output_dir));
    let _ = writeln!(w, "- name: Lux");
    let _ = writeln!(w, "  type: STRING");
    let _ = writeln!(w, "  description: The lux executable on the workers.");
    let _ = writeln!(w, "  default: {}", q(&args.lux));
    let _ = writeln!(w, "steps:");
    let _ = writeln!(w, "- name: Render");
    let _ = writeln!(w, "  parameterSpace:");
    let _ = writeln!(w, "    taskParameterDefinitions:");
    let _ = writeln!(w, "    - name: Frame");
    let _ = writeln!(w, "      type: INT");
    let _ = writeln!(w, "      range: {frames}");
    let _ = writeln!(w, "    - name: Tile");
    let _ = writeln!(w, "      type: INT");
    let _ = writeln!(w, "      range: {}", q(&format!("0-{}", n - 1)));
    let _ = writeln!(w, "  script:");
    let _ = writeln!(w, "    actions:");
    let _ = writeln!(w, "      onRun:");
    let _ = writeln!(w, "        command: \"{{{{Param.Lux}}}}\"");
    let _ = writeln!(w, "        args: {}", seq(&render));
    let _ = writeln!(w, "- name: Merge");
    let _ = writeln!(w, "  dependencies:");
    let _ = writeln!(w, "  - dependsOn: Render");
    let _ = writeln!(w, "  parameterSpace:");
    let _ = writeln!(w, "    taskParameterDefinitions:");
    let _ = writeln!(w, "    - name: Frame");
    let _ = writeln!(w, "      type: INT");
    let _ = writeln!(w, "      range: {frames}");
    let _ = writeln!(w, "  script:");
    let _ = writeln!(w, "    actions:");
    let _ = writeln!(w, "      onRun:");
    let _ = writeln!(w, "        command: \"{{{{Param.Lux}}}}\"");
    let _ = writeln!(w, "        args: {}", seq(&merge));
    Ok(y)
}

/// Writes the job template of `args` atomically.
pub fn run(args: &FarmArgs) -> Result<(), String> {
    check_render_args(&args.render_args)?;
    if !args.scene.exists() {
        eprintln!(
            "lux: warning: {} does not exist here (the workers must see it as ScenePath)",
            args.scene.display()
        );
    }
    let yaml = template(args)?;
    lux_render::image_io::write_atomically(&args.output, |w| {
        use std::io::Write;
        w.write_all(yaml.as_bytes())
            .map_err(|source| lux_render::image_io::ImageError::Io {
                path: args.output.clone(),
                action: "write",
                source,
            })
    })
    .map_err(|e| e.to_string())?;
    let [a, b] = args.frames;
    eprintln!(
        "lux: wrote {}: frames {a}-{b} × {} tiles, then a merge per frame",
        args.output.display(),
        args.tiles
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames() {
        assert_eq!(parse_frames("1-24"), Ok([1, 24]));
        assert_eq!(parse_frames("7"), Ok([7, 7]));
        assert_eq!(parse_frames("-2-3"), Ok([-2, 3]));
        assert_eq!(parse_frames("-5--1"), Ok([-5, -1]));
        assert!(parse_frames("3-1").is_err());
        assert!(parse_frames("a-b").is_err());
    }

    #[test]
    fn relative_paths() {
        let r = |b: &str, p: &str| relative_to(Path::new(b), Path::new(p)).unwrap();
        assert_eq!(r("/a/b", "/a/c/d.usda"), PathBuf::from("../c/d.usda"));
        assert_eq!(r("/a/b", "/a/b/f"), PathBuf::from("f"));
        assert_eq!(r("/a/b", "/a/b"), PathBuf::from("."));
        assert_eq!(r("/a/./b", "/x"), PathBuf::from("../../x"));
    }

    #[test]
    fn render_args_are_checked() {
        let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        assert!(check_render_args(&s(&["--spp", "4", "--resolution", "48x32"])).is_ok());
        assert!(check_render_args(&s(&["--frame", "3"])).is_err());
        assert!(check_render_args(&s(&["--tile=0/2"])).is_err());
        assert!(check_render_args(&s(&["-ox.exr"])).is_err());
        assert!(check_render_args(&s(&["--spp", "many"])).is_err());
        assert!(check_render_args(&s(&["--no-such-option"])).is_err());
    }
}
