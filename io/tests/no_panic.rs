//! No input makes a reader panic: arbitrary text for the CSV and CUReT
//! readers (often with a valid header, so the value parsing is reached) and
//! arbitrary bytes for the MERL reader. Every failure is an error naming the
//! file.

use laminar_brdf_fit::Quantity;
use laminar_brdf_io::curet::{read_brdf, read_oren_nayar, read_table};
use laminar_brdf_io::{merl, read_csv, read_geometry, AngleUnit};
use proptest::prelude::*;

/// Text from an alphabet that makes numbers, separators, comments and junk.
fn text() -> impl Strategy<Value = String> {
    let header = prop_oneof![
        Just("theta_i,phi_i,theta_v,phi_v,value\n".to_string()),
        Just("theta_i,theta_s,phi_s,r,g,sigma_r\n".to_string()),
        Just("theta_i,theta_s,phi_s,sigma,v\n".to_string()),
        Just(String::new()),
    ];
    let body = proptest::collection::vec(
        prop_oneof![
            Just("0.5"),
            Just("-1"),
            Just("1e400"),
            Just("nan"),
            Just("inf"),
            Just(","),
            Just("\n"),
            Just("\r\n"),
            Just("#"),
            Just(" "),
            Just("x"),
            Just("\""),
            Just("90"),
            Just("0"),
            Just("1.5707963267948966"),
            Just("1e-300"),
            Just("\u{00e9}"),
        ],
        0..60,
    )
    .prop_map(|v| v.concat());
    (header, body).prop_map(|(h, b)| h + &b)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn text_readers_never_panic(t in text(), deg in any::<bool>()) {
        let d = tempfile::tempdir().unwrap();
        let path = d.path().join("m.csv");
        std::fs::write(&path, &t).unwrap();
        let unit = if deg { AngleUnit::Degrees } else { AngleUnit::Radians };
        for r in [
            read_csv(&path, unit, Quantity::Brdf).map(|_| ()),
            read_geometry(&path, unit).map(|_| ()),
            read_table(&path).map(|_| ()),
            read_brdf(&path, 3).map(|_| ()),
            read_oren_nayar(&path).map(|_| ()),
        ] {
            if let Err(e) = r {
                prop_assert!(e.to_string().contains("m.csv"), "{e}");
            }
        }
        // A set that reads fine becomes a scene or a named error, never a panic.
        if let Ok(set) = read_csv(&path, unit, Quantity::Brdf) {
            for c in set.channel_names() {
                let _ = set.scene(c);
            }
        }
    }

    #[test]
    fn merl_reader_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..64)) {
        let d = tempfile::tempdir().unwrap();
        let path = d.path().join("m.binary");
        std::fs::write(&path, &bytes).unwrap();
        let e = merl::read_merl(&path).unwrap_err();
        prop_assert!(e.to_string().contains("m.binary"));
    }
}

#[test]
fn merl_with_wrong_dimensions_or_length_is_named() {
    let d = tempfile::tempdir().unwrap();
    let path = d.path().join("m.binary");
    let mut bytes: Vec<u8> = [90i32, 90, 360]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    std::fs::write(&path, &bytes).unwrap();
    let e = merl::read_merl(&path).unwrap_err().to_string();
    assert!(e.contains("dimensions 90×90×360"), "{e}");
    bytes = [90i32, 90, 180]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    bytes.extend_from_slice(&[0; 16]);
    std::fs::write(&path, &bytes).unwrap();
    let e = merl::read_merl(&path).unwrap_err().to_string();
    assert!(e.contains("28 bytes, expected 34992012"), "{e}");
}
