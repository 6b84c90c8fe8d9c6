//! The ASTM E1392 reader on the Cornell gonioreflectometer's files
//! (`../shared/data/cornell`, its PROVENANCE.md): row counts, wavelengths,
//! the shared geometry, and PROVENANCE.md's spot values. Needs
//! `CORNELL_DIR` (the directory of the `.astm` files); without it the test
//! says `SKIPPED`, and fails under `LAMINAR_REQUIRE_CORNELL=1` (set by
//! `.ci/run`).

mod common;

use common::{data_dir, lab, values};
use laminar_brdf_fit::MeasurementSet;
use laminar_brdf_io::astm::read_astm;

/// The value of `channel` at the row nearest the mirror direction among
/// those with θi at `theta_i_deg`, and that row's distance from the mirror
/// (degrees, as the angle between the two directions).
fn nearest_mirror(set: &MeasurementSet, channel: &str, theta_i_deg: f64) -> (f64, f64) {
    let values = values(set, channel);
    let unit = |theta: f64, phi: f64| {
        [
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        ]
    };
    let (mut best, mut value) = (f64::INFINITY, f64::NAN);
    for (k, a) in set.angles().iter().enumerate() {
        let [ti, pi, tv, pv] = lab(a);
        if (ti.to_degrees() - theta_i_deg).abs() > 0.01 {
            continue;
        }
        let mirror = unit(ti, pi + std::f64::consts::PI);
        let view = unit(tv, pv);
        let cos: f64 = mirror.iter().zip(&view).map(|(a, b)| a * b).sum();
        let off = cos.clamp(-1.0, 1.0).acos().to_degrees();
        if off < best {
            (best, value) = (off, values[k]);
        }
    }
    (value, best)
}

#[test]
fn the_cornell_files_read_as_provenance_says() {
    let Some(dir) = data_dir("CORNELL_DIR", "LAMINAR_REQUIRE_CORNELL", "Cornell test") else {
        return;
    };
    let read = |name: &str| read_astm(&dir.join(name)).unwrap_or_else(|e| panic!("{e}"));
    let wavelengths: Vec<String> = (400..=700).step_by(10).map(|w| format!("{w}nm")).collect();
    let spectral = ["krylon_blue.astm", "cayman.astm", "acryl_blue.astm"];
    let sets: Vec<MeasurementSet> = spectral.iter().map(|n| read(n)).collect();
    let rgb = read("krylon_blue_RGB.astm");
    for (name, set) in spectral.iter().zip(&sets) {
        assert_eq!(set.len(), 1439, "{name}");
        assert_eq!(set.channel_names(), wavelengths, "{name}");
    }
    assert_eq!(rgb.len(), 1439);
    assert_eq!(rgb.channel_names(), ["r", "g", "b"]);
    // Every file on the same 1,439 geometries, row by row.
    for set in sets.iter().chain([&rgb]) {
        assert_eq!(set.angles(), sets[0].angles());
    }
    // φi = 0 everywhere; θi in 10°, …, 80°; no row exactly at the mirror.
    let angles: Vec<[f64; 4]> = sets[0].angles().iter().map(lab).collect();
    assert!(angles.iter().all(|a| a[1] == 0.0));
    for a in &angles {
        let deg = a[0].to_degrees();
        assert!(
            ((deg / 10.0).round() * 10.0 - deg).abs() < 0.01
                && (10.0..=80.0).contains(&deg.round())
        );
    }
    // The first and last rows of krylon_blue.
    let krylon = &sets[0];
    assert_eq!(angles[0], [0.872665, 0.0, 0.573513, 0.0]);
    let at = |set: &MeasurementSet, channel: &str, k: usize| values(set, channel)[k];
    assert_eq!(
        (at(krylon, "400nm", 0), at(krylon, "410nm", 0)),
        (0.017415, 0.036844)
    );
    let last = 1438;
    assert_eq!(angles[last][2].to_degrees().round(), 79.0);
    for (channel, want) in [("400nm", 64.22), ("550nm", 34.78), ("700nm", 49.53)] {
        let v = at(krylon, channel, last);
        assert!((v - want).abs() < 0.005, "{channel}: {v} against {want}");
    }
    // The 550 nm values nearest the mirror direction, and how far off it.
    let spots: [(usize, [f64; 4]); 3] = [
        (0, [0.171, 0.354, 0.670, 34.78]),
        (1, [0.166, 0.478, 8.216, 631.3]),
        (2, [0.0365, 3.224, 7.766, 24.10]),
    ];
    let off_mirror = [1.9, 1.4, 0.21, 0.95];
    for (s, want) in spots {
        for ((theta, want), off) in [10.0, 40.0, 50.0, 80.0].iter().zip(want).zip(off_mirror) {
            let (v, d) = nearest_mirror(&sets[s], "550nm", *theta);
            assert!(
                (v - want).abs() <= 0.0051 * want,
                "{} θi {theta}: {v} against {want}",
                spectral[s]
            );
            assert!(
                (d - off).abs() < 0.05,
                "{} θi {theta}: {d}° off the mirror, {off}° said",
                spectral[s]
            );
        }
    }
    // The blue paint is blue off the specular peak (θi 30°, θs 0).
    let diffuse = (0..1439)
        .find(|&k| (angles[k][0].to_degrees() - 30.0).abs() < 0.01 && angles[k][2] == 0.0)
        .unwrap();
    assert!((at(krylon, "450nm", diffuse) - 0.093).abs() < 0.001);
    assert!((at(krylon, "700nm", diffuse) - 0.013).abs() < 0.001);
    // acryl_blue's clipped zeros: 18,901 of its 44,609 values.
    let zeros: usize = (sets[2].channel_names().iter())
        .map(|c| values(&sets[2], c).iter().filter(|&&v| v == 0.0).count())
        .sum();
    assert_eq!(zeros, 18_901);
    // The RGB file keeps its negative values (Cornell left them in).
    assert!(values(&rgb, "r").iter().any(|&v| v < 0.0));
}
