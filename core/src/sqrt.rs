//! The correctly rounded `f32` square root of the scalar path.
//!
//! IEEE 754 defines `sqrt` to the bit, so every implementation gives the
//! same result; only the cost differs. On ARM hard-float targets
//! (`target_abi = "eabihf"`: Cortex-M4F, M7F, M33F and the like) the FPU's
//! `vsqrt.f32` is one instruction, where libm's software `sqrtf` is about
//! 50 (the `libm` crate has no ARM path, and `core` has no stable
//! `f32::sqrt`). Everywhere else this is `libm::sqrtf`, unchanged.
//!
//! The instruction needs inline assembly, hence `unsafe`: this module is
//! the only place in the crate that has any (the crate denies `unsafe_code`
//! and allows it here). The firmware test (`ffi/tests/firmware.rs`)
//! compares the Cortex-M4 results with the host's, bit for bit.

/// `√x`, correctly rounded (IEEE 754 round-to-nearest-even).
///
/// Rust's inline assembly offers the single-precision registers only with
/// the double-precision `vfp2` feature, which single-precision FPUs (the
/// M4F's) lack. So the operands travel in core registers and the
/// assembly borrows `s0`, restoring it: seven instructions with the moves,
/// against about fifty for the software root.
#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
#[inline]
#[allow(unsafe_code)]
pub fn sqrtf(x: f32) -> f32 {
    let root: f32;
    // SAFETY: the assembly saves `s0` in a scratch core register, computes
    // in it, and restores it, so no register the compiler uses changes
    // except the declared outputs; it touches no memory, no stack and no
    // flags other than the FPSCR's cumulative exception bits. Every
    // hard-float ABI guarantees the FPU is present and enabled.
    unsafe {
        core::arch::asm!(
            "vmov {saved}, s0",
            "vmov s0, {x}",
            "vsqrt.f32 s0, s0",
            "vmov {root}, s0",
            "vmov s0, {saved}",
            x = in(reg) x,
            root = lateout(reg) root,
            saved = out(reg) _,
            options(pure, nomem, nostack, preserves_flags),
        );
    }
    root
}

/// `√x`, correctly rounded (libm).
#[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
#[inline]
pub fn sqrtf(x: f32) -> f32 {
    libm::sqrtf(x)
}
