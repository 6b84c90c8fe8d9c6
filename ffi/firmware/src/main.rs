//! Evaluates every probe case (`laminar_brdf_ffi::probe`) through the C ABI on
//! the device and prints, in hex: per geometry (`G` lines) the fields of
//! its two `f32`-built geometries; per (geometry, parameters, correlation)
//! the case's values (`probe::case_values`). The host test computes the
//! same lines and compares them bit for bit.

#![no_std]
#![no_main]

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprint, hprintln};
use laminar_brdf_ffi::probe;
use laminar_firmware as _; // the interrupt table

// The panic handler is laminar-brdf-ffi's (bare metal): no function it exports
// panics, and the host test runs this image under a timeout.

#[entry]
fn main() -> ! {
    for g in 0..probe::GEOMETRIES {
        hprint!("G {}", g);
        for v in probe::geometry_values(g) {
            hprint!(" {:08x}", v);
        }
        hprintln!();
        for j in 0..probe::PARAMS {
            for corr in 0..2 {
                hprint!("{} {} {}", g, j, corr);
                for v in probe::case_values(g, j, corr) {
                    hprint!(" {:x}", v);
                }
                hprintln!();
            }
        }
    }
    hprintln!("done");
    debug::exit(debug::EXIT_SUCCESS);
    loop {
        cortex_m::asm::wfi(); // not reached: the exit above ends QEMU
    }
}
