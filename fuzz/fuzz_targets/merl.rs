//! MERL `.binary` and `.npy` files: any bytes give a table or an error
//! naming the file, never a panic.
#![no_main]

use laminar_brdf_io::merl::parse_merl;
use laminar_brdf_io::values::parse_npy;
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let _ = parse_merl(Path::new("fuzz.binary"), data);
    if let Ok(v) = parse_npy(Path::new("fuzz.npy"), data) {
        assert_eq!(v.data.len(), v.rows * v.cols);
    }
});
