//! Reading a fit's error surface (docs/conventions.md §11): confidence
//! intervals from the profile of each parameter, and the basins the grid
//! shows near its minimum.
//!
//! A parameter's profile is the smallest objective `Σ (D − P)²` over the
//! other parameters at each of its values. With noise variance `s²`, the
//! values where the profile is at most `min + Δ s²` form the interval of
//! confidence level 68.27% for `Δ = 1` and 95% for `Δ = 3.841` (one
//! parameter of interest; Wilks). The grid gives the profile at its axis
//! values; the refined minimum is added as one more point, and each end is
//! placed by interpolating `sqrt(profile − min)` linearly between the last
//! point inside and the first outside (exact where the profile is a
//! parabola, as it is near a smooth minimum).

use std::collections::HashMap;

/// `Δχ²` of a 68.27% interval for one parameter.
pub const DELTA_68: f64 = 1.0;
/// `Δχ²` of a 95% interval for one parameter (the 0.95 quantile of χ²₁).
pub const DELTA_95: f64 = 3.841_458_820_694_124;
/// The normal quantile of a two-sided 95% interval (Jacobian intervals are
/// `θ ± Z_95 sd`).
pub const Z_95: f64 = 1.959_963_984_540_054;

/// A confidence interval of one parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    /// Lower end.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
    /// The profile had not risen to the level at the lowest value searched,
    /// which is not a bound of the domain: the true end may lie below `lo`.
    pub open_below: bool,
    /// As `open_below`, at the highest value searched.
    pub open_above: bool,
}

/// One parameter's profile: `(value, objective)` at each searched value,
/// the objective +∞ where it exceeded the `cutoff` it was computed to.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    /// `(value, objective)` pairs (any order).
    pub points: Vec<(f64, f64)>,
    /// Objectives above this were not computed exactly.
    pub cutoff: f64,
}

impl Profile {
    /// The interval where the profile is at most `min + delta·s2`, `min`
    /// being the refined objective `sse` at `centre` (added as a point), in
    /// the domain `domain`. An end whose first point outside is only known
    /// to exceed the cutoff is placed as if it were at the cutoff: further
    /// out than the truth, so the interval errs on the wide side.
    pub fn interval(
        &self,
        (centre, sse): (f64, f64),
        delta: f64,
        s2: f64,
        (lowest, highest): (f64, f64),
    ) -> Interval {
        let mut points = self.points.clone();
        points.push((centre, sse));
        points.sort_by(|p, q| p.0.total_cmp(&q.0));
        let height = |e: f64| (e.min(self.cutoff) - sse).max(0.0).sqrt();
        let target = (delta * s2).sqrt();
        let inside: Vec<usize> = (0..points.len())
            .filter(|&i| height(points[i].1) <= target && points[i].1 <= self.cutoff)
            .collect();
        // The refined point is always inside (height 0).
        let (first, last) = (inside[0], inside[inside.len() - 1]);
        let end = |i_in: usize, i_out: usize| {
            let (v0, h0) = (points[i_in].0, height(points[i_in].1));
            let (v1, h1) = (points[i_out].0, height(points[i_out].1));
            if h1 > h0 {
                v0 + (target - h0) / (h1 - h0) * (v1 - v0)
            } else {
                v1
            }
        };
        let lo = if first > 0 {
            end(first, first - 1)
        } else {
            points[0].0
        };
        let hi = if last + 1 < points.len() {
            end(last, last + 1)
        } else {
            points[last].0
        };
        Interval {
            lo,
            hi,
            open_below: first == 0 && points[0].0 > lowest,
            open_above: last + 1 == points.len() && points[last].0 < highest,
        }
    }
}

/// The basins of a grid whose points near the minimum are `near` (flat
/// index in row-major order over axes of lengths `lens`, objective): the
/// points no axis neighbour of which is lower (ties: the smaller flat index
/// is lower), best first, at most `most`. A neighbour not in `near` is
/// higher than every point in it.
pub fn basins(near: &[(usize, f64)], lens: &[usize], most: usize) -> Vec<(usize, f64)> {
    let values: HashMap<usize, f64> = near.iter().copied().collect();
    let strides: Vec<usize> = (0..lens.len())
        .map(|i| lens[i + 1..].iter().product())
        .collect();
    let lower = |&(f, e): &(usize, f64), g: usize| {
        values.get(&g).is_some_and(|&h| h < e || (h == e && g < f))
    };
    let mut minima: Vec<(usize, f64)> = near
        .iter()
        .filter(|p| {
            lens.iter().zip(&strides).all(|(&len, &stride)| {
                let i = (p.0 / stride) % len;
                let below = i > 0 && lower(p, p.0 - stride);
                let above = i + 1 < len && lower(p, p.0 + stride);
                !(below || above)
            })
        })
        .copied()
        .collect();
    minima.sort_by(|p, q| p.1.total_cmp(&q.1).then(p.0.cmp(&q.0)));
    minima.truncate(most);
    minima
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_parabola_gives_its_exact_interval() {
        // Objective 2 + 50 (x − 0.33)² sampled on a grid of step 0.1: the
        // 68% interval for s² = 0.5 is 0.33 ± 0.1.
        let f = |x: f64| 2.0 + 50.0 * (x - 0.33) * (x - 0.33);
        let points = (0..=10)
            .map(|i| (0.1 * i as f64, f(0.1 * i as f64)))
            .collect();
        let p = Profile {
            points,
            cutoff: f64::INFINITY,
        };
        let i = p.interval((0.33, 2.0), DELTA_68, 0.5, (0.0, 1.0));
        assert!(
            (i.lo - 0.23).abs() < 1e-12 && (i.hi - 0.43).abs() < 1e-12,
            "{i:?}"
        );
        assert!(!i.open_below && !i.open_above);
        // Noise → 0: the interval shrinks onto the refined value.
        let i = p.interval((0.33, 2.0), DELTA_68, 1e-12, (0.0, 1.0));
        assert!(i.hi - i.lo < 1e-6);
    }

    #[test]
    fn open_sides_and_unknown_points_are_reported() {
        // Flat towards 0 (the range starts at 0.2, the domain at 0): open below.
        let points = vec![(0.2, 1.0), (0.3, 1.0), (0.4, 1.5), (0.5, f64::INFINITY)];
        let p = Profile {
            points,
            cutoff: 3.0,
        };
        let i = p.interval((0.25, 1.0), DELTA_95, 0.25, (0.0, 1.0));
        assert!(i.open_below && !i.open_above);
        assert_eq!(i.lo, 0.2);
        // Level 1 + 0.96: between 0.4 (1.5) and 0.5 (taken as the cutoff 3).
        let (h0, h1, t) = (0.5f64.sqrt(), 2f64.sqrt(), (DELTA_95 * 0.25).sqrt());
        assert!((i.hi - (0.4 + (t - h0) / (h1 - h0) * 0.1)).abs() < 1e-12);
        // At a domain bound the interval is closed, not open.
        let i = p.interval((0.25, 1.0), DELTA_95, 0.25, (0.2, 1.0));
        assert!(!i.open_below);
    }

    #[test]
    fn basins_are_local_minima() {
        // 1-D: values 3 1 2 0.5 4 → minima at 1 and 3, best first.
        let near = vec![(0, 3.0), (1, 1.0), (2, 2.0), (3, 0.5), (4, 4.0)];
        assert_eq!(basins(&near, &[5], 4), vec![(3, 0.5), (1, 1.0)]);
        assert_eq!(basins(&near, &[5], 1), vec![(3, 0.5)]);
        // 2-D 2 × 3, a plateau: the smaller index wins.
        let near = vec![(0, 1.0), (1, 1.0), (5, 0.9)];
        assert_eq!(basins(&near, &[2, 3], 4), vec![(5, 0.9), (0, 1.0)]);
    }
}
