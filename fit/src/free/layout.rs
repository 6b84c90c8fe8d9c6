//! How a model's reported parameters map onto the free objective
//! (docs/conventions.md §4b): the box and grid of each nonlinear parameter
//! (in its coordinate, ln σ/T for the slope) and β's box, built once per
//! fit (or batch) from the model's table and the user's grid.

use super::coordinate::Coordinate;
use super::model::{FreeModel, Scale};
use super::search::GridAxes;
use crate::grid::Grid;
use crate::model::{attainable_domain, Param};

/// A model's reported parameters and how each maps onto the objective.
#[derive(Debug, Clone)]
pub struct Layout {
    /// The reported parameters, in output order.
    pub names: &'static [Param],
    /// Where each is in the objective.
    pub coordinates: Vec<Coordinate>,
    /// Grid axes of the nonlinear parameters (model units).
    pub axes: GridAxes,
    /// Box of the nonlinear parameters (internal coordinates).
    pub bounds: Vec<(f64, f64)>,
    /// The same box in the parameters' units.
    pub reported: Vec<(f64, f64)>,
    /// Domain of the nonlinear parameters (internal coordinates).
    pub domain: Vec<(f64, f64)>,
    /// β's box.
    pub beta: (f64, f64),
}

impl Layout {
    /// The layout of `model` (at any measurements) on `grid`: its
    /// nonlinear parameters' axes ([`FreeModel::axes`]) and β's.
    pub fn new<M: FreeModel>(model: &M, grid: &Grid) -> Self {
        let table = model.table();
        let axes = model.axes(grid);
        let names = model.model().free_params();
        let coordinates = names
            .iter()
            .map(|&name| match table.position(name) {
                Some(j) => Coordinate::Nonlinear {
                    j,
                    log: table.entries()[j].scale == Scale::Log,
                },
                None => Coordinate::Beta,
            })
            .collect();
        let entries = table.entries();
        Self {
            names,
            coordinates,
            bounds: (entries.iter().zip(&axes))
                .map(|(e, axis)| e.scale.range(axis.range()))
                .collect(),
            reported: axes.iter().map(|axis| axis.range()).collect(),
            domain: entries
                .iter()
                .map(|e| e.scale.range(attainable_domain(e.name)))
                .collect(),
            beta: if model.has_balance() {
                grid.beta.range()
            } else {
                (0.0, 0.0)
            },
            axes: GridAxes::new(table, axes),
        }
    }
}
