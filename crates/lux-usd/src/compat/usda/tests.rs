//! Tests of the `.usda` compatibility pass.

use super::*;

fn rw(text: &str) -> String {
    rewrite(text)
        .map(|r| r.text)
        .unwrap_or_else(|| text.to_owned())
}

fn parses(text: &str) {
    if let Err(e) = openusd::usda::parse(text) {
        panic!("{e:#}\n{text}");
    }
}

#[test]
fn ordinary_text_is_not_copied() {
    let src = "#usda 1.0\ndef Xform \"a\" {\n    float f = 1 # c\n    color3f c = (1, 2, 3)\n    string s = \"http://x\"\n}\n";
    // `//` inside a string triggers the scan but no edit
    assert_eq!(rewrite(src), None);
    assert_eq!(rewrite("#usda 1.0\ndef \"a\" {}\n"), None);
    assert!(!may_need_rewrite(
        "#usda 1.0\ndef Mesh \"m\" { color3f[] primvars:displayColor }\n"
    ));
}

#[test]
fn line_comments_become_hash_comments() {
    let src = "#usda 1.0\n// head\ndef Xform \"a\" ( // meta\n) {\n    float f = 1// tail\n    string s = \"// kept\" // c\n    asset a = @//srv/x.png@\n    rel r = </a> // c\n    /* block // inside */ float g = 2\n}\n";
    let out = rw(src);
    assert_eq!(out.len(), src.len());
    assert_eq!(out.lines().count(), src.lines().count());
    assert!(out.contains("#/ head"));
    assert!(out.contains("( #/ meta"));
    assert!(out.contains("1#/ tail"));
    assert!(out.contains("\"// kept\" #/ c"));
    assert!(out.contains("@//srv/x.png@"));
    assert!(out.contains("/* block // inside */"));
    parses(&out);
}

#[test]
fn magic_line_tail_is_dropped() {
    for first in [
        "#usda 1.0 // x",
        "#usda 1.0 /* x */",
        "#usda 1.0   ",
        "#usda 1.0\tjunk",
    ] {
        let src = format!("{first}\ndef \"a\" {{\n}}\n");
        let out = rw(&src);
        assert!(out.starts_with("#usda 1.0\n"), "{out:?}");
        parses(&out);
    }
    assert_eq!(magic_tail("#usda 1.0\n"), None);
    assert_eq!(magic_tail("#usda 1.0.32 x"), Some(12));
    assert_eq!(magic_tail("#usda 1.0x"), None);
}

#[test]
fn asset_strings_become_asset_paths() {
    let src = "#usda 1.0\ndef X \"a\" (\n    customData = {\n        asset k = \"k.png\"\n        asset \"quoted key\" = 'q.png'\n    }\n)\n{\n    asset a = \"foo.png\"\n    asset b = \"a\\\\b.png\" (doc = \"x\")\n    asset[] arr = [\"x.png\", @y.png@, 'z.png']\n    asset c = \"with@at.png\"\n    asset d = \"\"\"tri.png\"\"\"\n    asset e = \"\\x41\\101.png\"\n    string s = \"not.png\"\n    token asset = \"t\"\n}\n";
    let out = rw(src);
    assert_eq!(out.lines().count(), src.lines().count());
    assert!(out.contains("asset k = @k.png@\n"), "{out}");
    assert!(out.contains("asset \"quoted key\" = @q.png@\n"), "{out}");
    assert!(out.contains("asset a = @foo.png@\n"), "{out}");
    assert!(out.contains("asset b = @a\\b.png@  (doc"), "{out}");
    assert!(out.contains("[@x.png@, @y.png@, @z.png@]"), "{out}");
    assert!(out.contains("asset c = @@@with@at.png@@@\n"), "{out}");
    assert!(out.contains("asset d = @tri.png@    \n"), "{out}");
    assert!(out.contains("asset e = @AA.png@      \n"), "{out}");
    assert!(out.contains("string s = \"not.png\""), "{out}");
    assert!(out.contains("token asset = \"t\""), "{out}");
    parses(&out);
}

#[test]
fn scalar_asset_samples_become_arrays() {
    let src = "#usda 1.0\ndef X \"a\" {\n    asset inputs:f.timeSamples = {\n        1: @../a.ies@,\n        2: @@@b@c.ies@@@,\n        3: None,\n        4: \"s.ies\",\n        -1.5: @@,\n    }\n    asset[] g.timeSamples = { 1: [\"x\", @y@] }\n    asset h.timeSamples = { 1: None }\n    asset inputs:k = @keep.ies@\n    string s.timeSamples = { 1: \"@x@\" }\n}\n";
    let out = rw(src);
    assert!(out.contains("asset[] inputs:f.timeSamples"), "{out}");
    assert!(out.contains("1: [@../a.ies@],"), "{out}");
    assert!(out.contains("2: [@@@b@c.ies@@@],"), "{out}");
    assert!(out.contains("3: None,"), "{out}");
    assert!(out.contains("4: [@s.ies@],"), "{out}");
    assert!(out.contains("-1.5: [@@],"), "{out}");
    assert!(
        out.contains("asset[] g.timeSamples = { 1: [@x@, @y@] }"),
        "{out}"
    );
    assert!(out.contains("asset h.timeSamples = { 1: None }"), "{out}");
    assert!(out.contains("asset inputs:k = @keep.ies@"), "{out}");
    assert!(out.contains("1: \"@x@\""), "{out}");
    parses(&out);
}

#[test]
fn config_becomes_uniform() {
    let src = "#usda 1.0\ndef X \"a\" {\n    config token info:id = \"PxrSurface\"\n    custom config double[] d = [1]\n    token config = \"x\"\n    token config\n    float f = 1\n}\n";
    let out = rw(src);
    assert!(out.contains("uniform token info:id"), "{out}");
    assert!(out.contains("custom uniform double[] d"), "{out}");
    assert!(out.contains("token config = \"x\""), "{out}");
    assert!(out.contains("token config\n"), "{out}");
    parses(&out);
}

#[test]
fn legacy_type_names_become_current() {
    let src = "#usda 1.0\ndef Point \"p\" (\n    customData = { Vec3f v = (1, 2, 3) }\n)\n{\n    PointFloat[] points = [(1, 2, 3)]\n    uniform Matrix4d m = ((1,0,0,0),(0,1,0,0),(0,0,1,0),(0,0,0,1))\n    custom Color c = (1, 2, 3)\n    float3 Color = (1, 2, 3)\n    Vec3f []v = [(1, 2, 3)]\n    Quatf q = (1, 0, 0, 0)\n    FaceIndex[] fi = [1]\n}\n";
    let out = rw(src);
    assert!(
        out.contains("def Point \"p\""),
        "prim type names are not attribute types: {out}"
    );
    assert!(out.contains("{ float3 v"), "{out}");
    assert!(out.contains("point3f   [] points"), "{out}");
    assert!(out.contains("uniform matrix4d m"), "{out}");
    assert!(out.contains("custom color3d c"), "{out}");
    assert!(
        out.contains("float3 Color ="),
        "attribute names are kept: {out}"
    );
    assert!(out.contains("float3 []v"), "{out}");
    assert!(out.contains("quatf q"), "{out}");
    assert!(out.contains("int      [] fi"), "{out}");
    parses(&out);
}

#[test]
fn offsets_map_back_through_longer_replacements() {
    let src = "#usda 1.0\ndef X \"a\" {\n    config Vec3f v = (1, 2, 3)\n}\n";
    let r = rewrite(src).unwrap();
    assert_eq!(
        r.text,
        "#usda 1.0\ndef X \"a\" {\n    uniform float3 v = (1, 2, 3)\n}\n"
    );
    let v_new = r.text.find(" v =").unwrap() + 1;
    let v_old = src.find(" v =").unwrap() + 1;
    assert_eq!(r.original_offset(v_new), v_old);
    assert_eq!(r.original_offset(3), 3);
    assert_eq!(r.original_offset(r.text.len()), src.len());
    // inside a replacement: into what it replaced
    let u = r.text.find("uniform").unwrap();
    assert_eq!(r.original_offset(u + 6), src.find("config").unwrap() + 5);
}

#[test]
fn malformed_input_never_panics() {
    for src in [
        "",
        "#",
        "#usda ",
        "#usda 1.",
        "asset",
        "asset a = \"",
        "asset a = \"x",
        "asset a.timeSamples = {",
        "asset a.timeSamples = { 1: ",
        "asset[] a = [\"x\"",
        "config",
        "config float",
        "/*",
        "//",
        "@@@",
        "@a",
        "<a",
        "\"\"\"",
        "Vec3f",
        "Vec3f[",
        "asset a = \"\\",
        "asset a = \"\\x\"",
        "asset a = \"\\777\"",
        "asset a = \"\u{e9}\"",
        "\u{e9}config float x",
        "asset b = \"x\" asset c = \"@\"",
    ] {
        let _ = rewrite(src);
        let _ = rewrite(&format!("#usda 1.0\n{src}"));
    }
}

#[test]
fn path_expressions_are_read_as_strings() {
    let src = "#usda 1.0\ndef RectLight \"L\" {\n    uniform pathExpression collection:lightLink:membershipExpression = \"/World/A// - /World/A/m1\"\n}\n";
    let out = rw(src);
    assert_eq!(out.len(), src.len());
    assert!(
        out.contains("uniform string         collection:lightLink:membershipExpression = \"/World/A// - /World/A/m1\""),
        "{out}"
    );
    parses(&out);
}
