//! Evaluates every probe case (`laminar_ffi::probe`) through the C ABI on
//! the device and prints, one line per (geometry, parameters, correlation):
//! the f32 total's bits, then the seven f64 components' bits, in hex.

#![no_std]
#![no_main]

use cortex_m_rt::entry;
use laminar_firmware as _; // the interrupt table
use cortex_m_semihosting::{debug, hprintln};
use laminar_ffi::{
    laminar_components_f64, laminar_total_radiance_f32, probe, Status, LAMINAR_COMPONENTS,
};

// The panic handler is laminar-ffi's (bare metal): no function it exports
// panics, and the host test runs this image under a timeout.

#[entry]
fn main() -> ! {
    for g in 0..probe::GEOMETRIES {
        let a = probe::angles(g);
        for j in 0..probe::PARAMS {
            let p = probe::params(j);
            for corr in 0..2 {
                let mut total = [0.0f32];
                let mut parts = [0.0f64; LAMINAR_COMPONENTS];
                let s1 = laminar_total_radiance_f32(corr, p, &a, 1, total.as_mut_ptr());
                let s2 = laminar_components_f64(corr, p, &a, 1, parts.as_mut_ptr());
                if s1 != Status::Ok || s2 != Status::Ok {
                    hprintln!("status {} {}", s1 as u32, s2 as u32);
                    debug::exit(debug::EXIT_FAILURE);
                }
                hprintln!(
                    "{} {} {} {:08x} {:016x} {:016x} {:016x} {:016x} {:016x} {:016x} {:016x}",
                    g,
                    j,
                    corr,
                    total[0].to_bits(),
                    parts[0].to_bits(),
                    parts[1].to_bits(),
                    parts[2].to_bits(),
                    parts[3].to_bits(),
                    parts[4].to_bits(),
                    parts[5].to_bits(),
                    parts[6].to_bits()
                );
            }
        }
    }
    hprintln!("done");
    debug::exit(debug::EXIT_SUCCESS);
    loop {}
}
