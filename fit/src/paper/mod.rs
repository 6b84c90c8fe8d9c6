//! The paper's objective after its grid search (docs/conventions.md §11),
//! as a one-way pipeline: each module knows only those before it.
//!
//! 1. `objective`: `Σ (D − P)²` of the max-normalised prediction over a
//!    model's continuous parameters.
//! 2. `refine`: Nelder–Mead from the grid's basins.
//! 3. `intervals`: the Jacobian's covariance and the profile intervals.
//! 4. `record`: each searched parameter's value, intervals and flags.
//! 5. [`profiles`]: the profile curves of a reported fit, for figures.
//!
//! The grid search before it is [`crate::paper::search`]; the free-amplitude
//! objective has its own pipeline, `crate::free`.

pub(crate) mod driver;
pub(crate) mod intervals;
pub(crate) mod objective;
pub mod profiles;
pub(crate) mod record;
pub(crate) mod refine;
pub mod search;
