//! Buffers of the evaluations, kept per thread for the next evaluation.
//!
//! A fit evaluates its columns, their derivatives and its residuals a few
//! hundred times, each a vector of K values (and a layered model's terms,
//! a group per four measurements); above glibc's per-thread cache (1 KB),
//! each allocation and release goes through the allocator's bins. The
//! vectors released here ([`Columns`](super::basis::Columns) on drop, the
//! residuals by hand) are handed out again by [`vector`], emptied, and the
//! layered terms' groups likewise by their own [`Free`] in
//! [`super::basis`]: the arithmetic never sees what a vector held before,
//! so nothing a fit computes depends on them.

use std::cell::RefCell;

/// A thread's free vectors of one element type, at most `MOST` of them:
/// about as many as one step of a minimisation has in use at once (each
/// kept vector stays allocated until its thread ends).
pub(super) struct Free<T, const MOST: usize>(RefCell<Vec<Vec<T>>>);

impl<T, const MOST: usize> Free<T, MOST> {
    pub(super) const fn new() -> Self {
        Self(RefCell::new(Vec::new()))
    }

    /// An empty vector with room for at least `len` elements.
    pub(super) fn take(&self, len: usize) -> Vec<T> {
        let mut v = self.0.borrow_mut().pop().unwrap_or_default();
        v.clear();
        v.reserve(len);
        v
    }

    /// Keeps `v` (when it holds memory and fewer than `MOST` are kept).
    pub(super) fn give(&self, v: Vec<T>) {
        if v.capacity() > 0 {
            let mut free = self.0.borrow_mut();
            if free.len() < MOST {
                free.push(v);
            }
        }
    }
}

thread_local! {
    /// Columns, derivatives and residuals: seven at a Jacobian.
    static VECTORS: Free<f64, 12> = const { Free::new() };
}

/// An empty vector of `f64` with room for `len` values.
pub(super) fn vector(len: usize) -> Vec<f64> {
    VECTORS.with(|f| f.take(len))
}

/// Keeps `v` for a later [`vector`].
pub(super) fn release(v: Vec<f64>) {
    // During a thread's teardown the pool may be gone: then `v` is freed.
    let _ = VECTORS.try_with(|f| f.give(v));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A released vector comes back from the next [`vector`] of this
    /// thread: the same memory, emptied, with the room asked for.
    #[test]
    fn a_released_vector_is_handed_out_again_empty() {
        let mut v = vector(198);
        v.extend((0..198).map(f64::from));
        let at = v.as_ptr();
        release(v);
        let again = vector(100);
        assert!(again.is_empty());
        assert!(again.capacity() >= 198);
        assert_eq!(again.as_ptr(), at);
        // More room than it has: grown, still empty.
        release(again);
        let bigger = vector(1_000);
        assert!(bigger.is_empty() && bigger.capacity() >= 1_000);
    }
}
