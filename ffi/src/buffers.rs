//! Caller-owned buffers from raw C pointers: the one place of this crate
//! that needs `unsafe` (a C caller hands over a pointer and a length; Rust
//! can only trust the pair it is given). Every other module works on slices.

#![allow(unsafe_code)]

use crate::Status;

/// [`Status::BadLength`] unless `count` values of `T` fit in one object
/// (at most `isize::MAX` bytes, what a slice may span): checked before any
/// slice is made from the count.
fn fits<T>(count: usize) -> Result<(), Status> {
    match count.checked_mul(core::mem::size_of::<T>()) {
        Some(bytes) if bytes <= isize::MAX as usize => Ok(()),
        _ => Err(Status::BadLength),
    }
}

/// The `count` values at `ptr` as a slice, or [`Status::NullPointer`] for a
/// null pointer with a positive count.
///
/// # Errors
/// [`Status::BadLength`] for a count no buffer can hold,
/// [`Status::NullPointer`].
pub fn input<'a, T>(ptr: *const T, count: usize) -> Result<&'a [T], Status> {
    fits::<T>(count)?;
    if count == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(Status::NullPointer);
    }
    // SAFETY: the C contract of every function taking `(ptr, count)`: `ptr`
    // points to `count` initialised values that stay valid and unchanged
    // for the call (no output of the call overlaps them: the header's
    // aliasing rule); `count` values span at most isize::MAX bytes (`fits`).
    Ok(unsafe { core::slice::from_raw_parts(ptr, count) })
}

/// The `count` slots at `ptr` as a mutable slice, or
/// [`Status::NullPointer`] for a null pointer with a positive count.
///
/// # Errors
/// [`Status::BadLength`] for a count no buffer can hold,
/// [`Status::NullPointer`].
pub fn output<'a, T>(ptr: *mut T, count: usize) -> Result<&'a mut [T], Status> {
    fits::<T>(count)?;
    if count == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() {
        return Err(Status::NullPointer);
    }
    // SAFETY: the C contract: `ptr` points to `count` writable slots that
    // no other pointer of the call aliases (the header's aliasing rule),
    // valid for the call; they span at most isize::MAX bytes (`fits`).
    Ok(unsafe { core::slice::from_raw_parts_mut(ptr, count) })
}

/// The core's scratch memories, which a [`crate::LaminarFitScratch`] holds:
/// sealed to types of `f32` and `f64` values alone, for which every bit
/// pattern is valid.
pub trait Scratch: sealed::Sealed {}

mod sealed {
    pub trait Sealed {}
    impl Sealed for laminar_brdf_core::small_fit::Scratch {}
    impl Sealed for laminar_brdf_core::small_free_fit::FreeScratch<f32> {}
}

impl Scratch for laminar_brdf_core::small_fit::Scratch {}
impl Scratch for laminar_brdf_core::small_free_fit::FreeScratch<f32> {}

/// The fit's scratch words at `ptr` as one of the core's scratch memories,
/// or [`Status::NullPointer`].
///
/// # Errors
/// [`Status::NullPointer`].
pub fn scratch<'a, T: Scratch>(
    ptr: *mut crate::scratch::LaminarFitScratch,
) -> Result<&'a mut T, Status> {
    if ptr.is_null() {
        return Err(Status::NullPointer);
    }
    // SAFETY: the C contract: `ptr` points to a writable
    // `LaminarFitScratch` that nothing else uses during the call. It is at
    // least as large and as aligned as every `Scratch` type (checked at
    // compile time in `fit.rs`), which hold only `f32` and `f64` values,
    // for which every bit pattern is valid.
    Ok(unsafe { &mut *ptr.cast::<T>() })
}
