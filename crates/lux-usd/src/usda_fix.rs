//! The `.usda` rewrite applied before `openusd` 0.6 parses a text layer, under its original
//! name: now the whole compatibility pass of [`crate::compat::usda`].
//!
//! It began as the work-around for scalar asset-path time samples (`asset
//! inputs:shaping:ies:file.timeSamples = { 1: @a.ies@ }`, which `openusd` 0.6.0 rejects with
//! "Unsupported property metadata value token" although the luxtest scenes author exactly
//! that): each such sample becomes a one-element `asset[]` (`1: [@a.ies@]`), which the parser
//! accepts, whose paths the composition engine still resolves against the authoring layer, and
//! which the loader reads back as a single asset path. The same pass now also rewrites `//`
//! comments, quoted strings used as asset values, `config` variability and legacy type names
//! (see [`crate::compat::usda`]).

/// Applies the `.usda` compatibility pass ([`crate::compat::usda::rewrite`]) to `text`, scalar
/// asset time samples (`asset NAME.timeSamples = { t: @path@, … }` → `asset[] …` with
/// one-element arrays) included. Returns `None` when the text needs no change.
///
/// Strings, asset paths and comments are copied verbatim except where the pass rewrites them;
/// malformed blocks (no closing brace) are left as they are, so the parser reports them.
pub fn rewrite_asset_time_samples(text: &str) -> Option<String> {
    crate::compat::usda::rewrite(text).map(|r| r.text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wraps_scalar_asset_samples_only() {
        let src = "#usda 1.0\ndef X \"a\" {\n    asset inputs:f.timeSamples = {\n        1: @../a.ies@,\n        2: @@@b@c.ies@@@,\n        3: None,\n    }\n    asset inputs:g = @keep.ies@\n    string s.timeSamples = { 1: \"@x@\" }\n}\n";
        let out = rewrite_asset_time_samples(src).expect("changed");
        assert!(out.contains("asset[] inputs:f.timeSamples"));
        assert!(out.contains("1: [@../a.ies@],"));
        assert!(openusd::usda::parse(&out).is_ok());
        assert!(out.contains("2: [@@@b@c.ies@@@],"));
        assert!(out.contains("3: None,"));
        assert!(out.contains("asset inputs:g = @keep.ies@"));
        assert!(out.contains("1: \"@x@\""));
    }

    #[test]
    fn wraps_empty_asset_samples() {
        // the luxtest cylinder scene authors `1: @@` (no profile on frame 1)
        let src = "#usda 1.0\ndef X \"a\" {\n    asset inputs:shaping:ies:file.timeSamples = {\n        1: @@,\n        2: @a.ies@,\n    }\n}\n";
        let out = rewrite_asset_time_samples(src).expect("changed");
        assert!(out.contains("1: [@@],"), "{out}");
        assert!(out.contains("2: [@a.ies@],"), "{out}");
        assert!(openusd::usda::parse(&out).is_ok());
    }

    #[test]
    fn untouched_text_is_not_copied() {
        assert_eq!(
            rewrite_asset_time_samples("#usda 1.0\ndef X \"a\" {}\n"),
            None
        );
        // unterminated block: left for the parser to report
        assert_eq!(
            rewrite_asset_time_samples("asset a.timeSamples = { 1: @x@"),
            None
        );
    }
}
