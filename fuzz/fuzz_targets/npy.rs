//! `.npy` values (`fit-batch --values`): any bytes give N × K finite values
//! or an error naming the file, never a panic, a hang or an allocation the
//! data do not back (a header may claim any shape).
#![no_main]

use laminar_brdf_io::values::parse_npy;
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(v) = parse_npy(Path::new("fuzz.npy"), data) {
        assert_eq!(v.data.len(), v.rows * v.cols);
        assert!(v.data.iter().all(|x| x.is_finite()));
        // Every value came from the file: at most one per 4 bytes.
        assert!(v.data.len() <= data.len() / 4);
    }
});
