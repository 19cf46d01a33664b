//! The public API of the small crates other renderers pin (lux-math, lux-ies, lux-shaping,
//! lux-sample, lux-spectral, and lux-irradiance, which lux-sample's signatures use) changes
//! only on purpose: each crate's API, read from its sources with `syn`, is compared with the
//! listing committed in `api/<crate>.txt`, and a difference fails with the lines that changed
//! and the command that rewrites the listings:
//!
//! ```sh
//! LUX_UPDATE_API=1 cargo test -p lux-usdlux --test public_api
//! ```
//!
//! Commit the rewritten listing with the change that made it, so that the diff shows the API
//! change for review (and a release bumps the version accordingly).
//!
//! What is listed, one item per line, sorted: every item reachable from the crate root by a
//! public path — public items of public modules, and what `pub use` re-exports from private
//! modules or other crates (chains of re-exports followed) — with its signature: functions and
//! methods (inherent `impl` blocks of the public types), structs with their public fields,
//! enums with their variants, constants and statics with their types, type aliases, traits,
//! the derived and implemented traits of the public types, and re-exported external items by
//! their path. Items under `#[cfg(test)]` or `#[cfg(doctest)]` are not API. Private and
//! `pub(crate)` items, bodies and documentation are left out, so a refactoring that keeps the
//! API keeps the listing.

use proc_macro2::{Delimiter, Spacing, TokenStream, TokenTree};
use quote::ToTokens;
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use syn::{Attribute, ImplItem, Item, UseTree, Visibility};

/// The crates whose API is pinned, by package directory under `crates/`.
const CRATES: [&str; 6] = [
    "lux-math",
    "lux-ies",
    "lux-shaping",
    "lux-sample",
    "lux-spectral",
    "lux-irradiance",
];

// ------------------------------------------------------------------------------------------
// Tokens to text

/// Tokens as one line of Rust: no spaces inside paths, generics and groups, one after `,`, `;`
/// and a type's `:`, around `->`, `=>`, `=`, `+` and `|`.
/// Attributes (`#[doc]`, `#[error]` on fields and variants) and trailing commas are left out.
fn text(ts: TokenStream) -> String {
    let mut out = String::new();
    write_tokens(&mut out, ts);
    for (from, to) in [(",)", ")"), (", }", " }"), (",]", "]"), (",>", ">")] {
        out = out.replace(from, to);
    }
    out
}

fn write_tokens(out: &mut String, ts: TokenStream) {
    let mut joint_prev = false;
    let mut tts = ts.into_iter().peekable();
    while let Some(tt) = tts.next() {
        if let TokenTree::Punct(p) = &tt
            && p.as_char() == '#'
            && matches!(tts.peek(), Some(TokenTree::Group(g)) if g.delimiter() == Delimiter::Bracket)
        {
            tts.next();
            continue;
        }
        match tt {
            TokenTree::Group(g) => {
                let (open, close) = match g.delimiter() {
                    Delimiter::Parenthesis => ("(", ")"),
                    Delimiter::Bracket => ("[", "]"),
                    Delimiter::Brace => ("{ ", " }"),
                    Delimiter::None => ("", ""),
                };
                if g.delimiter() == Delimiter::Brace && !out.ends_with(' ') && !out.is_empty() {
                    out.push(' ');
                }
                out.push_str(open);
                write_tokens(out, g.stream());
                if g.delimiter() == Delimiter::Brace && g.stream().is_empty() {
                    out.truncate(out.len() - 1);
                }
                out.push_str(close);
                joint_prev = false;
            }
            TokenTree::Ident(i) => {
                space_before_word(out);
                let _ = write!(out, "{i}");
                joint_prev = false;
            }
            TokenTree::Literal(l) => {
                space_before_word(out);
                let _ = write!(out, "{l}");
                joint_prev = false;
            }
            TokenTree::Punct(p) => {
                let c = p.as_char();
                let spaced =
                    matches!(c, '=' | '+' | '|') || (c == '-' && p.spacing() == Spacing::Joint);
                if spaced && !joint_prev && !out.ends_with(' ') && !out.is_empty() {
                    out.push(' ');
                }
                out.push(c);
                let alone = p.spacing() == Spacing::Alone;
                if alone {
                    let colon_of_path = c == ':' && joint_prev;
                    let after = matches!(c, ',' | ';' | '=' | '+' | '|')
                        || (c == '>' && joint_prev && out.ends_with("->"))
                        || (c == '>' && joint_prev && out.ends_with("=>"))
                        || (c == ':' && !colon_of_path);
                    if after {
                        out.push(' ');
                    }
                }
                joint_prev = !alone;
            }
        }
    }
    let trimmed = out.trim_end_matches(' ').len();
    if out.ends_with(' ') && !out.ends_with("{ ") {
        out.truncate(trimmed);
    }
}

/// A space between two words (identifiers, literals, a lifetime's name after `'` excepted).
fn space_before_word(out: &mut String) {
    if let Some(c) = out.chars().last()
        && (c.is_alphanumeric() || c == '_' || c == '>' || c == ')' || c == ']' || c == '"')
    {
        out.push(' ');
    }
}

fn tokens(t: &impl ToTokens) -> String {
    text(t.to_token_stream())
}

/// A function's signature without `mut` on its parameters (an implementation detail).
fn signature(sig: &syn::Signature) -> String {
    tokens(sig).replace("(mut ", "(").replace(", mut ", ", ")
}

// ------------------------------------------------------------------------------------------
// Reading a crate

/// One module of a crate: its path, whether it is reachable publicly, its items.
struct Module {
    path: Vec<String>,
    public: bool,
    items: Vec<Item>,
}

/// Whether `attrs` put the item under `cfg(test)` or `cfg(doctest)`.
fn test_only(attrs: &[Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("cfg") && {
            let s = tokens(&a.meta);
            s.contains("test") && !s.contains("not")
        }
    })
}

fn is_pub(v: &Visibility) -> bool {
    matches!(v, Visibility::Public(_))
}

/// Every module of the crate whose root file is `lib`, depth first.
fn read_modules(lib: &Path) -> Vec<Module> {
    let mut out = Vec::new();
    read_module(
        lib,
        lib.parent().unwrap().to_path_buf(),
        Vec::new(),
        true,
        &mut out,
    );
    out
}

fn read_module(file: &Path, dir: PathBuf, path: Vec<String>, public: bool, out: &mut Vec<Module>) {
    let src = std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let parsed = syn::parse_file(&src).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    collect(parsed.items, &dir, path, public, out);
}

fn collect(items: Vec<Item>, dir: &Path, path: Vec<String>, public: bool, out: &mut Vec<Module>) {
    let mut kept = Vec::new();
    for item in items {
        match item {
            Item::Mod(m) if test_only(&m.attrs) => {}
            Item::Mod(m) => {
                let name = m.ident.to_string();
                let mut sub = path.clone();
                sub.push(name.clone());
                let public = public && is_pub(&m.vis);
                match m.content {
                    Some((_, inline)) => collect(inline, &dir.join(&name), sub, public, out),
                    None => {
                        let flat = dir.join(format!("{name}.rs"));
                        let file = if flat.exists() {
                            flat
                        } else {
                            dir.join(&name).join("mod.rs")
                        };
                        read_module(&file, dir.join(&name), sub, public, out);
                    }
                }
            }
            other => kept.push(other),
        }
    }
    out.push(Module {
        path,
        public,
        items: kept,
    });
}

fn attrs_of(item: &Item) -> &[Attribute] {
    match item {
        Item::Const(i) => &i.attrs,
        Item::Enum(i) => &i.attrs,
        Item::Fn(i) => &i.attrs,
        Item::Impl(i) => &i.attrs,
        Item::Static(i) => &i.attrs,
        Item::Struct(i) => &i.attrs,
        Item::Trait(i) => &i.attrs,
        Item::Type(i) => &i.attrs,
        Item::Use(i) => &i.attrs,
        _ => &[],
    }
}

/// The public name an item defines, with its visibility.
fn defined_name(item: &Item) -> Option<(String, bool)> {
    Some(match item {
        Item::Const(i) => (i.ident.to_string(), is_pub(&i.vis)),
        Item::Enum(i) => (i.ident.to_string(), is_pub(&i.vis)),
        Item::Fn(i) => (i.sig.ident.to_string(), is_pub(&i.vis)),
        Item::Static(i) => (i.ident.to_string(), is_pub(&i.vis)),
        Item::Struct(i) => (i.ident.to_string(), is_pub(&i.vis)),
        Item::Trait(i) => (i.ident.to_string(), is_pub(&i.vis)),
        Item::Type(i) => (i.ident.to_string(), is_pub(&i.vis)),
        _ => return None,
    })
}

/// The `pub use` leaves of a use tree: (name it is visible under, full source path).
fn use_leaves(tree: &UseTree, prefix: &mut Vec<String>, out: &mut Vec<(String, Vec<String>)>) {
    match tree {
        UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            use_leaves(&p.tree, prefix, out);
            prefix.pop();
        }
        UseTree::Name(n) => {
            let mut full = prefix.clone();
            full.push(n.ident.to_string());
            out.push((n.ident.to_string(), full));
        }
        UseTree::Rename(r) => {
            let mut full = prefix.clone();
            full.push(r.ident.to_string());
            out.push((r.rename.to_string(), full));
        }
        UseTree::Group(g) => {
            for t in &g.items {
                use_leaves(t, prefix, out);
            }
        }
        UseTree::Glob(_) => {
            let mut full = prefix.clone();
            full.push("*".into());
            out.push(("*".into(), full));
        }
    }
}

// ------------------------------------------------------------------------------------------
// The listing

/// Where a public name leads: an item of this crate (module index, item index) or an external
/// path.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Target {
    Local(usize, usize),
    External(String),
}

struct Crate {
    name: String,
    modules: Vec<Module>,
}

impl Crate {
    fn module(&self, path: &[String]) -> Option<usize> {
        self.modules.iter().position(|m| m.path == path)
    }

    /// What `name` in module `m` refers to: an item defined there, or the target of a `use` there
    /// (public or not: a `pub use` elsewhere may re-export a private `use`'s name).
    fn resolve_in(&self, m: usize, name: &str, depth: usize) -> Option<Target> {
        if depth > 16 {
            return None;
        }
        for (i, item) in self.modules[m].items.iter().enumerate() {
            if test_only(attrs_of(item)) {
                continue;
            }
            if defined_name(item).is_some_and(|(n, _)| n == name) {
                return Some(Target::Local(m, i));
            }
        }
        for item in &self.modules[m].items {
            if let Item::Use(u) = item {
                let mut leaves = Vec::new();
                use_leaves(&u.tree, &mut Vec::new(), &mut leaves);
                for (visible, full) in leaves {
                    if visible == name {
                        return self.resolve_path(m, &full, depth + 1);
                    }
                    if visible == "*"
                        && let Some(from) = self.module_of_path(m, &full[..full.len() - 1])
                        && let Some(t) = self.resolve_in(from, name, depth + 1)
                    {
                        return Some(t);
                    }
                }
            }
        }
        None
    }

    /// The module a use path's prefix names, seen from module `m` (`super`, `self`, `crate`,
    /// a child).
    fn module_of_path(&self, m: usize, prefix: &[String]) -> Option<usize> {
        let mut path = self.modules[m].path.clone();
        for (k, seg) in prefix.iter().enumerate() {
            match seg.as_str() {
                "crate" if k == 0 => path.clear(),
                "self" if k == 0 => {}
                "super" => {
                    path.pop()?;
                }
                other => path.push(other.to_owned()),
            }
        }
        self.module(&path)
    }

    /// A use path seen from module `m`: `crate::…`, `self::…`, `super::…`, a child module, or
    /// another crate.
    fn resolve_path(&self, m: usize, full: &[String], depth: usize) -> Option<Target> {
        let here = &self.modules[m].path;
        let (mut base, rest): (Vec<String>, &[String]) = match full[0].as_str() {
            "crate" => (Vec::new(), &full[1..]),
            "self" => (here.clone(), &full[1..]),
            "super" => (here[..here.len().saturating_sub(1)].to_vec(), &full[1..]),
            first
                if self
                    .module(&[here.clone(), vec![first.to_owned()]].concat())
                    .is_some() =>
            {
                (here.clone(), full)
            }
            first if self.module(&[first.to_owned()]).is_some() && here.is_empty() => {
                (Vec::new(), full)
            }
            _ => return Some(Target::External(full.join("::"))),
        };
        let (name, mods) = rest.split_last()?;
        base.extend(mods.iter().cloned());
        let target = self.module(&base)?;
        self.resolve_in(target, name, depth)
    }

    /// Every public path of the crate and what it leads to.
    fn public_paths(&self) -> BTreeMap<String, Target> {
        let mut out = BTreeMap::new();
        for (m, module) in self.modules.iter().enumerate() {
            if !module.public {
                continue;
            }
            let prefix: Vec<&str> = std::iter::once(self.name.as_str())
                .chain(module.path.iter().map(String::as_str))
                .collect();
            let prefix = prefix.join("::");
            for (i, item) in module.items.iter().enumerate() {
                if test_only(attrs_of(item)) {
                    continue;
                }
                if let Some((name, true)) = defined_name(item) {
                    out.insert(format!("{prefix}::{name}"), Target::Local(m, i));
                }
                if let Item::Use(u) = item
                    && is_pub(&u.vis)
                {
                    let mut leaves = Vec::new();
                    use_leaves(&u.tree, &mut Vec::new(), &mut leaves);
                    for (visible, full) in leaves {
                        if let Some(t) = self.resolve_path(m, &full, 0) {
                            out.insert(format!("{prefix}::{visible}"), t);
                        }
                    }
                }
            }
        }
        out
    }

    /// The listing of the crate's API (see the module documentation).
    fn listing(&self) -> String {
        let paths = self.public_paths();
        // the public name of each local type, for its impl blocks
        let mut type_paths: BTreeMap<(usize, usize), String> = BTreeMap::new();
        for (path, t) in &paths {
            if let Target::Local(m, i) = t {
                type_paths.entry((*m, *i)).or_insert_with(|| path.clone());
            }
        }
        let mut lines = BTreeSet::new();
        for (path, t) in &paths {
            match t {
                Target::External(ext) => {
                    lines.insert(format!("pub use {ext} as {path}"));
                }
                Target::Local(m, i) => {
                    self.item_lines(path, &self.modules[*m].items[*i], &mut lines);
                }
            }
        }
        // impl blocks anywhere in the crate, for the public types they name
        for (m, module) in self.modules.iter().enumerate() {
            for item in &module.items {
                let Item::Impl(imp) = item else { continue };
                if test_only(&imp.attrs) {
                    continue;
                }
                let syn::Type::Path(tp) = &*imp.self_ty else {
                    continue;
                };
                let Some(last) = tp.path.segments.last() else {
                    continue;
                };
                let Some(Target::Local(dm, di)) = self.resolve_in(m, &last.ident.to_string(), 0)
                else {
                    continue;
                };
                let Some(ty) = type_paths.get(&(dm, di)) else {
                    continue;
                };
                let generics = tokens(&imp.generics);
                match &imp.trait_ {
                    Some((bang, tr, _)) => {
                        let bang = if bang.is_some() { "!" } else { "" };
                        lines.insert(format!("impl{generics} {bang}{} for {ty}", tokens(tr)));
                    }
                    None => {
                        for ii in &imp.items {
                            match ii {
                                ImplItem::Fn(f) if is_pub(&f.vis) && !test_only(&f.attrs) => {
                                    lines.insert(format!(
                                        "impl{generics} {ty}: pub {}",
                                        signature(&f.sig)
                                    ));
                                }
                                ImplItem::Const(c) if is_pub(&c.vis) && !test_only(&c.attrs) => {
                                    lines.insert(format!(
                                        "impl{generics} {ty}: pub const {}: {}",
                                        c.ident,
                                        tokens(&c.ty)
                                    ));
                                }
                                _ => {}
                            }
                        }
                    }
                }
            }
        }
        let mut s = String::new();
        for l in lines {
            s.push_str(&l);
            s.push('\n');
        }
        s
    }

    fn item_lines(&self, path: &str, item: &Item, lines: &mut BTreeSet<String>) {
        let derives = |attrs: &[Attribute]| -> String {
            let d: Vec<String> = attrs
                .iter()
                .filter(|a| a.path().is_ident("derive"))
                .map(|a| tokens(&a.meta))
                .collect();
            if d.is_empty() {
                String::new()
            } else {
                format!(" #[{}]", d.join(", "))
            }
        };
        match item {
            Item::Fn(f) => {
                let sig = signature(&f.sig);
                let name = f.sig.ident.to_string();
                lines.insert(format!(
                    "pub {}",
                    sig.replacen(&format!("fn {name}"), &format!("fn {path}"), 1)
                ));
            }
            Item::Const(c) => {
                lines.insert(format!("pub const {path}: {}", tokens(&c.ty)));
            }
            Item::Static(s) => {
                lines.insert(format!("pub static {path}: {}", tokens(&s.ty)));
            }
            Item::Type(t) => {
                lines.insert(format!(
                    "pub type {path}{} = {}",
                    tokens(&t.generics),
                    tokens(&t.ty)
                ));
            }
            Item::Struct(st) => {
                let generics = tokens(&st.generics);
                let nonexhaustive = st.attrs.iter().any(|a| a.path().is_ident("non_exhaustive"));
                lines.insert(format!(
                    "pub struct {path}{generics}{}{}",
                    derives(&st.attrs),
                    if nonexhaustive {
                        " #[non_exhaustive]"
                    } else {
                        ""
                    }
                ));
                for (k, f) in st.fields.iter().enumerate() {
                    if is_pub(&f.vis) {
                        let name = f.ident.as_ref().map_or(k.to_string(), ToString::to_string);
                        lines.insert(format!("pub field {path}::{name}: {}", tokens(&f.ty)));
                    }
                }
            }
            Item::Enum(e) => {
                lines.insert(format!(
                    "pub enum {path}{}{}",
                    tokens(&e.generics),
                    derives(&e.attrs)
                ));
                for v in &e.variants {
                    let fields = tokens(&v.fields);
                    let gap = if fields.starts_with('{') { " " } else { "" };
                    lines.insert(format!("pub variant {path}::{}{gap}{fields}", v.ident));
                }
            }
            Item::Trait(t) => {
                lines.insert(format!("pub trait {path}{}", tokens(&t.generics)));
                for ti in &t.items {
                    if let syn::TraitItem::Fn(f) = ti {
                        lines.insert(format!("pub trait {path}: {}", signature(&f.sig)));
                    }
                }
            }
            _ => {}
        }
    }
}

fn workspace() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The lines only in `old` (`-`) and only in `new` (`+`).
fn diff(old: &str, new: &str) -> String {
    let a: BTreeSet<&str> = old.lines().collect();
    let b: BTreeSet<&str> = new.lines().collect();
    let mut s = String::new();
    for l in a.difference(&b) {
        let _ = writeln!(s, "- {l}");
    }
    for l in b.difference(&a) {
        let _ = writeln!(s, "+ {l}");
    }
    s
}

fn listing_of(krate: &str) -> String {
    let root = workspace().join("crates").join(krate).join("src/lib.rs");
    let c = Crate {
        name: krate.replace('-', "_"),
        modules: read_modules(&root),
    };
    c.listing()
}

#[test]
fn the_small_crates_public_api_changes_only_on_purpose() {
    let ws = workspace();
    if !ws.join("crates").is_dir() {
        // the published lux-usdlux package carries its tests but not the member crates
        eprintln!("no crates/ beside this package: the API listings are checked in the workspace");
        return;
    }
    let update = std::env::var_os("LUX_UPDATE_API").is_some();
    let mut failures = String::new();
    for krate in CRATES {
        let file = ws.join("api").join(format!("{krate}.txt"));
        let now = listing_of(krate);
        assert!(now.lines().count() > 10, "{krate}: {now}");
        if update {
            std::fs::create_dir_all(file.parent().unwrap()).unwrap();
            std::fs::write(&file, &now).unwrap();
            continue;
        }
        let committed = std::fs::read_to_string(&file).unwrap_or_default();
        if committed != now {
            let _ = writeln!(
                failures,
                "\n{krate}: the public API differs from api/{krate}.txt:\n{}",
                diff(&committed, &now)
            );
        }
    }
    assert!(
        failures.is_empty(),
        "{failures}\nIf the change is intended, rewrite the listings and commit them with it:\n    \
         LUX_UPDATE_API=1 cargo test -p lux-usdlux --test public_api\n"
    );
}

/// The reader itself: re-exports through private modules and other crates, impl blocks in
/// submodules, public fields and variants, test-only items left out.
#[test]
fn the_listing_follows_re_exports_and_impls() {
    let dir = std::env::temp_dir().join(format!("lux-public-api-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("inner")).unwrap();
    std::fs::write(
        dir.join("lib.rs"),
        "mod inner;\npub mod open;\npub use inner::{Thing, helper as renamed};\npub use other::Ext;\n\
         #[cfg(test)] mod tests { pub fn hidden() {} }\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("inner.rs"),
        "mod deeper;\n#[derive(Clone, Debug)]\npub struct Thing { pub a: f64, b: u8 }\n\
         pub fn helper(x: &[f64; 2]) -> Option<f64> { None }\npub fn not_exported() {}\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("inner/deeper.rs"),
        "use super::*;\nimpl Thing { pub fn new(a: f64) -> Self { todo!() } pub(crate) fn private(&self) {} }\n\
         impl Default for Thing { fn default() -> Self { todo!() } }\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("open.rs"),
        "pub enum Kind { A, B { x: f64 }, C(u32) }\npub const N: usize = 3;\npub(crate) fn no() {}\n",
    )
    .unwrap();
    let c = Crate {
        name: "demo".into(),
        modules: read_modules(&dir.join("lib.rs")),
    };
    let got = c.listing();
    let want = "\
impl Default for demo::Thing
impl demo::Thing: pub fn new(a: f64) -> Self
pub const demo::open::N: usize
pub enum demo::open::Kind
pub field demo::Thing::a: f64
pub fn demo::renamed(x: &[f64; 2]) -> Option<f64>
pub struct demo::Thing #[derive(Clone, Debug)]
pub use other::Ext as demo::Ext
pub variant demo::open::Kind::A
pub variant demo::open::Kind::B { x: f64 }
pub variant demo::open::Kind::C(u32)
";
    assert_eq!(got, want, "\n{}", diff(want, &got));
}
