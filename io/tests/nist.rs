//! The NIST reader on Germer's sintered-PTFE file
//! (`../shared/data/nist-ptfe/PTFE.data.csv`, its PROVENANCE.md): the
//! counts, the wavelengths, the signed incidence and PROVENANCE.md's spot
//! values. Needs `NIST_DIR` (the directory of `PTFE.data.csv`); without
//! it the test says `SKIPPED`, and fails under `LAMINAR_REQUIRE_NIST=1`
//! (set by `.ci/run`).

mod common;

use common::{data_dir, lab, values};
use laminar_brdf_fit::MeasurementAngles;
use laminar_brdf_io::nist::read_nist;

/// θi, φi, θv, φv in degrees.
fn degrees(a: &MeasurementAngles) -> [f64; 4] {
    lab(a).map(f64::to_degrees)
}

#[test]
fn the_ptfe_file_reads_as_provenance_says() {
    let Some(dir) = data_dir("NIST_DIR", "LAMINAR_REQUIRE_NIST", "NIST test") else {
        return;
    };
    let set = read_nist(&dir.join("PTFE.data.csv")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(set.channel_names(), ["351nm", "532nm", "633nm", "1064nm"]);
    assert_eq!(set.len(), 1824);
    let angles: Vec<[f64; 4]> = set.angles().iter().map(degrees).collect();
    // Per incidence (−75, …, −15, −0.001 as written: the source at azimuth
    // 180°), the viewing directions PROVENANCE.md counts.
    for (theta, count) in [
        (75.0, 305),
        (60.0, 304),
        (45.0, 304),
        (30.0, 304),
        (15.0, 303),
        (0.001, 304),
    ] {
        let n = angles
            .iter()
            .filter(|a| (a[0] - theta).abs() < 1e-9)
            .count();
        assert_eq!(n, count, "θi {theta}");
    }
    assert!(angles.iter().all(|a| (a[1] - 180.0).abs() < 1e-9));
    // Row 1, at each wavelength: 0.262, 0.265, 0.267, 0.272.
    assert!((angles[0][2] - 80.0258).abs() < 1e-9);
    for (channel, want) in [
        ("351nm", 0.262),
        ("532nm", 0.265),
        ("633nm", 0.267),
        ("1064nm", 0.272),
    ] {
        assert_eq!(values(&set, channel)[0], want, "{channel}");
    }
    // The last row: 1064 nm, θi 75, θr 80.0258, φr 23.9625: 0.654.
    let last = angles.len() - 1;
    assert_eq!(
        (angles[last][0], angles[last][2], angles[last][3]),
        (75.0, 80.0258, 23.9625)
    );
    assert_eq!(values(&set, "1064nm")[last], 0.654);
    // The exact specular row at θi 30 is left out as specular, and only
    // rows within the tolerance of the mirror are.
    let exact = (0..angles.len())
        .find(|&k| {
            let [ti, _, tv, pv] = angles[k];
            (ti - 30.0).abs() < 1e-9 && (tv - 30.0).abs() < 1e-9 && pv.abs() < 1e-9
        })
        .unwrap();
    assert_eq!(values(&set, "351nm")[exact], 0.326);
    let kept = set.kept();
    assert!(!kept.contains(&exact));
    assert!(
        kept.len() >= 1818 && kept.len() < 1824,
        "{} kept",
        kept.len()
    );
    // Mean f_r11 at normal incidence per wavelength: 0.3102, 0.3144,
    // 0.3144, 0.3138 (PTFE is white at all four).
    let normal: Vec<usize> = (0..angles.len()).filter(|&k| angles[k][0] < 0.01).collect();
    for (channel, want) in [
        ("351nm", 0.3102),
        ("532nm", 0.3144),
        ("633nm", 0.3144),
        ("1064nm", 0.3138),
    ] {
        let v = values(&set, channel);
        let mean = normal.iter().map(|&k| v[k]).sum::<f64>() / normal.len() as f64;
        assert!(
            (mean - want).abs() < 5e-5,
            "{channel}: {mean} against {want}"
        );
    }
}
