//! Search grids (docs/conventions.md §6): the paper preset and
//! `start:stop:count` axes, validated against the model's domain and a size
//! limit before anything is allocated.

use crate::error::GridError;
use laminar_brdf_core::small_fit::{stepped, Axes, AxisError, PAPER};
use laminar_brdf_core::Param;
use std::fmt;

/// Most values one axis may hold. [`Axis::parse`] refuses longer axes before
/// allocating them.
pub const MAX_AXIS_LEN: usize = 1_000_000;

/// Most parameter sets a grid may hold (1.8 thousand times the paper grid;
/// a search over it takes hours, not a lifetime).
pub const MAX_GRID_SIZE: u128 = 10_000_000_000;

/// One grid axis: `count` evenly spaced values from `start` to `stop`.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// The values, in search order.
    pub values: Vec<f64>,
}

impl Axis {
    /// `count` values `start + i (stop − start)/(count − 1)`, `i = 0..count`
    /// (a single value when `count = 1`). When `stop − start` overflows,
    /// the values are `start (1 − t) + stop t`, `t = i/(count − 1)`, so they
    /// stay finite.
    pub fn linspace(start: f64, stop: f64, count: usize) -> Self {
        let span = stop - start;
        let at = |i: usize| {
            let t = i as f64 / (count - 1) as f64;
            if span.is_finite() {
                start + span * i as f64 / (count - 1) as f64
            } else {
                start * (1.0 - t) + stop * t
            }
        };
        let values = if count <= 1 {
            vec![start]
        } else {
            (0..count).map(at).collect()
        };
        Self { values }
    }

    /// `count` values spaced evenly in the logarithm from `start` to `stop`
    /// (both positive), the ends exact.
    ///
    /// ```
    /// use laminar_brdf_fit::Axis;
    /// let a = Axis::logspace(0.02, 20.0, 4);
    /// assert_eq!(a.values[0], 0.02);
    /// assert_eq!(a.values[3], 20.0);
    /// assert!((a.values[1] - 0.2).abs() < 1e-12);
    /// ```
    pub fn logspace(start: f64, stop: f64, count: usize) -> Self {
        if count <= 1 {
            return Self {
                values: vec![start],
            };
        }
        let (l0, l1) = (libm::log(start), libm::log(stop));
        let values = (0..count)
            .map(|i| match i {
                0 => start,
                i if i + 1 == count => stop,
                i => libm::exp(l0 + (l1 - l0) * i as f64 / (count - 1) as f64),
            })
            .collect();
        Self { values }
    }

    /// The smallest and largest value: the range the axis searches.
    pub fn range(&self) -> (f64, f64) {
        self.values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            })
    }

    /// `start + step·i` for `i = 0..count`, the paper's construction.
    pub fn stepped(start: f64, step: f64, count: usize) -> Self {
        Self {
            values: (0..count).map(|i| stepped(start, step, i)).collect(),
        }
    }

    /// Parses `start:stop:count`, `start:stop:count:log` (log-spaced, both
    /// ends positive) or a single value. A count above
    /// [`MAX_AXIS_LEN`] is refused before anything is allocated.
    ///
    /// ```
    /// use laminar_brdf_fit::Axis;
    /// assert_eq!(Axis::parse("1.3:1.5:11").unwrap().len(), 11);
    /// assert_eq!(Axis::parse("0.5").unwrap().values, vec![0.5]);
    /// assert!(Axis::parse("0.12:4.04:100000000000").is_err());
    /// ```
    ///
    /// # Errors
    /// [`GridError`] naming the malformed field, or the count when it exceeds [`MAX_AXIS_LEN`].
    pub fn parse(text: &str) -> Result<Self, GridError> {
        let parts: Vec<&str> = text.split(':').collect();
        let num = |s: &str| {
            s.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| GridError::NotANumber {
                    text: text.to_string(),
                    field: s.to_string(),
                })
        };
        let log = parts.len() == 4 && parts[3].trim() == "log";
        let parts = if log { &parts[..3] } else { &parts[..] };
        match parts {
            [v] => Ok(Self {
                values: vec![num(v)?],
            }),
            [a, b, c] => {
                let count: u128 = c.trim().parse().ok().filter(|&n| n >= 1).ok_or_else(|| {
                    GridError::BadCount {
                        text: text.to_string(),
                        field: c.to_string(),
                    }
                })?;
                if count > MAX_AXIS_LEN as u128 {
                    return Err(GridError::AxisTooLong {
                        text: text.to_string(),
                        count,
                        limit: MAX_AXIS_LEN,
                    });
                }
                let (start, stop) = (num(a)?, num(b)?);
                if log {
                    if !(start > 0.0 && stop > 0.0) {
                        return Err(GridError::LogNotPositive {
                            text: text.to_string(),
                        });
                    }
                    return Ok(Self::logspace(start, stop, count as usize));
                }
                Ok(Self::linspace(start, stop, count as usize))
            }
            _ => Err(GridError::Syntax {
                text: text.to_string(),
            }),
        }
    }

    /// Number of values.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// True when the axis has no value.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }
}

/// The four-axis grid of the absorptive model.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// σ/T (slowest axis).
    pub slope: Axis,
    /// Refractive index n.
    pub n: Axis,
    /// Absorption a.
    pub a: Axis,
    /// Balance β (fastest axis).
    pub beta: Axis,
}

impl Grid {
    /// The paper preset (docs/conventions.md §6): σ/T = 0.12 + 0.08 i (50), β = 0.01 j
    /// (j = 1..100), n = 1.30 + 0.02 m (11), a = 0.01 l (101): 5,555,000 sets.
    pub fn paper() -> Self {
        let [slope, n, a, beta] =
            PAPER.map(|(start, step, count)| Axis::stepped(start, step, count));
        Self { slope, n, a, beta }
    }

    /// The default box for a user's own data under the free-amplitude
    /// objective (docs/conventions.md §4b): σ/T log-spaced over [0.02, 20]
    /// (40 values, a factor 1.19 apart), n over [1, 2.5] (11), a over
    /// [0, 1] (21), β over [0, 1] (β is solved in closed form: its axis
    /// gives only the range). The grid only has to place a start in the
    /// optimum's basin: refinement is continuous.
    pub fn user() -> Self {
        Self {
            slope: Axis::logspace(0.02, 20.0, 40),
            n: Axis::linspace(1.0, 2.5, 11),
            a: Axis::linspace(0.0, 1.0, 21),
            beta: Axis::linspace(0.0, 1.0, 101),
        }
    }

    /// The parameters the grid has an axis of, in the order front ends
    /// list them.
    pub const PARAMS: [Param; 4] = [Param::Slope, Param::Beta, Param::N, Param::A];

    /// The axis of parameter `p` (`None` for a baseline's parameter).
    pub fn axis(&self, p: Param) -> Option<&Axis> {
        match p {
            // The untied models search σ′/T′ over σ/T's axis.
            Param::Slope | Param::SubSlope => Some(&self.slope),
            Param::Beta => Some(&self.beta),
            Param::N => Some(&self.n),
            Param::A => Some(&self.a),
            _ => None,
        }
    }

    /// The axis of parameter `p` to change (`None` for a baseline's parameter).
    pub fn axis_mut(&mut self, p: Param) -> Option<&mut Axis> {
        match p {
            Param::Slope => Some(&mut self.slope),
            Param::Beta => Some(&mut self.beta),
            Param::N => Some(&mut self.n),
            Param::A => Some(&mut self.a),
            _ => None,
        }
    }

    /// The grid's axes as the core's search sees them.
    pub fn axes(&self) -> Axes<'_> {
        Axes {
            slope: &self.slope.values,
            n: &self.n.values,
            a: &self.a.values,
            beta: &self.beta.values,
        }
    }

    /// The same grid with a = 0 only (Ragheb–Hancock).
    pub fn ragheb_hancock(&self) -> Self {
        Self {
            a: Axis { values: vec![0.0] },
            ..self.clone()
        }
    }

    /// Number of parameter sets.
    pub fn size(&self) -> usize {
        self.slope.len() * self.n.len() * self.a.len() * self.beta.len()
    }

    /// Flattened index in loop order σ/T, n, a, β (docs/conventions.md §6 tie-break).
    pub fn flat(&self, s: usize, n: usize, a: usize, b: usize) -> usize {
        self.axes().flat(s, n, a, b)
    }

    /// The axis indices (σ/T, n, a, β) of a flattened index ([`Grid::flat`]).
    pub fn indices(&self, flat: usize) -> (usize, usize, usize, usize) {
        self.axes().indices(flat)
    }

    /// Checks every value against the model's domain ([`laminar_brdf_core::Params::new`]; the
    /// domain is a box, so each axis is checked on its own) and the size
    /// against [`MAX_GRID_SIZE`].
    ///
    /// ```
    /// use laminar_brdf_fit::{Axis, Grid};
    /// let mut g = Grid::paper();
    /// g.a = Axis::parse("-0.1").unwrap();
    /// assert_eq!(g.validate().unwrap_err().to_string(), "axis a: a = -0.1 is outside [0, 1]");
    /// ```
    ///
    /// # Errors
    /// [`GridError::Empty`], [`GridError::OutOfDomain`] naming the axis and value,
    /// or [`GridError::TooLarge`] with the size.
    pub fn validate(&self) -> Result<(), GridError> {
        self.axes().validate().map_err(|e| match e {
            AxisError::Empty { axis } => GridError::Empty { axis },
            AxisError::OutOfDomain { axis, error } => GridError::OutOfDomain { axis, error },
        })?;
        let size = [&self.slope, &self.n, &self.a, &self.beta]
            .iter()
            .map(|a| a.len() as u128)
            .product::<u128>();
        if size > MAX_GRID_SIZE {
            return Err(GridError::TooLarge {
                size,
                shape: format!(
                    "{}×{}×{}×{}",
                    self.slope.len(),
                    self.n.len(),
                    self.a.len(),
                    self.beta.len()
                ),
                limit: MAX_GRID_SIZE,
            });
        }
        Ok(())
    }
}

impl fmt::Display for Grid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "slope×n×a×beta = {}×{}×{}×{} = {} parameter sets",
            self.slope.len(),
            self.n.len(),
            self.a.len(),
            self.beta.len(),
            self.size()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_grid_matches_conventions() {
        let g = Grid::paper();
        assert_eq!(g.size(), 5_555_000);
        assert!((g.slope.values[49] - 4.04).abs() < 1e-12);
        assert!((g.n.values[10] - 1.5).abs() < 1e-12);
        assert_eq!(g.a.values[0], 0.0);
        assert!((g.beta.values[99] - 1.0).abs() < 1e-12);
        assert!(g.validate().is_ok());
    }

    #[test]
    fn parse_axes() {
        assert_eq!(Axis::parse("0.12:4.04:50").unwrap().len(), 50);
        assert_eq!(Axis::parse("1.5").unwrap().values, vec![1.5]);
        assert!(Axis::parse("1:2").is_err());
        assert!(Axis::parse("1:2:x").is_err());
        assert!(Axis::parse("1:nan:3").is_err());
        // A span that overflows still gives finite values, ends exact.
        let wide = Axis::parse("-1e308:1e308:3").unwrap();
        assert_eq!(wide.values, vec![-1e308, 0.0, 1e308]);
        assert!(matches!(
            Axis::parse("0.12:4.04:100000000000"),
            Err(GridError::AxisTooLong {
                count: 100_000_000_000,
                ..
            })
        ));
    }

    #[test]
    fn oversized_grids_are_refused_with_their_size() {
        let g = Grid {
            slope: Axis::linspace(0.12, 4.04, 1_000_000),
            n: Axis::linspace(1.0, 2.0, 1000),
            ..Grid::paper()
        };
        let e = g.validate().unwrap_err();
        assert!(
            matches!(
                e,
                GridError::TooLarge {
                    size: 10_100_000_000_000,
                    ..
                }
            ),
            "{e}"
        );
        assert!(e.to_string().contains("1000000×1000×101×100"), "{e}");
    }
}
