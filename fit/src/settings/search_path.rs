//! The paper objective's search path ([`SearchPath`]): which method of the
//! exhaustive search (crate::paper::search) runs, in which arithmetic.

use crate::error::UnknownName;
use std::fmt;
use std::str::FromStr;

/// How the β loop of the search is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Method {
    /// SearchPath 1: every (parameter set, measurement) pair evaluated in full.
    Direct,
    /// SearchPath 2: hoisted terms, one pass per parameter set.
    OnePass,
    /// SearchPath 3: hoisted terms, closed-form β sweep over the upper envelope.
    Envelope,
}

/// The arithmetic a path evaluates the model in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Arith {
    /// `f32x8` SIMD (eight measurements per vector).
    F32x8,
    /// Scalar `f32`, the bitwise twin of [`Arith::F32x8`].
    F32,
    /// Scalar `f64`.
    F64,
}

/// A search path: a method in an arithmetic, e.g. `envelope-f32x8`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SearchPath {
    /// The method.
    pub method: Method,
    /// The arithmetic.
    pub arith: Arith,
}

impl SearchPath {
    /// The default of every command: the closed-form sweep on `f32x8`.
    pub const DEFAULT: SearchPath = SearchPath::new(Method::Envelope, Arith::F32x8);
    /// The accuracy reference: direct `f64`.
    pub const REFERENCE: SearchPath = SearchPath::new(Method::Direct, Arith::F64);

    /// A path.
    pub const fn new(method: Method, arith: Arith) -> Self {
        Self { method, arith }
    }

    /// Every path, reference first.
    pub fn all() -> Vec<SearchPath> {
        let mut out = Vec::new();
        for method in [Method::Direct, Method::OnePass, Method::Envelope] {
            for arith in [Arith::F64, Arith::F32, Arith::F32x8] {
                out.push(SearchPath::new(method, arith));
            }
        }
        out
    }

    /// The same method in the other f32 arithmetic (`f32x8` ↔ `f32`), the pair
    /// whose grid values must agree bit for bit.
    pub fn twins(self) -> (SearchPath, SearchPath) {
        (
            SearchPath::new(self.method, Arith::F32x8),
            SearchPath::new(self.method, Arith::F32),
        )
    }
}

impl fmt::Display for SearchPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let method = match self.method {
            Method::Direct => "direct",
            Method::OnePass => "onepass",
            Method::Envelope => "envelope",
        };
        let arith = match self.arith {
            Arith::F32x8 => "f32x8",
            Arith::F32 => "f32",
            Arith::F64 => "f64",
        };
        write!(f, "{method}-{arith}")
    }
}

impl FromStr for SearchPath {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, UnknownName> {
        SearchPath::all()
            .into_iter()
            .find(|p| p.to_string() == s)
            .ok_or_else(|| UnknownName {
                what: "search path",
                given: s.to_string(),
                expected: "METHOD-ARITH with METHOD one of direct, onepass, envelope and ARITH one of f32x8, f32, f64".into(),
            })
    }
}
