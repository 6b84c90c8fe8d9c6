//! The on-device fit (`laminar_fit`) on the paper grid (5,555,000 points)
//! at K = 32 and K = 64, once each, counted as `bench` counts (QEMU
//! `-icount shift=0`, APB timer 0 at 25 MHz: 40 instructions per tick).
//! Prints `FIT k instructions status index rms_bits`; the host test
//! compares the results with the same call on the host.

#![no_std]
#![no_main]

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use laminar_firmware as _; // the interrupt table

const TIMER_CTRL: *mut u32 = 0x4000_0000 as *mut u32;
const TIMER_VALUE: *mut u32 = 0x4000_0004 as *mut u32;
const TIMER_RELOAD: *mut u32 = 0x4000_0008 as *mut u32;

#[entry]
#[allow(unsafe_code)]
fn main() -> ! {
    // SAFETY: memory-mapped registers of the MPS2's APB timer 0, which
    // nothing else uses in this image.
    let timer = || unsafe { TIMER_VALUE.read_volatile() };
    unsafe {
        TIMER_RELOAD.write_volatile(u32::MAX);
        TIMER_VALUE.write_volatile(u32::MAX);
        TIMER_CTRL.write_volatile(1);
    }
    for k in [32, 64] {
        let t0 = timer();
        let (status, index, rms_bits) = laminar_ffi::probe::fit_values(k);
        let t1 = timer();
        let count = t0.wrapping_sub(t1) as u64 * 40;
        hprintln!("FIT {} {} {} {} {:x}", k, count, status as u32, index, rms_bits);
    }
    hprintln!("done");
    debug::exit(debug::EXIT_SUCCESS);
    loop {
        cortex_m::asm::wfi(); // not reached: the exit above ends QEMU
    }
}
