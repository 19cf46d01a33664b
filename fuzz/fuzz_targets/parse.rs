//! Fuzz target: any byte string either parses or gives a typed error; a parsed file expands,
//! evaluates, integrates and writes back without panicking, and re-parses to the same value.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lux_ies::{Edition, IesFile, Interpolation, PhotometricWeb};
use lux_math::Profile;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let Ok(file) = IesFile::parse(&text) else { return };
    for profile in Profile::ALL {
        if let Ok(web) = PhotometricWeb::new(&file, profile) {
            let _ = web.mean_intensity(profile);
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
        let target = if file.edition == Edition::Lm63_2019 { Edition::Lm63_2019 } else { Edition::Lm63_2002 };
        let back = IesFile::parse(&file.write(target)).expect("written file re-parses");
        let mut expect = file.clone();
        expect.edition = target;
        assert_eq!(back, expect);
    }
});
