//! A model's table of nonlinear parameters: each parameter's name and the
//! coordinate it is searched and refined in. Every stage finds a parameter
//! in θ by its name ([`Table::position`]), never by a fixed index.

use crate::model::Param;

/// The coordinate a nonlinear parameter is searched and refined in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    /// The parameter itself.
    Linear,
    /// Its logarithm (σ/T: its box is log-spaced, and steps are relative).
    Log,
}

impl Scale {
    /// `value` (model units) in this coordinate.
    pub fn internal(self, value: f64) -> f64 {
        match self {
            Self::Linear => value,
            Self::Log => libm::log(value),
        }
    }

    /// `value` of this coordinate in model units.
    pub fn external(self, value: f64) -> f64 {
        match self {
            Self::Linear => value,
            Self::Log => libm::exp(value),
        }
    }

    /// A `[lo, hi]` range (model units) in this coordinate.
    pub fn range(self, (lo, hi): (f64, f64)) -> (f64, f64) {
        (self.internal(lo), self.internal(hi))
    }
}

/// One nonlinear parameter: its name and coordinate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Nonlinear {
    /// The parameter.
    pub name: Param,
    /// Its coordinate in θ.
    pub scale: Scale,
}

impl Nonlinear {
    /// A parameter in its own units.
    pub const fn linear(name: Param) -> Self {
        Self {
            name,
            scale: Scale::Linear,
        }
    }

    /// A parameter in its logarithm.
    pub const fn log(name: Param) -> Self {
        Self {
            name,
            scale: Scale::Log,
        }
    }
}

/// The nonlinear parameters of a model, in θ's order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Table {
    entries: Vec<Nonlinear>,
}

impl Table {
    /// The table of `entries`, in θ's order.
    pub fn new(entries: Vec<Nonlinear>) -> Self {
        Self { entries }
    }

    /// Number of nonlinear parameters.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// The parameters, in θ's order.
    pub fn entries(&self) -> &[Nonlinear] {
        &self.entries
    }

    /// Where `name` is in θ (`None` when the model has no such
    /// nonlinear parameter).
    pub fn position(&self, name: Param) -> Option<usize> {
        self.entries.iter().position(|e| e.name == name)
    }

    /// Every parameter free (a minimisation over all of them).
    pub fn all_free(&self) -> Vec<bool> {
        vec![true; self.len()]
    }

    /// Every parameter free but `held`.
    pub fn hold(&self, held: Param) -> Vec<bool> {
        self.entries.iter().map(|e| e.name != held).collect()
    }
}
