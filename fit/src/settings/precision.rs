//! The free objective's grid-stage arithmetic ([`Precision`]).

/// The arithmetic of the grid stage's model side: each column's base `B`
/// (eqs. 3–7) at every grid point of σ/T and n. Its sums, the data's and
/// every later stage run in `f64` either way.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Precision {
    /// `f64x4` lanes (the default): the grid values are the objective
    /// evaluated in `f64` at each grid point.
    #[default]
    F64,
    /// `f32x8` lanes (the core's single-precision path, bitwise its scalar
    /// `f32` on every target), widened exactly to `f64` for the sums: each
    /// `B` within a few `f32` ulps, so a grid value moves by about 10⁻⁷ of
    /// `Σ w D²`, which can change the grid's best point only among
    /// near-ties; the refinement then runs in `f64` from the grid's basins
    /// (the measured differences: docs/speed.md).
    F32,
}

impl Precision {
    /// Both, the default first.
    pub const ALL: [Precision; 2] = [Self::F64, Self::F32];
}

impl std::fmt::Display for Precision {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::F64 => "f64",
            Self::F32 => "f32",
        })
    }
}

impl std::str::FromStr for Precision {
    type Err = crate::error::UnknownName;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        crate::error::find_named("precision", &Self::ALL, |p| p.to_string(), s)
    }
}
