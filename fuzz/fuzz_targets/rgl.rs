//! RGL tensor-file BRDFs: any bytes give a set or an error naming the
//! file, never a panic; sets become scenes or named errors.
#![no_main]

use laminar_brdf_io::rgl::parse_rgl;
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(set) = parse_rgl(Path::new("fuzz.bsdf"), data) {
        for c in set.channel_names() {
            let _ = set.scene(c);
        }
    }
});
