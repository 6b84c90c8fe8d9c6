//! Which lanes the fitting kernels run with: chosen once per process from
//! what the processor has, or forced by `LAMINAR_SIMD`.
//!
//! | `LAMINAR_SIMD` | lanes |
//! |---|---|
//! | unset or `auto` | AVX2 when the processor has AVX2 and FMA, else portable |
//! | `portable` | `wide::f64x4` (two SSE halves in a build for every x86-64 processor) |
//! | `avx2` | AVX2; an error on a processor without it |
//!
//! Every path gives the same bits (`laminar_brdf_core::simd`): the choice
//! changes only the speed. `laminar report speed-vs-error` and the Python
//! package's `simd_path()` say which path runs.
//!
//! ```
//! use laminar_brdf_fit::simd::{self, Path};
//! let path = simd::path();
//! assert!(matches!(path, Path::Portable | Path::Avx2));
//! ```

pub use laminar_brdf_core::simd::Path;
use laminar_brdf_core::simd::{self as lanes, Kernel};
use std::sync::OnceLock;

/// Why `LAMINAR_SIMD` cannot be followed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SimdError {
    /// Not one of the accepted names.
    #[error("LAMINAR_SIMD={value:?}: expected one of auto, portable, avx2")]
    Unknown {
        /// The variable's value.
        value: String,
    },
    /// AVX2 asked for on a processor (or build target) without it.
    #[error("LAMINAR_SIMD=avx2, but this processor does not have AVX2 and FMA")]
    Unsupported,
}

/// True when the processor has AVX2 and FMA (and the system saves them).
pub fn has_avx2() -> bool {
    lanes::avx2_available()
}

/// The path `LAMINAR_SIMD`'s value `value` (`None`: unset) asks for on
/// this processor.
///
/// # Errors
/// [`SimdError`] for an unknown name, or `avx2` without the instructions.
pub fn choose(value: Option<&str>) -> Result<Path, SimdError> {
    match value.map(str::trim) {
        None | Some("" | "auto") => Ok(if has_avx2() {
            Path::Avx2
        } else {
            Path::Portable
        }),
        Some("portable") => Ok(Path::Portable),
        Some("avx2") if has_avx2() => Ok(Path::Avx2),
        Some("avx2") => Err(SimdError::Unsupported),
        Some(other) => Err(SimdError::Unknown {
            value: other.to_string(),
        }),
    }
}

/// This process's `LAMINAR_SIMD`, read and judged once.
fn chosen() -> &'static Result<Path, SimdError> {
    static CHOSEN: OnceLock<Result<Path, SimdError>> = OnceLock::new();
    CHOSEN.get_or_init(|| {
        let value = std::env::var_os("LAMINAR_SIMD");
        choose(value.as_ref().map(|v| v.to_string_lossy()).as_deref())
    })
}

/// The path of this process's `LAMINAR_SIMD` (read once), or why it cannot
/// be followed. Front ends call it at start to report the error.
///
/// # Errors
/// As [`choose`].
pub fn from_env() -> Result<Path, SimdError> {
    chosen().clone()
}

/// The path the kernels take: [`from_env`]'s, or the portable one when
/// `LAMINAR_SIMD` cannot be followed (front ends report that error first).
/// Called at every kernel's entry: no allocation, even on the error.
pub fn path() -> Path {
    chosen().as_ref().copied().unwrap_or(Path::Portable)
}

/// `kernel` on [`path`]'s lanes.
#[inline]
pub(crate) fn run<K: Kernel>(kernel: K) -> K::Output {
    lanes::run(path(), kernel)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_read_and_refused() {
        assert_eq!(choose(Some("portable")), Ok(Path::Portable));
        assert_eq!(choose(Some(" portable ")), Ok(Path::Portable));
        let auto = choose(None).unwrap();
        assert_eq!(choose(Some("auto")), Ok(auto));
        assert_eq!(auto == Path::Avx2, has_avx2());
        assert_eq!(
            choose(Some("avx2")),
            if has_avx2() {
                Ok(Path::Avx2)
            } else {
                Err(SimdError::Unsupported)
            }
        );
        let err = choose(Some("sse9")).unwrap_err();
        assert_eq!(
            err.to_string(),
            "LAMINAR_SIMD=\"sse9\": expected one of auto, portable, avx2"
        );
    }
}
