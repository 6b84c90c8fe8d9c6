//! A `cdylib` that exports the probe values of `cases.rs`; built for
//! `wasm32-unknown-unknown` and run by node in `core/tests/wasm_parity.rs`.
#![cfg_attr(target_arch = "wasm32", no_std)]

mod cases;

#[cfg(target_arch = "wasm32")]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    core::arch::wasm32::unreachable()
}

/// Number of probe values.
#[no_mangle]
pub extern "C" fn probe_count() -> u32 {
    cases::count()
}

/// Bits of value `i` on the `f32x8` path.
#[no_mangle]
pub extern "C" fn probe_f32x8(i: u32) -> u32 {
    cases::value_f32x8(i)
}

/// Bits of value `i` on the scalar `f32` path.
#[no_mangle]
pub extern "C" fn probe_f32(i: u32) -> u32 {
    cases::value_f32(i)
}

/// Bits of value `i` on the scalar `f64` path.
#[no_mangle]
pub extern "C" fn probe_f64(i: u32) -> u64 {
    cases::value_f64(i)
}
