//! Fits under the free-amplitude objective (docs/conventions.md §4b, §11b),
//! a one-way pipeline, each module knowing only those before it:
//!
//! 1. [`model`]: each model's table of nonlinear parameters, its columns
//!    at a point of them and their derivatives ([`model::FreeModel`];
//!    [`boundary`]: the layered models' upper boundary at one n; [`sums`]:
//!    the inner products every step uses);
//! 2. [`linear`]: β and the amplitude in closed form (variable projection);
//! 3. [`problem`]: the weighted objective of one (scene, model, box), and
//!    its normal equations ([`jacobian`]);
//! 4. [`layout`]: the reported parameters' places in it ([`coordinate`])
//!    and the box;
//! 5. [`search`]: the objective on a grid of the nonlinear parameters, and
//!    the grid's basins;
//! 6. [`refine`]: Levenberg–Marquardt from the basins, inside the box;
//! 7. [`statistics`]: what the refined solution says (intervals,
//!    bootstrap, released faces, adequacy, cross-validation);
//! 8. [`record`]: each reported parameter's values, flags and intervals.
//!
//! [`driver`] runs the stages in order, from a scene to a [`crate::Fit`];
//! [`estimate`] and [`slice`] turn points into the estimates it reports.
//!
//! Everything reported lies in the box that was searched.

pub(crate) mod boundary;
pub(crate) mod coordinate;
pub(crate) mod dispatch;
pub(crate) mod driver;
pub(crate) mod estimate;
pub(crate) mod jacobian;
pub(crate) mod joint;
pub(crate) mod layout;
pub(crate) mod linear;
pub(crate) mod model;
mod pool;
pub(crate) mod problem;
pub(crate) mod record;
pub(crate) mod refine;
pub(crate) mod search;
pub(crate) mod slice;
pub(crate) mod statistics;
pub(crate) mod sums;
