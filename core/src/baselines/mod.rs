//! The baseline models the paper compares against (conventions §7).

pub mod jensen;
pub mod oren_nayar;
