//! The option parsers (`--samples`, `--models`, `--path`, `--objective`,
//! `--uncertainty`, `--quantity`, `--angles`): any text gives a value or a
//! message, never a panic; a value parsed prints back to what parses to it.
#![no_main]

use laminar_brdf::selection::parse_samples;
use laminar_brdf_fit::{Model, Objective, Quantity, SearchPath, Uncertainty};
use laminar_brdf_io::AngleUnit;
use libfuzzer_sys::fuzz_target;
use std::str::FromStr;

/// `text` parses as `T` or not; a value's `Display` parses to the same value.
fn round_trip<T: FromStr + ToString + PartialEq + std::fmt::Debug>(text: &str) {
    if let Ok(v) = text.parse::<T>() {
        let back = v.to_string().parse::<T>().ok();
        assert_eq!(back.as_ref(), Some(&v), "{text:?}");
    }
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(Some(samples)) = parse_samples(text) {
        assert!(samples.iter().all(|&s| s > 0));
    }
    for part in text.split(',') {
        round_trip::<Model>(part);
    }
    round_trip::<SearchPath>(text);
    round_trip::<Objective>(text);
    round_trip::<Uncertainty>(text);
    round_trip::<Quantity>(text);
    let _ = text.parse::<AngleUnit>();
});
