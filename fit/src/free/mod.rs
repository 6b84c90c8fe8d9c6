//! Fits under the free-amplitude objective (docs/conventions.md §4b, §11b),
//! a one-way pipeline, each module knowing only those before it:
//!
//! 1. [`basis`]: the model's columns at given nonlinear parameters
//!    ([`boundary`]: the upper boundary's terms at one n; [`sums`]: the
//!    inner products every step uses);
//! 2. [`linear`]: β and the amplitude in closed form (variable projection);
//! 3. [`problem`]: the weighted objective of one (scene, model, box);
//! 4. [`search`]: the objective on a grid of the nonlinear parameters, and
//!    the grid's basins;
//! 5. [`refine`]: Levenberg–Marquardt from the basins, inside the box;
//! 6. [`intervals`]: Jacobian covariance and profile intervals;
//! 7. [`record`]: each reported parameter's values, flags and intervals.
//!
//! [`layout`] maps the reported parameters onto the objective, and
//! [`driver`] runs the stages in order, from a scene to a [`crate::Fit`].
//!
//! Everything reported lies in the box that was searched.

pub(crate) mod basis;
pub(crate) mod bootstrap;
pub(crate) mod boundary;
mod cross_validation;
pub(crate) mod driver;
pub(crate) mod intervals;
pub(crate) mod layout;
pub(crate) mod linear;
mod pool;
pub(crate) mod problem;
pub(crate) mod record;
pub(crate) mod refine;
pub(crate) mod search;
pub(crate) mod sums;
