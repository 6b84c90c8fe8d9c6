//! Search grids (conventions §6): the paper preset and `start:stop:count` axes.

use std::fmt;

/// One grid axis: `count` evenly spaced values from `start` to `stop`.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// The values, in search order.
    pub values: Vec<f64>,
}

impl Axis {
    /// `count` values `start + i (stop − start)/(count − 1)`, `i = 0..count`
    /// (a single value when `count = 1`).
    pub fn linspace(start: f64, stop: f64, count: usize) -> Self {
        let values = if count <= 1 {
            vec![start]
        } else {
            (0..count)
                .map(|i| start + (stop - start) * i as f64 / (count - 1) as f64)
                .collect()
        };
        Self { values }
    }

    /// `start + step·i` for `i = 0..count`, the paper's construction.
    pub fn stepped(start: f64, step: f64, count: usize) -> Self {
        Self {
            values: (0..count).map(|i| start + step * i as f64).collect(),
        }
    }

    /// Parses `start:stop:count` or a single value.
    pub fn parse(text: &str) -> Result<Self, String> {
        let parts: Vec<&str> = text.split(':').collect();
        let num = |s: &str| {
            s.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("`{s}` in axis `{text}` is not a finite number"))
        };
        match parts.as_slice() {
            [v] => Ok(Self {
                values: vec![num(v)?],
            }),
            [a, b, c] => {
                let count: usize = c.trim().parse().ok().filter(|&n| n >= 1).ok_or_else(|| {
                    format!("count `{c}` in axis `{text}` is not a positive integer")
                })?;
                Ok(Self::linspace(num(a)?, num(b)?, count))
            }
            _ => Err(format!(
                "axis `{text}` is not `start:stop:count` or a single value"
            )),
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
    /// The paper preset (conventions §6): σ/T = 0.12 + 0.08 i (50), β = 0.01 j
    /// (j = 1..100), n = 1.30 + 0.02 m (11), a = 0.01 l (101): 5,555,000 sets.
    pub fn paper() -> Self {
        Self {
            slope: Axis::stepped(0.12, 0.08, 50),
            n: Axis::stepped(1.30, 0.02, 11),
            a: Axis::stepped(0.0, 0.01, 101),
            beta: Axis::stepped(0.01, 0.01, 100),
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

    /// Flattened index in loop order σ/T, n, a, β (conventions §6 tie-break).
    pub fn flat(&self, s: usize, n: usize, a: usize, b: usize) -> usize {
        ((s * self.n.len() + n) * self.a.len() + a) * self.beta.len() + b
    }

    /// Checks every value against the model's domain
    /// ([`laminar_core::Params::new`]).
    pub fn validate(&self) -> Result<(), String> {
        for (name, axis) in [
            ("slope", &self.slope),
            ("n", &self.n),
            ("a", &self.a),
            ("beta", &self.beta),
        ] {
            if axis.is_empty() {
                return Err(format!("axis {name} is empty"));
            }
        }
        for &s in &self.slope.values {
            for &n in &self.n.values {
                for &a in &self.a.values {
                    for &b in &self.beta.values {
                        laminar_core::Params::new(s, b, n, a)
                            .map_err(|e| format!("grid value: {e}"))?;
                    }
                }
            }
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
    }
}
