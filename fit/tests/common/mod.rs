//! What the integration tests share: the paper's CUReT samples, the
//! Cornell gonioreflectometer's geometry.

#![allow(dead_code)] // each test binary uses some of these

use laminar_brdf_core::Angles;
use laminar_brdf_fit::Scene;
use laminar_brdf_io::curet::CuretDir;
use std::path::{Path, PathBuf};

/// The paper's 13 CUReT samples.
pub const PAPER_SAMPLES: [u32; 13] = [1, 3, 7, 18, 19, 21, 25, 48, 51, 52, 53, 55, 61];

/// The avg channel of the paper's 13 samples from `CURET_DIR`, or `None`
/// after printing, past the test harness's capture, that `test` was
/// skipped (a failure instead with `LAMINAR_REQUIRE_CURET`).
pub fn paper_scenes(test: &str) -> Option<Vec<Scene>> {
    let Some(dir) = std::env::var_os("CURET_DIR") else {
        if std::env::var_os("LAMINAR_REQUIRE_CURET").is_some() {
            panic!("LAMINAR_REQUIRE_CURET is set but CURET_DIR is not");
        }
        let _ = std::io::Write::write_all(
            &mut std::io::stderr(),
            format!("SKIPPED {test}: CURET_DIR is not set\n").as_bytes(),
        );
        return None;
    };
    let samples = CuretDir::open(Path::new(&dir))
        .unwrap()
        .samples(&[PathBuf::from("abrdf.dat")], Some(&PAPER_SAMPLES))
        .unwrap();
    assert_eq!(samples.len(), PAPER_SAMPLES.len());
    Some(
        samples
            .iter()
            .map(|s| s.set.scene("avg").unwrap())
            .collect(),
    )
}

/// The 1,439 geometries of Cornell's `krylon_blue.astm` from `CORNELL_DIR`,
/// or `None` after printing that `test` was skipped (a failure instead
/// with `LAMINAR_REQUIRE_CORNELL`).
pub fn cornell_geometry(test: &str) -> Option<Vec<Angles>> {
    let Some(dir) = std::env::var_os("CORNELL_DIR") else {
        if std::env::var_os("LAMINAR_REQUIRE_CORNELL").is_some() {
            panic!("LAMINAR_REQUIRE_CORNELL is set but CORNELL_DIR is not");
        }
        let _ = std::io::Write::write_all(
            &mut std::io::stderr(),
            format!("SKIPPED {test}: CORNELL_DIR is not set\n").as_bytes(),
        );
        return None;
    };
    let set = laminar_brdf_io::astm::read_astm(&Path::new(&dir).join("krylon_blue.astm")).unwrap();
    Some(set.scenes().unwrap().remove(0).angles().to_vec())
}
