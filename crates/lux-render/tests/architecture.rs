//! The shape of lux-render's source, checked: its top-level modules import one another without
//! circles (outside tests), and no function is longer than [`MAX_FN_LINES`] lines.
//!
//! A module's imports are the `crate::<module>` paths in its files (`src/<module>.rs` and
//! everything under `src/<module>/`), comments, strings and `#[cfg(test)]` items left out.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Longest function body allowed, in lines (signature to closing brace).
const MAX_FN_LINES: usize = 150;

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// `src` with comments and the contents of string and char literals blanked (newlines kept,
/// so line numbers stay).
fn strip(src: &str) -> String {
    let b: Vec<char> = src.chars().collect();
    let mut out = String::with_capacity(src.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c == '/' && b.get(i + 1) == Some(&'/') {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && b.get(i + 1) == Some(&'*') {
            i += 2;
            while i + 1 < b.len() && !(b[i] == '*' && b[i + 1] == '/') {
                if b[i] == '\n' {
                    out.push('\n');
                }
                i += 1;
            }
            i += 2;
        } else if c == 'r'
            && matches!(b.get(i + 1), Some('"') | Some('#'))
            && !b[..i]
                .last()
                .is_some_and(|p| p.is_alphanumeric() || *p == '_')
        {
            // raw string r"…" / r#"…"#
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            j += 1;
            loop {
                if j >= b.len() {
                    break;
                }
                if b[j] == '"' && (0..hashes).all(|k| b.get(j + 1 + k) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                if b[j] == '\n' {
                    out.push('\n');
                }
                j += 1;
            }
            out.push_str("\"\"");
            i = j;
        } else if c == '"' {
            i += 1;
            while i < b.len() && b[i] != '"' {
                if b[i] == '\\' {
                    i += 1;
                }
                if b.get(i) == Some(&'\n') {
                    out.push('\n');
                }
                i += 1;
            }
            i += 1;
            out.push_str("\"\"");
        } else if c == '\'' {
            // a char literal ('x', '\n', '\u{..}'), else a lifetime
            let close = if b.get(i + 1) == Some(&'\\') {
                (i + 2..b.len().min(i + 12)).find(|&j| b[j] == '\'')
            } else if b.get(i + 2) == Some(&'\'') {
                Some(i + 2)
            } else {
                None
            };
            match close {
                Some(j) => {
                    out.push_str("' '");
                    i = j + 1;
                }
                None => {
                    out.push(c);
                    i += 1;
                }
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// The index just past the brace that closes the one at `open`.
fn matching(s: &[u8], open: usize) -> usize {
    let mut depth = 0;
    for (k, &c) in s.iter().enumerate().skip(open) {
        match c {
            b'{' => depth += 1,
            b'}' => {
                depth -= 1;
                if depth == 0 {
                    return k + 1;
                }
            }
            _ => {}
        }
    }
    s.len()
}

/// `s` (stripped) without its `#[cfg(test)]` items (blanked, newlines kept).
fn without_tests(s: &str) -> String {
    let mut out: Vec<u8> = s.as_bytes().to_vec();
    let mut from = 0;
    while let Some(at) = s[from..].find("#[cfg(test)]") {
        let start = from + at;
        // the item: up to its `;` or its closing brace
        let rest = &s.as_bytes()[start..];
        let semi = rest.iter().position(|&c| c == b';');
        let brace = rest.iter().position(|&c| c == b'{');
        let end = match (semi, brace) {
            (Some(a), Some(b)) if a < b => start + a + 1,
            (_, Some(b)) => matching(s.as_bytes(), start + b),
            (Some(a), None) => start + a + 1,
            (None, None) => s.len(),
        };
        for c in &mut out[start..end] {
            if *c != b'\n' {
                *c = b' ';
            }
        }
        from = end;
    }
    String::from_utf8(out).unwrap()
}

/// The top-level module a file under `src` belongs to (`None` for `lib.rs`).
fn module_of(src: &Path, file: &Path) -> Option<String> {
    let rel = file.strip_prefix(src).unwrap();
    let first = rel.components().next()?.as_os_str().to_str()?.to_owned();
    let name = first.strip_suffix(".rs").unwrap_or(&first).to_owned();
    (name != "lib").then_some(name)
}

/// The top-level modules each module imports (`crate::<m>`), outside tests.
fn import_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut modules = BTreeSet::new();
    for f in rust_files(src) {
        if let Some(m) = module_of(src, &f) {
            modules.insert(m);
        }
    }
    for f in rust_files(src) {
        let Some(m) = module_of(src, &f) else {
            continue;
        };
        let code = without_tests(&strip(&std::fs::read_to_string(&f).unwrap()));
        let entry = graph.entry(m.clone()).or_default();
        let mut rest = code.as_str();
        while let Some(at) = rest.find("crate::") {
            let after = &rest[at + 7..];
            let name: String = after
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            let whole_word = at == 0 || {
                let prev = rest[..at].chars().last().unwrap();
                !(prev.is_alphanumeric() || prev == '_')
            };
            if whole_word && name != m && modules.contains(&name) {
                entry.insert(name);
            }
            rest = after;
        }
        // `use crate::{a, b::c}` groups
        let mut rest = code.as_str();
        while let Some(at) = rest.find("crate::{") {
            let open = at + 7;
            let close = matching(rest.as_bytes(), open);
            for part in rest[open + 1..close - 1].split([',', '{', '}']) {
                let name: String = part
                    .trim()
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if name != m && modules.contains(&name) {
                    entry.insert(name);
                }
            }
            rest = &rest[close..];
        }
    }
    graph
}

/// A circle in `graph`, if any, as the modules along it.
fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    // 0 unvisited, 1 on the stack, 2 done
    fn visit(
        n: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(n.to_owned(), 1);
        stack.push(n.to_owned());
        for m in graph.get(n).into_iter().flatten() {
            match state.get(m.as_str()).copied().unwrap_or(0) {
                1 => {
                    let from = stack.iter().position(|s| s == m).unwrap();
                    let mut cycle = stack[from..].to_vec();
                    cycle.push(m.clone());
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(m, graph, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(n.to_owned(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for n in graph.keys() {
        if state.get(n.as_str()).copied().unwrap_or(0) == 0
            && let Some(c) = visit(n, graph, &mut state, &mut Vec::new())
        {
            return Some(c);
        }
    }
    None
}

/// Functions longer than `max` lines in `code` (stripped): (name, first line, lines).
fn long_functions(code: &str, max: usize) -> Vec<(String, usize, usize)> {
    let bytes = code.as_bytes();
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(at) = code[from..].find("fn ") {
        let start = from + at;
        from = start + 3;
        let word_start = start == 0 || {
            let p = bytes[start - 1];
            !(p.is_ascii_alphanumeric() || p == b'_')
        };
        if !word_start {
            continue;
        }
        let name: String = code[start + 3..]
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        if name.is_empty() {
            continue;
        }
        // the body: the first `{` before any `;` (a declaration without body has none)
        let rest = &bytes[start..];
        let Some(open) = rest.iter().position(|&c| c == b'{' || c == b';') else {
            continue;
        };
        if rest[open] == b';' {
            continue;
        }
        let end = matching(bytes, start + open);
        let first = code[..start].matches('\n').count() + 1;
        let lines = code[start..end].matches('\n').count() + 1;
        if lines > max {
            out.push((name, first, lines));
        }
    }
    out
}

#[test]
fn top_level_modules_import_one_another_without_circles() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let graph = import_graph(&src);
    assert!(graph.len() >= 15, "modules found: {:?}", graph.keys());
    // The checker sees imports: the integrators read the visibility, the tile loop the film.
    assert!(graph["integrator"].contains("visibility"), "{graph:?}");
    assert!(graph["tiles"].contains("film"), "{graph:?}");
    // The statistics import nothing of the renderer.
    assert!(
        graph["stats"].is_empty(),
        "stats imports {:?}",
        graph["stats"]
    );
    assert_eq!(find_cycle(&graph), None, "import circle among {graph:#?}");
}

#[test]
fn no_function_is_longer_than_the_limit() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut long = Vec::new();
    for f in rust_files(&src) {
        let code = without_tests(&strip(&std::fs::read_to_string(&f).unwrap()));
        for (name, line, lines) in long_functions(&code, MAX_FN_LINES) {
            long.push(format!(
                "{}:{line} fn {name}: {lines} lines",
                f.strip_prefix(&src).unwrap().display()
            ));
        }
    }
    assert!(
        long.is_empty(),
        "functions over {MAX_FN_LINES} lines:\n{}",
        long.join("\n")
    );
}

/// The checker's own parts find what they look for.
#[test]
fn the_checker_sees_circles_strings_and_long_functions() {
    let g: BTreeMap<String, BTreeSet<String>> = [
        ("a", vec!["b"]),
        ("b", vec!["c"]),
        ("c", vec!["a"]),
        ("d", vec![]),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_owned(), v.into_iter().map(str::to_owned).collect()))
    .collect();
    assert_eq!(
        find_cycle(&g),
        Some(vec!["a".into(), "b".into(), "c".into(), "a".into()])
    );
    let s = strip("let x = \"crate::film\"; // crate::light\nuse crate::geometry; let c = '{';");
    assert!(!s.contains("film") && !s.contains("light") && s.contains("crate::geometry"));
    assert!(!s.contains("'{'"));
    let t = without_tests("use crate::a;\n#[cfg(test)]\nmod tests {\n use crate::b;\n}\n");
    assert!(t.contains("crate::a") && !t.contains("crate::b"));
    let body = format!(
        "fn long() {{\n{}}}\nfn short() {{\n}}\n",
        "x;\n".repeat(200)
    );
    let found = long_functions(&body, MAX_FN_LINES);
    assert_eq!(found.len(), 1);
    assert_eq!(
        (found[0].0.as_str(), found[0].1, found[0].2),
        ("long", 1, 202)
    );
}
