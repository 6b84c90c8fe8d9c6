//! What the images of this package share: the interrupt vector table and
//! the instruction counter of the benchmarks.
//!
//! Without a device crate, cortex-m-rt fills 240 interrupt vectors (960
//! bytes of flash); the MPS2 AN386 has 32. A real firmware has its own
//! device's table: this one is the emulated board's, so that the images'
//! flash is what the model costs plus what any firmware carries.

#![no_std]

/// The 32 external interrupt vectors, every one the default handler
/// (the images enable no interrupt).
#[link_section = ".vector_table.interrupts"]
#[no_mangle]
pub static __INTERRUPTS: [unsafe extern "C" fn(); 32] = [{
    unsafe extern "C" {
        fn DefaultHandler();
    }
    DefaultHandler
}; 32];

/// Instructions per tick of [`timer`] under QEMU `-icount shift=0` (one
/// instruction per virtual nanosecond): the timer counts at 25 MHz, 40 ns.
pub const INSTRUCTIONS_PER_TICK: u64 = 40;

/// The MPS2's APB timer 0 (CMSDK): control, current value, reload.
const TIMER_CTRL: *mut u32 = 0x4000_0000 as *mut u32;
const TIMER_VALUE: *mut u32 = 0x4000_0004 as *mut u32;
const TIMER_RELOAD: *mut u32 = 0x4000_0008 as *mut u32;

/// Starts APB timer 0 counting down from `u32::MAX` (wrapping).
#[allow(unsafe_code)]
pub fn timer_start() {
    // SAFETY: memory-mapped registers of the MPS2's APB timer 0, which
    // nothing else in these images uses.
    unsafe {
        TIMER_RELOAD.write_volatile(u32::MAX);
        TIMER_VALUE.write_volatile(u32::MAX);
        TIMER_CTRL.write_volatile(1);
    }
}

/// The timer's current value (it counts down: elapsed ticks are
/// `earlier.wrapping_sub(later)`).
#[allow(unsafe_code)]
pub fn timer() -> u32 {
    // SAFETY: as in `timer_start`.
    unsafe { TIMER_VALUE.read_volatile() }
}
