//! A free fit's intervals at its minimum (docs/conventions.md §11b): the
//! levels, the Jacobian covariance and the profile's walks on both sides
//! of every reported parameter, run side by side; a walk that finds a
//! point below the minimum restarts the refinement from there (MINOS's
//! "new minimum"), at most [`MOST_RESTARTS`] times.

use super::covariance::JacobianCovariance;
use super::levels::Levels;
use super::profile::{Side, Walk, WalkSettings};
use super::Solution;
use crate::analysis::Analysis;
use crate::free::model::FreeModel;
use crate::free::problem::{Point, Problem};
use crate::free::refine::{minimise, TOLERANCE};
use rayon::prelude::*;

/// Most restarts of the refinement from a lower point an interval's walk
/// found.
pub const MOST_RESTARTS: usize = 3;

/// Below this fraction of `Σ w D²`, a level's height is too close to the
/// objective's rounding (about 10⁻¹⁶ of it) for a profile to resolve.
const RESOLVABLE_LEVEL: f64 = 1e-13;

/// One parameter's profile ends, `[below, above]`, each at the 68.27% and
/// 95% levels as (value, stopped at the face of the box).
pub type Ends = [[(f64, bool); 2]; 2];

/// Intervals and covariance at a minimum.
#[derive(Debug, Clone)]
pub struct Analysed {
    /// The minimum (lower than the refinement's when a walk found one).
    pub minimum: Point,
    /// The levels, when there are degrees of freedom.
    pub levels: Option<Levels>,
    /// The Jacobian covariance, when `JᵀJ` is not singular.
    pub covariance: Option<JacobianCovariance>,
    /// Per reported parameter, `[below, above]` ends of both levels.
    pub profile: Option<Vec<Ends>>,
    /// True when the data are fitted to rounding: the residuals say
    /// nothing of the noise, so no misfit-robust interval is formed.
    pub rounding: bool,
}

impl Analysed {
    /// No intervals at `minimum` (the analysis off, or no degrees of
    /// freedom).
    pub fn none(minimum: Point) -> Self {
        Self {
            minimum,
            levels: None,
            covariance: None,
            profile: None,
            rounding: false,
        }
    }
}

/// The intervals at `solution`'s minimum, refining again from any lower
/// point a walk finds (at most [`MOST_RESTARTS`] times).
pub fn intervals<M: FreeModel>(solution: Solution<'_, M>, analysis: Analysis) -> Analysed {
    let Solution {
        problem,
        layout,
        mut minimum,
    } = solution;
    let coordinates = &layout.coordinates;
    let mut restarts = 0;
    loop {
        let Some(levels) = Levels::new(problem, minimum.sse) else {
            return Analysed::none(minimum);
        };
        let covariance = JacobianCovariance::new(problem, &minimum, coordinates, levels.s2);
        let rounding = fitted_to_rounding(problem, &levels);
        if !analysis.uncertainty.profile() || rounding {
            return Analysed {
                levels: Some(levels),
                covariance,
                rounding,
                ..Analysed::none(minimum)
            };
        }
        let sides: Vec<(usize, f64)> = (0..coordinates.len())
            .flat_map(|i| [(i, -1.0), (i, 1.0)])
            .collect();
        let walks: Vec<Walk> = sides
            .par_iter()
            .map(|&(index, direction)| {
                Side {
                    problem,
                    minimum: &minimum,
                    coordinate: coordinates[index],
                    index,
                    covariance: covariance.as_ref(),
                    coordinates,
                    direction,
                    levels,
                    settings: WalkSettings::default(),
                }
                .walk()
            })
            .collect();
        if restarts < MOST_RESTARTS {
            if let Some(lower) = lowest_new_minimum(&walks) {
                restarts += 1;
                let free = problem.all_free();
                let again = minimise(problem, &lower.theta, &free, problem.beta, TOLERANCE).point;
                if again.sse < minimum.sse {
                    minimum = again;
                    continue;
                }
            }
        }
        return Analysed {
            levels: Some(levels),
            covariance,
            profile: Some(
                walks
                    .chunks(2)
                    .map(|pair| [ends(&pair[0]), ends(&pair[1])])
                    .collect(),
            ),
            rounding,
            ..Analysed::none(minimum)
        };
    }
}

/// The lowest point below the minimum that a walk found.
fn lowest_new_minimum(walks: &[Walk]) -> Option<&Point> {
    walks
        .iter()
        .filter_map(|w| match w {
            Walk::NewMinimum(p) => Some(p),
            Walk::Ends(_) => None,
        })
        .min_by(|a, b| a.sse.total_cmp(&b.sse))
}

/// A walk's ends; a lower point that refinement could not improve on
/// leaves them unknown on its side, and the face closes it.
fn ends(walk: &Walk) -> [(f64, bool); 2] {
    match walk {
        Walk::Ends(e) => *e,
        Walk::NewMinimum(_) => [(f64::NAN, true); 2],
    }
}

/// True when the data are fitted to rounding (noise-free data): the 68%
/// level lies below [`RESOLVABLE_LEVEL`] of `Σ w D²`, where the profile's
/// heights are rounding noise (its walks would end at the box's faces). The
/// intervals then come from the Jacobian (docs/conventions.md §11b).
fn fitted_to_rounding<M>(problem: &Problem<M>, levels: &Levels) -> bool {
    levels.heights[0] < RESOLVABLE_LEVEL * problem.dd
}
