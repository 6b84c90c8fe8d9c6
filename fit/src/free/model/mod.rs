//! The models of the free objective (docs/conventions.md §4b), each one
//! implementation of [`FreeModel`] (the shape of varpro's
//! `SeparableNonlinearModel`): its table of nonlinear parameters
//! ([`Table`]), its columns at a point of them and their derivatives, and
//! its grid stage. The linear coefficients (β and the amplitude) multiply
//! the columns and are solved in closed form ([`super::linear`]).
//!
//! * [`LayeredModel`] (eqs. 1–2, 12–13): two columns, the raw surface term
//!   `S_k = L^sf_k` and the raw subsurface term `U_k = L^sb_k(a)`; eq. 8's
//!   mix is `(1 − β) S + β U`, times the amplitude. The nonlinear
//!   parameters are σ/T (searched and refined in its logarithm, so that
//!   steps are relative, as its box is log-spaced), n and, for the
//!   absorptive models, a (Ragheb–Hancock's a is 0). `U` is a quadratic in
//!   a: `U = B (1 − a cos²θi)(1 − a cos²θs)` with `B` the Ragheb–Hancock
//!   base (eqs. 3–4), which the grid stage uses.
//! * [`BaselineModel`] (§7): one column, the raw radiance `L_k` (Jensen's at
//!   (σa, σs′), Oren–Nayar's at (σ, ρ)).
//!
//! Every stage of the pipeline is written once over [`FreeModel`] (and
//! the grid stage's [`super::search::GridStage`]);
//! [`super::dispatch::dispatch`] picks the implementation of a [`Model`].

mod baseline;
mod layered;
mod table;

pub use baseline::BaselineModel;
pub use layered::{LayeredModel, Packed};
pub use table::{Nonlinear, Scale, Table};

use super::pool;
use crate::grid::{Axis, Grid};
use crate::model::Model;
use laminar_brdf_core::Angles;

/// The columns of a model at one point: `s` always, `u` for a model with
/// a second column (empty otherwise). Of a derivative, an empty column is
/// zero (the surface term's in n and a).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Columns {
    /// `S_k` (layered) or `L_k` (baseline).
    pub s: Vec<f64>,
    /// `U_k` (layered), empty for a one-column model.
    pub u: Vec<f64>,
}

impl Drop for Columns {
    /// The vectors go back to the thread's pool ([`pool`]).
    fn drop(&mut self) {
        pool::release(std::mem::take(&mut self.s));
        pool::release(std::mem::take(&mut self.u));
    }
}

/// The columns at one point, with what their derivatives there need
/// (`kept`), so that a minimisation that accepts a trial point reuses its
/// work.
#[derive(Debug, Clone)]
pub struct Evaluated<K> {
    /// The columns.
    pub columns: Columns,
    /// What the model keeps for the derivatives at this point.
    pub kept: K,
}

/// A model of the free objective: its nonlinear parameters, its columns
/// and their derivatives at a point of them.
pub trait FreeModel: Sized + Send + Sync + 'static {
    /// What an evaluation keeps for the derivatives at its point.
    type Kept: Send;
    /// What a minimisation keeps while some parameters are held
    /// ([`FreeModel::held`]).
    type Held: Default + Send + Sync;

    /// `model` at the measurements' directions `angles`.
    fn new(model: Model, angles: &[Angles]) -> Self;

    /// The model this is.
    fn model(&self) -> Model;

    /// The nonlinear parameters, in θ's order.
    fn table(&self) -> &Table;

    /// The grid axis of each nonlinear parameter, in θ's order (model
    /// units): the layered models' from `grid`, the baselines' their own.
    fn axes(&self, grid: &Grid) -> Vec<Axis>;

    /// True when the model has the second column `U` (and so β).
    fn has_balance(&self) -> bool;

    /// Number of measurements.
    fn len(&self) -> usize;

    /// What stays fixed while the parameters marked `free` move from
    /// `theta`.
    fn held(&self, theta: &[f64], free: &[bool]) -> Self::Held;

    /// The columns at `theta`, reusing what `held` keeps when it applies,
    /// and keeping what [`FreeModel::derivatives_at`] needs.
    fn evaluate(&self, theta: &[f64], held: &Self::Held) -> Evaluated<Self::Kept>;

    /// The columns at `theta`, already evaluated there (`at`), and their
    /// derivatives with respect to the parameters marked `wanted` (`None`
    /// for the others: a held parameter costs nothing). Differences, where
    /// a model uses them, are central when `central` (one-sided at an end
    /// of `domain`), else forward.
    fn derivatives_at(
        &self,
        theta: &[f64],
        domain: &[(f64, f64)],
        central: bool,
        at: Evaluated<Self::Kept>,
        wanted: &[bool],
    ) -> (Columns, Vec<Option<Columns>>);

    /// The columns at `theta`.
    fn columns(&self, theta: &[f64]) -> Columns {
        self.evaluate(theta, &Self::Held::default()).columns
    }

    /// The columns at `theta` and their derivatives with respect to every
    /// nonlinear parameter ([`FreeModel::derivatives_at`]).
    fn derivatives(
        &self,
        theta: &[f64],
        domain: &[(f64, f64)],
        central: bool,
    ) -> (Columns, Vec<Columns>) {
        let wanted = vec![true; theta.len()];
        let at = self.evaluate(theta, &Self::Held::default());
        let (columns, derivatives) = self.derivatives_at(theta, domain, central, at, &wanted);
        (columns, derivatives.into_iter().flatten().collect())
    }
}
