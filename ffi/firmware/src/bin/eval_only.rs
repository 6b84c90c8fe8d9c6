//! The smallest useful image: a sensor's directions in, the model's f32
//! radiance out, through the C ABI, and nothing else (no formatting).
//! `ffi/tests/firmware_cost.rs` measures its flash and checks it links no
//! `f64` software routine; it exits with failure if a call fails.

#![no_std]
#![no_main]

use core::hint::black_box;
use cortex_m_rt::entry;
use cortex_m_semihosting::debug;
use laminar_brdf_ffi::{
    laminar_evaluate_f32, laminar_geometry_from_directions, LaminarDirections, LaminarGeometry,
    LaminarParamsF32, Status,
};
use laminar_firmware as _; // the interrupt table

#[entry]
fn main() -> ! {
    // Opaque inputs, as if read from a sensor.
    let d = black_box(LaminarDirections {
        cos_i: 0.867_819,
        sin_i: 0.496_880,
        cos_s: 0.613_746,
        sin_s: 0.789_504,
        cos_phi: -0.666_276,
        sin_phi: 0.745_705,
    });
    let p = black_box(LaminarParamsF32 {
        slope: 1.48,
        beta: 0.39,
        n: 1.44,
        a: 0.17,
    });
    let mut g = LaminarGeometry::default();
    let mut out = [0.0f32; 2];
    let ok = laminar_geometry_from_directions(&d, 1, &mut g) == Status::Ok
        && laminar_evaluate_f32(0, p, &g, 1, &mut out[0]) == Status::Ok
        && laminar_evaluate_f32(1, p, &g, 1, &mut out[1]) == Status::Ok;
    black_box(out);
    debug::exit(if ok && out[0] > 0.0 && out[1] > 0.0 {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    loop {
        cortex_m::asm::wfi(); // not reached: the exit above ends QEMU
    }
}
