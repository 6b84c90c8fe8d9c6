//! The RGL reader on the database's isotropic RGB `.bsdf` files
//! (`../shared/data/rgl`, its PROVENANCE.md): the light's angles, and the
//! spot values PROVENANCE.md gives for each material at normal incidence,
//! at the mirror of the second light angle and at the node nearest
//! θo = 0 there. Needs `RGL_DIR` (the directory of the `.bsdf` files);
//! without it the test says `SKIPPED`, and fails under
//! `LAMINAR_REQUIRE_RGL=1` (set by `.ci/run`).

mod common;

use common::{data_dir, lab};
use laminar_brdf_fit::{MeasurementAngles, MeasurementSet};
use laminar_brdf_io::rgl::read_rgl;

/// θi, θo in degrees.
fn polar(a: &MeasurementAngles) -> [f64; 2] {
    let [theta_i, _, theta_v, _] = lab(a);
    [theta_i.to_degrees(), theta_v.to_degrees()]
}

/// The r, g, b values of measurement `k`.
fn rgb(set: &MeasurementSet, k: usize) -> [f64; 3] {
    let c = set.channels();
    [c[0].values[k], c[1].values[k], c[2].values[k]]
}

/// Each of `want` within 0.5% (and 10⁻³ absolute, for the values near 0)
/// of `got`.
fn close(got: [f64; 3], want: [f64; 3]) -> bool {
    got.iter()
        .zip(want)
        .all(|(g, w)| (g - w).abs() <= 0.005 * w.abs() + 1e-3)
}

#[test]
fn the_rgl_files_read_as_provenance_says() {
    let Some(dir) = data_dir("RGL_DIR", "LAMINAR_REQUIRE_RGL", "RGL test") else {
        return;
    };
    // Per file: the second light angle; r, g, b at normal incidence; at
    // the mirror of the second angle; then θo of the node nearest the
    // normal there, and its r, g, b.
    #[rustfmt::skip]
    let spots: [(&str, [f64; 11]); 5] = [
        ("paper_white", [27.7, 0.278, 0.283, 0.331, 0.250, 0.253, 0.294, 2.4, 0.274, 0.279, 0.328]),
        ("satin_rosaline", [27.5, 1.64, 1.02, 1.41, 2.47, 1.45, 1.85, 2.7, 0.203, 0.234, 0.223]),
        ("vch_golden_yellow", [31.6, 8.78, 4.49, 0.0, 8.47, 4.29, 0.0, 4.3, 0.0256, 0.0237, 0.0087]),
        ("cc_iris_purple_gem", [30.1, 0.933, 1.64, 3.96, 1.31, 1.67, 3.89, 3.4, 0.0, 0.0162, 0.0481]),
        ("cg_sunflower", [27.7, 119.0, 81.4, 44.0, 43.0, 43.1, 44.9, 1.2, 0.272, 0.129, 0.0]),
    ];
    for (name, [second, spot @ ..]) in spots {
        let rgb3 = |at: usize| [spot[at], spot[at + 1], spot[at + 2]];
        let (normal, mirror, off_theta, off) = (rgb3(0), rgb3(3), spot[6], rgb3(7));
        let set = read_rgl(&dir.join(format!("{name}_rgb.bsdf"))).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(set.channel_names(), ["r", "g", "b"], "{name}");
        let angles: Vec<[f64; 2]> = set.angles().iter().map(polar).collect();
        let mut lights: Vec<f64> = angles.iter().map(|a| a[0]).collect();
        lights.dedup();
        // Seven light angles: the file's eight but the grazing 90°.
        assert_eq!(lights.len(), 7, "{name}: {lights:?}");
        assert_eq!(lights[0], 0.0);
        assert!((lights[1] - second).abs() < 0.06, "{name}: {lights:?}");
        assert!(angles.iter().all(|a| a[1] < 90.0 && a[0] < 89.9));
        // Normal incidence, viewed at the normal (the mirror, where the
        // warp's first column lands).
        let at_normal = (0..angles.len())
            .filter(|&k| angles[k][0] == 0.0 && angles[k][1] < 0.02)
            .collect::<Vec<_>>();
        assert!(!at_normal.is_empty(), "{name}");
        assert!(
            at_normal.iter().any(|&k| close(rgb(&set, k), normal)),
            "{name} normal: {:?}",
            rgb(&set, at_normal[0])
        );
        // The mirror of the second light angle: the first column's nodes,
        // one per row, one of which PROVENANCE.md gives. They land within
        // 0.02° of it, not on it: the warp takes the first column of nodes
        // to the first column of the VNDF with mass.
        let copies: Vec<usize> = (0..angles.len())
            .filter(|&k| angles[k][0] == lights[1] && set.angles()[k].is_specular(1e-3))
            .collect();
        let side = if name == "cg_sunflower" { 64 } else { 32 };
        assert!(
            copies.len() >= side,
            "{name}: {} mirror copies",
            copies.len()
        );
        let spread = |c: usize| {
            let v: Vec<f64> = copies.iter().map(|&k| rgb(&set, k)[c]).collect();
            (
                v.iter().cloned().fold(f64::INFINITY, f64::min),
                v.iter().cloned().fold(0.0, f64::max),
            )
        };
        for (c, want) in mirror.iter().enumerate() {
            let (lo, hi) = spread(c);
            assert!(
                *want >= 0.995 * lo - 1e-3 && *want <= 1.005 * hi + 1e-3,
                "{name} mirror {c}: {want} outside [{lo}, {hi}]"
            );
        }
        // The node nearest θo = 0 at the second light angle.
        let nearest = (0..angles.len())
            .filter(|&k| angles[k][0] == lights[1])
            .min_by(|&x, &y| angles[x][1].total_cmp(&angles[y][1]))
            .unwrap();
        assert!(
            (angles[nearest][1] - off_theta).abs() < 0.06,
            "{name}: θo {}",
            angles[nearest][1]
        );
        assert!(
            close(rgb(&set, nearest), off),
            "{name} off: {:?}",
            rgb(&set, nearest)
        );
        // Out-of-gamut values are clipped: nothing negative.
        assert!(set
            .channels()
            .iter()
            .all(|c| c.values.iter().all(|&v| v >= 0.0)));
    }
}
