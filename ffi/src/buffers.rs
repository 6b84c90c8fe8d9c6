//! Caller-owned buffers from raw C pointers: the one place of this crate
//! that needs `unsafe` (a C caller hands over a pointer and a length; Rust
//! can only trust the pair it is given). Every other module works on slices.

#![allow(unsafe_code)]

use crate::Status;

/// The `count` values at `ptr` as a slice, or [`Status::NullPointer`] for a
/// null pointer with a positive count.
///
/// # Errors
/// [`Status::NullPointer`].
pub fn input<'a, T>(ptr: *const T, count: usize) -> Result<&'a [T], Status> {
    if count == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(Status::NullPointer);
    }
    // SAFETY: the C contract of every function taking `(ptr, count)`: `ptr`
    // points to `count` initialised values that stay valid and unchanged
    // for the call.
    Ok(unsafe { core::slice::from_raw_parts(ptr, count) })
}

/// The `count` slots at `ptr` as a mutable slice, or
/// [`Status::NullPointer`] for a null pointer with a positive count.
///
/// # Errors
/// [`Status::NullPointer`].
pub fn output<'a, T>(ptr: *mut T, count: usize) -> Result<&'a mut [T], Status> {
    if count == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() {
        return Err(Status::NullPointer);
    }
    // SAFETY: the C contract: `ptr` points to `count` writable slots that
    // no other pointer of the call aliases, valid for the call.
    Ok(unsafe { core::slice::from_raw_parts_mut(ptr, count) })
}
