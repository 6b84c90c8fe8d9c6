//! The on-device fits at K = 32 and K = 64, once each, counted as `bench`
//! counts (QEMU `-icount shift=0`, [`laminar_firmware::timer`]): the
//! paper objective's (`laminar_fit`) on the paper grid (5,555,000 points),
//! printed as `FIT k instructions status index rms_bits`, and the free
//! amplitude's (`laminar_fit_free`) on its σ/T, n and a axes (55,550
//! points), printed as `FREE k instructions status index objective_bits
//! rms_bits`. The host test compares the results with the same calls on
//! the host.

#![no_std]
#![no_main]

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use laminar_firmware::{timer, timer_start, INSTRUCTIONS_PER_TICK};

#[entry]
fn main() -> ! {
    timer_start();
    for k in [32, 64] {
        let t0 = timer();
        let (status, index, rms_bits) = laminar_brdf_ffi::probe::fit_values(k);
        let t1 = timer();
        let count = t0.wrapping_sub(t1) as u64 * INSTRUCTIONS_PER_TICK;
        hprintln!(
            "FIT {} {} {} {} {:x}",
            k,
            count,
            status as u32,
            index,
            rms_bits
        );
    }
    for k in [32, 64] {
        let t0 = timer();
        let (status, index, objective_bits, rms_bits) = laminar_brdf_ffi::probe::free_fit_values(k);
        let t1 = timer();
        let count = t0.wrapping_sub(t1) as u64 * INSTRUCTIONS_PER_TICK;
        hprintln!(
            "FREE {} {} {} {} {:x} {:x}",
            k,
            count,
            status as u32,
            index,
            objective_bits,
            rms_bits
        );
    }
    hprintln!("done");
    debug::exit(debug::EXIT_SUCCESS);
    loop {
        cortex_m::asm::wfi(); // not reached: the exit above ends QEMU
    }
}
