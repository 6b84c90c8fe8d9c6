//! The baselines under the free amplitude (docs/conventions.md §7): one
//! column, the raw radiance `L_k` at the baseline's two parameters
//! (Jensen's (σa, σs′), Oren–Nayar's (σ, ρ)), and its derivatives by
//! differences.

use super::table::{Nonlinear, Table};
use super::{Columns, Evaluated, FreeModel};
use crate::baseline::BaselineGeometry;
use crate::grid::{Axis, Grid};
use crate::model::{baseline_grid, Model};
use laminar_brdf_core::Angles;

/// Central difference step of the baselines' parameters: relative error
/// about `h²` from the truncation and `ε/h` from rounding, both near
/// 10⁻¹⁰.
const STEP: f64 = 1e-5;

/// A baseline at the measurements' directions.
#[derive(Debug, Clone)]
pub struct BaselineModel {
    model: Model,
    table: Table,
    geometry: BaselineGeometry,
}

impl BaselineModel {
    /// The baseline's two parameters at `theta` ([`laminar_brdf_core::Baseline`]'s order).
    fn params(theta: &[f64]) -> [f64; 2] {
        <[f64; 2]>::try_from(theta).expect("a baseline has two nonlinear parameters")
    }
}

impl FreeModel for BaselineModel {
    type Kept = ();
    type Held = ();

    fn new(model: Model, angles: &[Angles]) -> Self {
        let baseline = model
            .baseline()
            .unwrap_or_else(|| panic!("{model} is not a baseline"));
        let table = Table::new(
            baseline
                .params()
                .iter()
                .map(|&p| Nonlinear::linear(p))
                .collect(),
        );
        Self {
            model,
            table,
            geometry: BaselineGeometry::new(baseline, angles),
        }
    }

    fn model(&self) -> Model {
        self.model
    }

    fn table(&self) -> &Table {
        &self.table
    }

    /// The baseline's own grid ([`baseline_grid`]), whatever `grid` holds.
    fn axes(&self, _grid: &Grid) -> Vec<Axis> {
        let (outer, inner) = baseline_grid(self.geometry.baseline());
        vec![outer, inner]
    }

    fn has_balance(&self) -> bool {
        false
    }

    fn len(&self) -> usize {
        self.geometry.len()
    }

    fn held(&self, _theta: &[f64], _free: &[bool]) {}

    fn evaluate(&self, theta: &[f64], _held: &()) -> Evaluated<()> {
        let s = self
            .geometry
            .radiance(Self::params(theta))
            .expect("inside the box, which is inside the domain");
        Evaluated {
            columns: Columns { s, u: Vec::new() },
            kept: (),
        }
    }

    /// Differences: central when `central` (one-sided at an end of
    /// `domain`), else forward (one evaluation less, for the steps of a
    /// minimisation).
    fn derivatives_at(
        &self,
        theta: &[f64],
        domain: &[(f64, f64)],
        central: bool,
        at: Evaluated<()>,
        wanted: &[bool],
    ) -> (Columns, Vec<Option<Columns>>) {
        let at = at.columns;
        let out = (0..theta.len())
            .map(|j| {
                if !wanted[j] {
                    return None;
                }
                let (h, lo, hi) = difference(theta[j], domain[j], central);
                let moved = |v: f64| {
                    if v == theta[j] {
                        return at.s.clone();
                    }
                    let mut t = theta.to_vec();
                    t[j] = v;
                    std::mem::take(&mut self.columns(&t).s)
                };
                let (up, down) = (moved(hi), moved(lo));
                Some(Columns {
                    s: up.iter().zip(&down).map(|(u, d)| (u - d) / h).collect(),
                    u: Vec::new(),
                })
            })
            .collect();
        (at, out)
    }
}

/// The points `(width, lower, upper)` of a difference quotient at `v`
/// inside `[lo, hi]`: central where both fit (when `central`), else
/// one-sided.
fn difference(v: f64, (lo, hi): (f64, f64), central: bool) -> (f64, f64, f64) {
    let h = STEP * v.abs().max(1e-2);
    let (down, up) = match (v - h >= lo, v + h <= hi) {
        (true, true) if central => (v - h, v + h),
        (_, true) => (v, v + h),
        (true, false) => (v - h, v),
        (false, false) => (v, v + h),
    };
    (up - down, down, up)
}
