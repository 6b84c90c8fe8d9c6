//! The one place that maps a [`Model`] to its implementation of the free
//! objective ([`super::model::FreeModel`] and its grid stage, [`GridStage`]): a new
//! model is one arm here and one implementation in [`super::model`].

use super::model::{BaselineModel, LayeredModel};
use super::search::GridStage;
use crate::model::{Family, Model};

/// Work on one model's implementation, whichever it is ([`dispatch`]).
pub trait WithModel {
    /// What the work returns.
    type Output;
    /// The work, on `model`'s implementation `M`.
    fn run<M: GridStage>(self, model: Model) -> Self::Output;
}

/// `work` run on the implementation of `model`.
pub fn dispatch<W: WithModel>(model: Model, work: W) -> W::Output {
    match model.family() {
        Family::Layered { .. } => work.run::<LayeredModel>(model),
        Family::Baseline(_) => work.run::<BaselineModel>(model),
    }
}
