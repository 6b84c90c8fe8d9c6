//! What a fit does, set by name from any front end: the objective, the
//! grid's axes (and with the free objective the box every estimate and
//! interval stays in), the search path, the free objective's grid-stage
//! precision, the analysis after the search and the worker threads. The command line, Python and WebAssembly hand their
//! options over by name and text ([`Settings::set`]); the parsing and the
//! checks are here, once, and [`Settings::fitter`] builds the [`Fitter`].
//!
//! ```
//! use laminar_brdf_fit::{Objective, Param, Settings};
//! let mut s = Settings::default();
//! s.set("objective", "paper")?;
//! s.set("n", "1.3:1.5:11")?;
//! s.set("refine", "false")?;
//! let grid = s.grid()?;
//! assert_eq!(grid.n.len(), 11);
//! // The other axes are the paper objective's, set in any order.
//! assert_eq!(grid.slope.len(), 50);
//! let e = s.set("sigma", "0:1:3").unwrap_err();
//! assert!(e.to_string().contains("slope, beta, n, a"), "{e}");
//! assert_eq!(s.fitter()?.objective_of_fits(), Objective::Paper);
//! // The free objective's grid stage in f32x8 lanes.
//! s.set("precision", "f32")?;
//! let e = s.set("precision", "f16").unwrap_err();
//! assert!(e.to_string().contains("f64 or f32"), "{e}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::analysis::{parse_folds, parse_resamples, parse_seed, Analysis, Uncertainty};
use crate::error::{choices, FitError, GridError, UnknownName};
use crate::fit::Fitter;
use crate::fitted::param_names;
use crate::grid::{Axis, Grid};
use crate::model::Param;
use crate::noise::{Noise, DEFAULT_FLOOR};
use crate::objective::Objective;
use thiserror::Error;

pub mod precision;
pub mod search_path;
pub use precision::Precision;
pub use search_path::{Arith, Method, SearchPath};

/// A fit's settings: `laminar fit`'s defaults unless set.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// The objective (free by default).
    pub objective: Objective,
    /// The axes given, each replacing the objective's default axis
    /// ([`Objective::default_grid`]) whatever the order they were set in.
    pub axes: Vec<(Param, Axis)>,
    /// The search path of the layered models (the paper objective's grid search).
    pub path: SearchPath,
    /// The arithmetic of the free objective's grid stage (layered models).
    pub precision: Precision,
    /// Refinement and uncertainty after the search.
    pub analysis: Analysis,
    /// Worker threads (`None`: every core).
    pub threads: Option<usize>,
    /// The free objective's noise model ([`crate::noise`]; its floor is
    /// [`Settings::noise_floor`]'s).
    pub noise: Noise,
    /// The floor of relative noise ([`Noise::Relative`]).
    pub noise_floor: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            objective: Objective::Free,
            axes: Vec::new(),
            path: SearchPath::DEFAULT,
            precision: Precision::F64,
            analysis: Analysis::FULL,
            threads: None,
            noise: Noise::Given,
            noise_floor: DEFAULT_FLOOR,
        }
    }
}

/// A setting that cannot be taken: its name, and why.
#[derive(Debug, Error)]
pub enum SettingError {
    /// A name that is no setting.
    #[error(transparent)]
    Unknown(UnknownName),
    /// A value the setting does not take.
    #[error("{name}: {message}")]
    Value {
        /// The setting.
        name: String,
        /// Why, from the setting's parser.
        message: String,
    },
}

/// The names [`Settings::set`] takes besides the grid's axes ([`Grid::PARAMS`]).
pub const NAMES: [&str; 11] = [
    "objective",
    "refine",
    "uncertainty",
    "resamples",
    "seed",
    "folds",
    "path",
    "precision",
    "threads",
    "noise",
    "noise_floor",
];

impl Settings {
    /// Sets option `name` from its text: `objective` (`free`, `paper`),
    /// `refine` (`true`, `false`), `uncertainty` (`off`, `profile`,
    /// `jacobian`, `both`, `bootstrap`), `resamples` (the bootstrap's, 2 to
    /// 100,000), `seed` (the bootstrap's and the folds'), `folds` (of the
    /// cross-validation comparing models: 0, or 2 to 100), `path` (`METHOD-ARITH`),
    /// `precision` (the free objective's grid stage: `f64`, `f32`),
    /// `threads` (a count), `noise` (`given`, `equal`, `relative`:
    /// [`crate::noise`]), `noise_floor` (relative noise's floor, a fraction
    /// in (0, 1] of the median positive value)
    /// or a grid axis by its parameter's name (`slope`, `beta`, `n`, `a`:
    /// `start:stop:count`, `start:stop:count:log` or one value).
    ///
    /// # Errors
    /// [`SettingError`] naming the setting and what is wrong with the value.
    pub fn set(&mut self, name: &str, value: &str) -> Result<(), SettingError> {
        let invalid = |message: String| SettingError::Value {
            name: name.to_string(),
            message,
        };
        match name {
            "objective" => self.objective = value.parse().map_err(|e| invalid(format!("{e}")))?,
            "refine" => {
                self.analysis.refine = match value {
                    "true" | "on" => true,
                    "false" | "off" => false,
                    _ => return Err(invalid(format!("`{value}`: give true or false"))),
                }
            }
            "uncertainty" => {
                self.analysis.uncertainty = value.parse().map_err(|e| invalid(format!("{e}")))?
            }
            "resamples" => self.analysis.resamples = parse_resamples(value).map_err(invalid)?,
            "seed" => self.analysis.seed = parse_seed(value).map_err(invalid)?,
            "folds" => self.analysis.folds = parse_folds(value).map_err(invalid)?,
            "path" => self.path = value.parse().map_err(|e| invalid(format!("{e}")))?,
            "precision" => self.precision = value.parse().map_err(|e| invalid(format!("{e}")))?,
            "noise" => {
                self.noise =
                    Noise::named(value, self.noise_floor).map_err(|e| invalid(format!("{e}")))?
            }
            "noise_floor" => {
                let floor: f64 = value
                    .parse()
                    .map_err(|_| invalid(format!("`{value}`: give a number")))?;
                let noise = Noise::Relative { floor }
                    .validate()
                    .map_err(|e| invalid(format!("{e}")))?;
                self.noise_floor = floor;
                if let Noise::Relative { .. } = self.noise {
                    self.noise = noise;
                }
            }
            "threads" => {
                let t = value
                    .parse()
                    .map_err(|_| invalid(format!("`{value}`: give a whole number")))?;
                self.threads = Some(t);
            }
            _ => {
                let p = Self::axis_param(name).map_err(|_| {
                    let axes = param_names(&Grid::PARAMS);
                    SettingError::Unknown(UnknownName {
                        what: "setting",
                        given: name.to_string(),
                        expected: format!("an axis ({axes}) or {}", choices(&NAMES)),
                    })
                })?;
                let axis = Axis::parse(value).map_err(|e| invalid(e.to_string()))?;
                self.set_axis(p, axis);
            }
        }
        Ok(())
    }

    /// The grid parameter named `name` ([`Grid::PARAMS`]).
    ///
    /// # Errors
    /// [`SettingError::Unknown`] listing the axes.
    pub fn axis_param(name: &str) -> Result<Param, SettingError> {
        Param::from_name(name)
            .filter(|p| Grid::PARAMS.contains(p))
            .ok_or_else(|| {
                SettingError::Unknown(UnknownName {
                    what: "axis",
                    given: name.to_string(),
                    expected: param_names(&Grid::PARAMS),
                })
            })
    }

    /// Sets the axis of grid parameter `p` (replacing one set before).
    pub fn set_axis(&mut self, p: Param, axis: Axis) {
        self.axes.retain(|(q, _)| *q != p);
        self.axes.push((p, axis));
    }

    /// The objective's default grid with the axes set replaced, validated.
    ///
    /// # Errors
    /// [`GridError`] naming the axis and value outside the model's domain,
    /// or a grid too large.
    pub fn grid(&self) -> Result<Grid, GridError> {
        let mut grid = self.objective.default_grid();
        for (p, axis) in &self.axes {
            if let Some(slot) = grid.axis_mut(*p) {
                *slot = axis.clone();
            }
        }
        grid.validate()?;
        Ok(grid)
    }

    /// The fitter of these settings.
    ///
    /// # Errors
    /// [`FitError::Grid`] as [`Settings::grid`]; [`FitError::Threads`] for a
    /// thread count the machine cannot start.
    pub fn fitter(&self) -> Result<Fitter, FitError> {
        if self.objective == Objective::Paper && self.analysis.uncertainty == Uncertainty::Bootstrap
        {
            return Err(FitError::UncertaintyOfObjective {
                uncertainty: "bootstrap",
                objective: "paper",
                hint: "the paper objective's intervals are the profile's and the Jacobian's \
                       (uncertainty both); the bootstrap needs the free objective",
            });
        }
        if self.objective == Objective::Paper && self.noise != Noise::Given {
            return Err(FitError::NoiseOfObjective {
                noise: self.noise.name(),
            });
        }
        let fitter = Fitter::new(self.grid()?)?
            .noise(self.noise)?
            .objective(self.objective)
            .path(self.path)
            .grid_precision(self.precision)
            .analysis(self.analysis);
        match self.threads {
            Some(t) => fitter.threads(t),
            None => Ok(fitter),
        }
    }
}
