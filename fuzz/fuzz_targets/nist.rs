//! NIST Mueller-matrix BRDF CSV files: any bytes give a set or an error
//! naming the file, never a panic; sets become scenes or named errors.
#![no_main]

use laminar_brdf_io::nist::parse_nist;
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(set) = parse_nist(Path::new("fuzz.csv"), data) {
        for c in set.channel_names() {
            let _ = set.scene(c);
        }
    }
});
