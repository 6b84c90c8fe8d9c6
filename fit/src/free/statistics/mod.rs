//! What a free fit says about its parameters, each a function of the
//! refinement's [`Solution`] in a file of its own (varpro's
//! `statistics`): the intervals' levels ([`levels`]), the Jacobian and
//! sandwich covariance ([`covariance`]), the profile's walks
//! ([`profile`]), the intervals with their restarts from a lower point
//! ([`intervals`]), the pairs bootstrap ([`bootstrap`]), the fits with a
//! face of the box released ([`release`]), the residuals' adequacy and the
//! information criteria ([`adequacy`]), cross-validation
//! ([`cross_validation`]), and the joint fit's robust score test of one
//! value for every channel ([`score_test`]).

pub mod adequacy;
pub mod bootstrap;
pub mod covariance;
pub mod cross_validation;
pub mod intervals;
pub mod levels;
pub mod profile;
pub mod release;
pub mod score_test;

use super::layout::Layout;
use super::model::FreeModel;
use super::problem::{Point, Problem};
use crate::model::attainable_domain;

/// What the refinement returns: the minimum of one problem in its box,
/// and the layout that maps the reported parameters onto it.
#[derive(Debug)]
pub struct Solution<'a, M> {
    /// The objective.
    pub problem: &'a Problem<M>,
    /// The reported parameters' places in it.
    pub layout: &'a Layout,
    /// The minimum.
    pub minimum: Point,
}

impl<M: FreeModel> Solution<'_, M> {
    /// Reported parameter `i`'s value at the minimum.
    pub fn value(&self, i: usize) -> f64 {
        self.layout.coordinates[i].value(&self.minimum, self.problem)
    }

    /// Reported parameter `i`'s box, in its units.
    pub fn bounds(&self, i: usize) -> (f64, f64) {
        self.layout.coordinates[i].bounds(self.problem)
    }

    /// Reported parameter `i`'s domain, exactly (an open lower end at the
    /// smallest value a fit takes; not through σ/T's logarithm).
    pub fn domain(&self, i: usize) -> (f64, f64) {
        attainable_domain(self.layout.names[i])
    }
}
