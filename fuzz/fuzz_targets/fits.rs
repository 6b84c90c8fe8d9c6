//! Fitted-model files (`predict --fit`, `export --fit`): any text gives the
//! file or an error naming it, never a panic; every fit read either
//! predicts finite values at fixed geometries or says why not.
#![no_main]

use laminar_brdf_core::Angles;
use laminar_brdf_io::fits::parse_fits;
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(file) = parse_fits(Path::new("fuzz.json"), text) else {
        return;
    };
    let angles: Vec<Angles> = [(0.1, 0.2, 0.3), (0.7, 1.2, -2.0), (1.5, 0.0, 3.1)]
        .into_iter()
        .map(|(i, s, p)| Angles::new(i, s, p).expect("valid angles"))
        .collect();
    for e in &file.fits {
        for fitted in std::iter::once(&e.fitted).chain(e.rh_fitted.as_ref()) {
            if let Ok(p) = fitted.predict(&angles) {
                assert!(p.iter().all(|v| v.is_finite()), "{p:?}");
            }
            if let Ok(r) = fitted.predict_radiance(&angles) {
                assert!(r.iter().all(|v| v.is_finite()), "{r:?}");
            }
        }
    }
});
