//! CUReT `table.txt`, BRDF tables and Oren–Nayar files: any bytes give rows
//! or an error naming the file, never a panic; rows that read become
//! measurement sets and scenes or named errors.
#![no_main]

use laminar_brdf_io::curet::{measurement_set, parse_brdf, parse_oren_nayar, parse_table, Channel};
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let file = Path::new("fuzz.dat");
    let _ = parse_oren_nayar(file, data);
    if let Ok(table) = parse_table(file, data) {
        assert!(!table.is_empty());
    }
    // The same bytes as a BRDF table for a small geometry table.
    let table = parse_table(file, b"1 0.1 0 0.2 1\n2 0.3 1 0.4 2\n3 0.5 2 0.6 3\n").unwrap();
    if let Ok(rows) = parse_brdf(file, data, table.len()) {
        for row in &rows {
            if let Ok(set) = measurement_set(file, &table, row, Channel::Avg) {
                let _ = set.scene("avg");
            }
        }
    }
});
