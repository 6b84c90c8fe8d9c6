//! Long-format CSV measurements and geometry files: any bytes give a set or
//! an error naming the file, never a panic; sets become scenes or named
//! errors.
#![no_main]

use laminar_brdf_fit::Quantity;
use laminar_brdf_io::csv_file::{parse_csv, parse_geometry};
use laminar_brdf_io::values::parse_csv_values;
use laminar_brdf_io::AngleUnit;
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let file = Path::new("fuzz.csv");
    if let Ok(v) = parse_csv_values(file, data) {
        assert_eq!(v.data.len(), v.rows * v.cols);
    }
    for unit in [AngleUnit::Radians, AngleUnit::Degrees] {
        let _ = parse_geometry(file, data, unit);
        if let Ok(set) = parse_csv(file, data, unit, Quantity::Brdf) {
            for c in set.channel_names() {
                let _ = set.scene(c);
            }
        }
    }
});
