//! How well a free fit's model fits: the adequacy tests of its residuals
//! ([`crate::adequacy`]), χ²/ν and the information criteria
//! ([`crate::choice`]).

use super::Solution;
use crate::adequacy::{Adequacy, RunsOrder};
use crate::choice::Information;
use crate::free::model::{Columns, FreeModel};
use crate::free::problem::{Point, Problem};

/// The adequacy tests of the residuals at `solution`'s minimum, whose
/// columns are `columns` (`runs_order` the scene's measurements in the
/// runs test's order).
pub fn adequacy<M: FreeModel>(
    solution: &Solution<'_, M>,
    runs_order: &RunsOrder,
    columns: &Columns,
) -> Adequacy {
    let problem = solution.problem;
    let e = problem.residuals(columns, &solution.minimum.linear);
    Adequacy::in_order(runs_order, &e, problem.parameter_count(), problem.weighted)
}

/// The information criteria at `solution`'s minimum.
pub fn information<M: FreeModel>(solution: &Solution<'_, M>) -> Option<Information> {
    let problem = solution.problem;
    Information::new(
        solution.minimum.sse,
        problem.data.len(),
        problem.parameter_count(),
        problem.weighted,
    )
}

/// `Σ w r² / (K − p)` at `point`, when there are degrees of freedom.
pub fn chi2_weighted<M: FreeModel>(problem: &Problem<M>, point: &Point) -> Option<f64> {
    let nu = problem.data.len().checked_sub(problem.parameter_count())?;
    (nu > 0).then(|| point.sse / nu as f64)
}
