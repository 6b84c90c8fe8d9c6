//! Axis specs (`--slope`, `--beta`, `--n`, `--a`): any text gives an axis
//! or an error, never a panic or an allocation beyond the limit; a parsed
//! axis in a grid validates or is refused.
#![no_main]

use laminar_brdf_fit::{Axis, Grid};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(axis) = Axis::parse(text) {
        assert!(axis.len() <= laminar_brdf_fit::grid::MAX_AXIS_LEN);
        for g in [
            Grid {
                slope: axis.clone(),
                ..Grid::paper()
            },
            Grid {
                beta: axis.clone(),
                ..Grid::paper()
            },
            Grid {
                n: axis.clone(),
                ..Grid::paper()
            },
            Grid {
                a: axis,
                ..Grid::paper()
            },
        ] {
            let _ = g.validate();
        }
    }
});
