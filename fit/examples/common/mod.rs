//! What the grid examples (`grid_precision`, `grid_density`) share: the
//! geometries their sets are drawn on, and how much two fits of one set
//! differ.

use laminar_brdf_core::Angles;
use laminar_brdf_fit::synthetic;
use laminar_brdf_fit::Fit;
use laminar_brdf_io::curet::CuretDir;
use std::path::{Path, PathBuf};

/// A labelled geometry: the directions of a set's measurements.
pub type Geometry = (&'static str, Vec<Angles>);

/// The built-in geometry, and CUReT sample 21's when `CURET_DIR` is set.
pub fn geometries() -> Result<Vec<Geometry>, Box<dyn std::error::Error>> {
    let mut geometries = vec![("built-in", synthetic::geometries())];
    if let Some(dir) = std::env::var_os("CURET_DIR") {
        let scene = CuretDir::open(Path::new(&dir))?
            .samples(&[PathBuf::from("abrdf.dat")], Some(&[21]))?
            .remove(0)
            .set
            .scene("avg")?;
        geometries.push(("CUReT 21", scene.angles().to_vec()));
    }
    Ok(geometries)
}

/// The largest changes between two fits of one set, as fractions of the
/// `f64` fit's 68.27% intervals: (grid point moved, refined value, an
/// interval's end).
pub fn changes(wide: &Fit, narrow: &Fit) -> (bool, f64, f64) {
    let mut moved = false;
    let (mut value, mut end) = (0.0f64, 0.0f64);
    for (p, q) in wide.parameters.iter().zip(&narrow.parameters) {
        assert_eq!(p.name, q.name);
        moved |= p.grid != q.grid;
        let Some(width) = p.interval68.map(|i| i.hi - i.lo).filter(|w| *w > 0.0) else {
            continue;
        };
        value = value.max((p.value() - q.value()).abs() / width);
        for (a, b) in [(p.interval68, q.interval68), (p.interval95, q.interval95)] {
            if let (Some(a), Some(b)) = (a, b) {
                end = end.max((a.lo - b.lo).abs().max((a.hi - b.hi).abs()) / width);
            }
        }
    }
    (moved, value, end)
}
