//! The baseline models the paper compares against (docs/conventions.md §7).

pub mod jensen;
pub mod oren_nayar;
