//! Fuzz target: any byte string either parses or gives a typed error (strict and lenient
//! modes); a parsed file expands, evaluates, integrates and writes back without panicking, and
//! re-parses to the same value. Seed it with `./seed.sh` (the lux-ies test corpus).
#![no_main]

use libfuzzer_sys::fuzz_target;
use lux_ies::{Edition, IesFile, Interpolation, ParseOptions, PhotometricWeb};
use lux_math::Profile;

fn check(file: &IesFile) {
    for profile in Profile::ALL {
        if let Ok(web) = PhotometricWeb::new(file, profile) {
            let m = web.mean_intensity();
            assert!(m.is_finite() && m >= 0.0);
            let _ = web.beam_angles();
            for k in 0..16 {
                let t = k as f64 * 0.25 - 0.5;
                for interp in [Interpolation::Bilinear, Interpolation::Bicubic] {
                    let i = web.intensity_with(t, t * 1.7, interp);
                    assert!(i.is_finite() && i >= 0.0);
                }
            }
        }
    }
    if file.validate().is_ok() {
        let target = if file.edition == Edition::Lm63_2019 {
            Edition::Lm63_2019
        } else {
            Edition::Lm63_2002
        };
        let back = IesFile::parse(&file.write(target)).expect("written file re-parses");
        let mut expect = file.clone();
        expect.edition = target;
        assert_eq!(back, expect);
    }
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let strict = IesFile::parse(&text);
    let lenient = IesFile::parse_with(
        &text,
        &ParseOptions {
            lenient: true,
            ..Default::default()
        },
    );
    // Lenient accepts everything strict accepts, with the same result.
    if let Ok(f) = &strict {
        assert_eq!(Ok(f), lenient.as_ref().map(|p| &p.file));
    }
    if let Ok(p) = &lenient {
        check(&p.file);
    }
});
