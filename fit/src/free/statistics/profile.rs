//! Profile intervals of a free fit, found MINOS-style (docs/conventions.md
//! §11b): each end located by minimising every other parameter with this
//! one held fixed, walking out from the estimate on the profile of
//! `sqrt(profile − min)` until it reaches each level.

use super::covariance::JacobianCovariance;
use super::levels::Levels;
use crate::free::coordinate::Coordinate;
use crate::free::model::FreeModel;
use crate::free::problem::{Point, Problem};
use crate::free::refine::minimise;

/// What the walk along a profile found.
#[derive(Debug, Clone, PartialEq)]
pub enum Walk {
    /// The two ends (68.27%, 95%) on this side, and whether each stopped at
    /// the face of the box with the profile still below its level.
    Ends([(f64, bool); 2]),
    /// A point below the minimum (MINOS's "new minimum"): the refinement
    /// missed it, and starts again from there.
    NewMinimum(Point),
}

/// One side of one parameter's profile.
pub struct Side<'a, M> {
    /// The objective.
    pub problem: &'a Problem<M>,
    /// The minimum.
    pub minimum: &'a Point,
    /// The parameter.
    pub coordinate: Coordinate,
    /// Its index among the covariance's parameters.
    pub index: usize,
    /// The covariance at the minimum, when there is one.
    pub covariance: Option<&'a JacobianCovariance>,
    /// The coordinates of every reported parameter (covariance order).
    pub coordinates: &'a [Coordinate],
    /// −1 below the estimate, +1 above.
    pub direction: f64,
    /// The levels.
    pub levels: Levels,
    /// The walk's settings.
    pub settings: WalkSettings,
}

/// The profile walk's settings: how precisely each minimisation and each
/// end is found, and how many probes an end may take (the defaults are
/// the constants below, whose documents say why).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkSettings {
    /// [`PROFILE_TOLERANCE`].
    profile_tolerance: f64,
    /// [`MOST_STEPS`].
    most_steps: usize,
    /// [`END_TOLERANCE`].
    end_tolerance: f64,
    /// [`BRACKET_TOLERANCE`].
    bracket_tolerance: f64,
}

impl Default for WalkSettings {
    fn default() -> Self {
        Self {
            profile_tolerance: PROFILE_TOLERANCE,
            most_steps: MOST_STEPS,
            end_tolerance: END_TOLERANCE,
            bracket_tolerance: BRACKET_TOLERANCE,
        }
    }
}

/// The minimisations of a profile stop when a step gains less than this
/// fraction of the 68.27% level's height `Δ s²`: `sqrt(profile − min)` is
/// then known to about half of it, fifty times inside [`END_TOLERANCE`].
pub const PROFILE_TOLERANCE: f64 = 1e-3;

/// Most profile evaluations per end.
pub const MOST_STEPS: usize = 12;

/// A probe ends the search for a level when `sqrt(profile − min)` is within
/// this fraction of its target; the end is then one Newton step from the
/// probe (on the local slope of `sqrt(profile − min)`), whose error is of
/// the order of the square of this fraction when the step's slope is right
/// (with the probe's own error from [`PROFILE_TOLERANCE`]). Measured
/// against bisection of the profile: median 2·10⁻⁴ of the end's distance,
/// 99% within 1.3·10⁻², with known faults up to 0.12 (docs/conventions.md
/// §11b).
pub const END_TOLERANCE: f64 = 5e-2;

/// A walk ends when its bracket of the crossing is narrower than this
/// fraction of the crossing's distance, even with no probe within
/// [`END_TOLERANCE`] of the level: where the profile jumps across the level
/// (its minimum moves to another valley), no probe comes near it.
pub const BRACKET_TOLERANCE: f64 = 1e-2;

/// One probe of a walk: the distance from the estimate, `sqrt(profile − min)`
/// there, and the profile's minimising parameters.
#[derive(Debug, Clone)]
struct Probe {
    distance: f64,
    height: f64,
    theta: Vec<f64>,
    /// Minimised again from the profile's path below it (a jump's far side).
    rechecked: bool,
}

impl<M: FreeModel> Side<'_, M> {
    /// `value` in the internal coordinate of the held parameter.
    fn internal(&self, value: f64) -> f64 {
        match self.coordinate {
            Coordinate::Nonlinear { log: true, .. } => libm::log(value),
            _ => value,
        }
    }

    /// Where the profile's minimisation at `value` (at `distance` from the
    /// estimate) starts. After the first probe: on the profile's own path,
    /// interpolated (or extrapolated) between the two probes nearest in
    /// distance. Before it: on the Jacobian's linearised path.
    fn start(&self, value: f64, distance: f64, probes: &[Probe]) -> Vec<f64> {
        let problem = self.problem;
        let mut start = self.minimum.theta.clone();
        if probes.len() >= 2 {
            let mut nearest: Vec<&Probe> = probes.iter().collect();
            nearest.sort_by(|p, q| {
                (p.distance - distance)
                    .abs()
                    .total_cmp(&(q.distance - distance).abs())
            });
            let (p, q) = (nearest[0], nearest[1]);
            if p.distance != q.distance {
                let t = (distance - p.distance) / (q.distance - p.distance);
                for (x, (a, b)) in start.iter_mut().zip(p.theta.iter().zip(&q.theta)) {
                    *x = a + t * (b - a);
                }
            }
        } else if let Some(cov) = self.covariance {
            let estimate = self.coordinate.value(self.minimum, problem);
            if let Some(vv) = cov.matrix[self.index][self.index] {
                for (i, c) in self.coordinates.iter().enumerate() {
                    if let (Coordinate::Nonlinear { j, log }, Some(cv)) =
                        (c, cov.matrix[i][self.index])
                    {
                        let shift = cv / vv * (value - estimate);
                        let here = self.coordinates[i].value(self.minimum, problem);
                        let moved = here + shift;
                        start[*j] = if *log {
                            libm::log(moved.max(1e-300))
                        } else {
                            moved
                        };
                    }
                }
            }
        }
        if let Coordinate::Nonlinear { j, .. } = self.coordinate {
            start[j] = self.internal(value);
        }
        start
    }

    /// The profile at `value`: the minimum over every other parameter with
    /// this one held at `value`, from `start`; when that lands more than
    /// twice `target` (in `sqrt(profile − min)`) above the minimum, also
    /// from the minimum's own values (the path can start in another
    /// valley), keeping the lower.
    fn profile(&self, value: f64, target: f64, start: &[f64]) -> Point {
        let problem = self.problem;
        let mut free = problem.all_free();
        let beta = match self.coordinate {
            Coordinate::Nonlinear { j, .. } => {
                free[j] = false;
                problem.beta
            }
            Coordinate::Beta => (value, value),
        };
        // `minimise` takes its tolerance as a fraction of the objective.
        let tolerance =
            self.settings.profile_tolerance * self.levels.heights[0] / self.minimum.sse.max(1e-300);
        let from_start = minimise(problem, start, &free, beta, tolerance).point;
        if from_start.sse - self.minimum.sse <= 4.0 * target * target {
            return from_start;
        }
        let mut plain = self.minimum.theta.clone();
        if let Coordinate::Nonlinear { j, .. } = self.coordinate {
            plain[j] = self.internal(value);
        }
        if plain == start {
            return from_start;
        }
        let from_minimum = minimise(problem, &plain, &free, beta, tolerance).point;
        if from_minimum.sse < from_start.sse {
            from_minimum
        } else {
            from_start
        }
    }

    /// Walks out to both levels' ends on this side.
    pub fn walk(&self) -> Walk {
        let frame = Frame::new(self);
        let mut probes = vec![Probe {
            distance: 0.0,
            height: 0.0,
            theta: self.minimum.theta.clone(),
            rechecked: false,
        }];
        let mut ends = [(frame.face, true); 2];
        for (level, &height) in self.levels.heights.iter().enumerate() {
            let target = height.sqrt();
            if frame.room == 0.0 || (level == 1 && ends[0].1) {
                // No room, or the face is inside the 68.27% level already.
                continue;
            }
            let first = match (level, frame.sd) {
                (1, _) => next_distance(&probes, 0, target, frame.alpha),
                (_, Some(sd)) if sd > 0.0 => sd * (height / self.levels.s2).sqrt(),
                _ => 0.1 * frame.room,
            }
            .min(frame.room);
            match self.level_end(&frame, &mut probes, target, first) {
                Ok(end) => ends[level] = end,
                Err(lower) => return Walk::NewMinimum(lower),
            }
        }
        Walk::Ends(ends)
    }

    /// The end on this side of the level whose `sqrt(profile − min)` is
    /// `target`, probing first at distance `first` (`probes` holds the
    /// walk's probes so far, and gets this level's); or a point below the
    /// minimum. Runs [`LevelSearch::next_iter`] for at most the settings'
    /// steps.
    fn level_end(
        &self,
        frame: &Frame,
        probes: &mut Vec<Probe>,
        target: f64,
        first: f64,
    ) -> Result<(f64, bool), Point> {
        let mut search = LevelSearch {
            side: self,
            frame,
            target,
            before: probes.len(),
            next: first,
        };
        let most_steps = self.settings.most_steps;
        for step in 0..most_steps {
            if let Step::End(end) = search.next_iter(probes, step + 1 == most_steps)? {
                return Ok(end);
            }
        }
        Ok(search.interpolated(probes))
    }

    /// The profile at `value` from `start`, and `sqrt(profile − min)` there
    /// with the profile's minimising parameters; or a point below the
    /// minimum.
    fn measure(&self, value: f64, target: f64, start: &[f64]) -> Result<(f64, Vec<f64>), Point> {
        let sse_min = self.minimum.sse;
        let point = self.profile(value, target, start);
        if point.sse < sse_min * (1.0 - 1e-9) - 1e-300 {
            return Err(point);
        }
        Ok(((point.sse - sse_min).max(0.0).sqrt(), point.theta))
    }

    /// The end from the last probe, within the end tolerance of `target`
    /// at height `h` (held value `value`): one Newton step on the local
    /// slope of `sqrt(profile − min)`.
    fn end_near(
        &self,
        frame: &Frame,
        probes: &[Probe],
        (target, h): (f64, f64),
        value: f64,
    ) -> (f64, bool) {
        let here = probes.last().expect("a probe was just taken");
        let slope = local_slope(probes, here, target, frame.alpha);
        let end = here.distance + (target - h) / slope;
        if end.is_nan() || end <= 0.0 {
            (value, false)
        } else if end >= frame.room {
            (frame.face, true)
        } else {
            (frame.estimate + self.direction * end, false)
        }
    }

    /// Minimises the far side of the bracket of `target` again from its
    /// near side's parameters, keeping the lower; true when the far side is
    /// then below the level (the walk goes on).
    fn recheck(&self, frame: &Frame, probes: &mut [Probe], target: f64) -> Result<bool, Point> {
        let (near, above) = bracket(probes, target);
        let above = above.expect("a bracket");
        let (distance, mut start) = (above.distance, near.theta.clone());
        let value = frame.value_at(distance, self.direction);
        if let Coordinate::Nonlinear { j, .. } = self.coordinate {
            start[j] = self.internal(value);
        }
        let (h, theta) = self.measure(value, target, &start)?;
        let far = probes
            .iter_mut()
            .find(|p| p.distance == distance && p.height >= target)
            .expect("the bracket's far probe");
        far.rechecked = true;
        if h < far.height {
            (far.height, far.theta) = (h, theta);
        }
        Ok(h < target)
    }
}

/// The search for one level's end on one side, one probe per
/// [`LevelSearch::next_iter`] (argmin's stepper shape; [`Side::level_end`]
/// runs it).
struct LevelSearch<'w, 'a, M> {
    side: &'w Side<'a, M>,
    frame: &'w Frame,
    /// The level's `sqrt(profile − min)`.
    target: f64,
    /// The walk's probes before this level's.
    before: usize,
    /// The distance to probe next.
    next: f64,
}

/// What one probe of a level's search found.
enum Step {
    /// Not there yet: the next probe is chosen.
    Going,
    /// The end, and whether it is the face with the profile below the level.
    End((f64, bool)),
}

impl<M: FreeModel> LevelSearch<'_, '_, M> {
    /// Probes the profile once (at the face when `last` and every probe is
    /// still below the level, so that an end is put at the face only where
    /// the profile is seen below the level at the face itself), and ends
    /// the search there when the probe is within the end tolerance of the
    /// level, at the face below it, or on a bracket too narrow to hold a
    /// probe near the level (a jump); or a point below the minimum.
    fn next_iter(&mut self, probes: &mut Vec<Probe>, last: bool) -> Result<Step, Point> {
        let (side, frame, target) = (self.side, self.frame, self.target);
        if last && probes.iter().all(|p| p.height < target) {
            self.next = frame.room;
        }
        let value = frame.value_at(self.next, side.direction);
        let start = side.start(value, self.next, probes);
        let (h, theta) = side.measure(value, target, &start)?;
        probes.push(Probe {
            distance: self.next.min(frame.room),
            height: h,
            theta,
            rechecked: false,
        });
        if h < target && self.next >= frame.room {
            return Ok(Step::End((frame.face, true)));
        }
        if (h - target).abs() <= side.settings.end_tolerance * target {
            return Ok(Step::End(side.end_near(frame, probes, (target, h), value)));
        }
        self.next = self.next_distance(probes);
        let (near, above) = bracket(probes, target);
        let narrow = above.filter(|above| {
            above.distance - near.distance <= side.settings.bracket_tolerance * above.distance
        });
        if let Some(above) = narrow {
            // A bracket this narrow without a probe near the level: the
            // profile jumps across it (another valley takes over), and the
            // end is the jump; unless the far side's minimisation stopped
            // in another valley, which minimising there again from the
            // near side's parameters (the profile's path continued) shows.
            if !above.rechecked && side.recheck(frame, probes, target)? {
                self.next = self.next_distance(probes);
                return Ok(Step::Going);
            }
            return Ok(Step::End((
                frame.estimate + side.direction * self.next,
                false,
            )));
        }
        Ok(Step::Going)
    }

    /// [`next_distance`] over this level's probes, inside the box.
    fn next_distance(&self, probes: &[Probe]) -> f64 {
        let fresh = probes.len() - self.before;
        next_distance(probes, fresh, self.target, self.frame.alpha).min(self.frame.room)
    }

    /// The end after the last step (a probe above the level, the last
    /// step saw to that): the crossing interpolated in the bracket.
    fn interpolated(&self, probes: &[Probe]) -> (f64, bool) {
        let d = self.next_distance(probes);
        (self.frame.estimate + self.side.direction * d, false)
    }
}

/// The farthest probe below `target` (the origin at least), and the
/// nearest probe beyond it at or above `target`, when there is one: the
/// crossing of the level lies between them.
fn bracket(probes: &[Probe], target: f64) -> (&Probe, Option<&Probe>) {
    let near = probes
        .iter()
        .filter(|p| p.height < target)
        .max_by(|p, q| p.distance.total_cmp(&q.distance))
        .expect("the origin is below every level");
    let above = probes
        .iter()
        .filter(|p| p.height >= target && p.distance > near.distance)
        .min_by(|p, q| p.distance.total_cmp(&q.distance));
    (near, above)
}

/// The next distance to probe for `target`. With the Jacobian's slope
/// `alpha` of `sqrt(profile − min)` at the estimate (`√s² / sd`), the
/// model `h(d) = α d + γ d²` through the probe nearest the target, kept
/// inside the bracket when there is one. Otherwise inside a bracket,
/// linear interpolation between its ends (nearly exact, as `sqrt(profile
/// − min)` is nearly linear in the distance); beyond every probe, the
/// secant of the two farthest (the origin among them). Never more than
/// four times as far as the farthest probe below the target.
///
/// Inside a bracket, when the last two of this walk's `fresh` probes
/// fell on one side of the target, neither the model nor false position
/// is used (false position creeps towards the crossing from that side
/// when the far end sits where the profile is steep, at a face or
/// across a jump): the secant through those two probes when it lands
/// inside the bracket, else the bracket's midpoint, so that the bracket
/// at least halves.
fn next_distance(probes: &[Probe], fresh: usize, target: f64, alpha: Option<f64>) -> f64 {
    let mut below: Vec<&Probe> = probes.iter().filter(|p| p.height < target).collect();
    below.sort_by(|p, q| p.distance.total_cmp(&q.distance));
    let (near, above) = bracket(probes, target);
    let most = match above {
        Some(above) => above.distance,
        None => 4.0 * near.distance,
    };
    // How many of this walk's latest probes fell below (above) the target
    // in a row.
    let streak = |below_target: bool| {
        probes[probes.len() - fresh.min(probes.len())..]
            .iter()
            .rev()
            .take_while(|p| (p.height < target) == below_target)
            .count()
    };
    let stalled = above.is_some() && (streak(true) >= 2 || streak(false) >= 2);
    let quadratic = alpha.filter(|_| !stalled).and_then(|alpha| {
        let nearest = probes.iter().filter(|p| p.distance > 0.0).min_by(|p, q| {
            (p.height - target)
                .abs()
                .total_cmp(&(q.height - target).abs())
        })?;
        let (d, h) = (nearest.distance, nearest.height);
        let gamma = (h - alpha * d) / (d * d);
        let root = if gamma == 0.0 {
            target / alpha
        } else {
            let disc = alpha * alpha + 4.0 * gamma * target;
            (disc >= 0.0).then(|| 2.0 * target / (alpha + disc.sqrt()))?
        };
        (root > near.distance && root < most).then_some(root)
    });
    if let Some(root) = quadratic {
        return root;
    }
    match above {
        Some(above) if stalled => {
            // The secant through the streak's last two probes, when it
            // lands inside the bracket; else its midpoint.
            let n = probes.len();
            let (p, q) = (&probes[n - 2], &probes[n - 1]);
            let secant = q.distance
                + (target - q.height) * (q.distance - p.distance) / (q.height - p.height);
            let inside = secant > near.distance && secant < above.distance;
            if inside {
                secant
            } else {
                0.5 * (near.distance + above.distance)
            }
        }
        Some(above) if above.height > near.height => {
            let t = (target - near.height) / (above.height - near.height);
            near.distance + t * (above.distance - near.distance)
        }
        Some(above) => 0.5 * (near.distance + above.distance),
        None => {
            let far = near.distance;
            let slope = match below.len() {
                1 => 0.0,
                n => {
                    let before = below[n - 2];
                    (near.height - before.height) / (far - before.distance)
                }
            };
            if slope > 0.0 {
                (far + (target - near.height) / slope).min(most)
            } else {
                2.0 * far
            }
        }
    }
}

/// The slope of `sqrt(profile − min)` in the distance at the probe
/// `here` (near `target`): the secant with another probe near the
/// target when there is one; else the derivative of the model
/// `h(d) = α d + γ d²` through `here` with the Jacobian's slope `alpha`
/// at the estimate; else the secant from the estimate.
fn local_slope(probes: &[Probe], here: &Probe, target: f64, alpha: Option<f64>) -> f64 {
    let other = probes
        .iter()
        .filter(|p| p.distance > 0.0 && p.distance != here.distance)
        .filter(|p| (p.height - target).abs() <= 0.25 * target)
        .min_by(|p, q| {
            (p.distance - here.distance)
                .abs()
                .total_cmp(&(q.distance - here.distance).abs())
        });
    let secant = |p: &Probe| (here.height - p.height) / (here.distance - p.distance);
    match (other, alpha) {
        (Some(p), _) if secant(p) > 0.0 => secant(p),
        (_, Some(alpha)) => {
            let (d, h) = (here.distance, here.height);
            let gamma = (h - alpha * d) / (d * d);
            let slope = alpha + 2.0 * gamma * d;
            if slope > 0.0 {
                slope
            } else {
                h / d
            }
        }
        _ => here.height / here.distance,
    }
}

/// What a walk on one side knows before its first probe.
struct Frame {
    /// The estimate (reported units).
    estimate: f64,
    /// The face of the box on this side.
    face: f64,
    /// The distance to the face.
    room: f64,
    /// The Jacobian's standard deviation, when there is one.
    sd: Option<f64>,
    /// The Jacobian's slope of `sqrt(profile − min)` at the estimate.
    alpha: Option<f64>,
}

impl Frame {
    fn new<M: FreeModel>(side: &Side<'_, M>) -> Self {
        let estimate = side.coordinate.value(side.minimum, side.problem);
        let (lo, hi) = side.coordinate.bounds(side.problem);
        let face = if side.direction < 0.0 { lo } else { hi };
        let sd = side.covariance.and_then(|c| c.sd(side.index));
        let alpha = sd
            .filter(|&sd| sd > 0.0)
            .map(|sd| side.levels.s2.sqrt() / sd);
        Self {
            estimate,
            face,
            room: (face - estimate).abs(),
            sd,
            alpha,
        }
    }

    /// The held value at `distance` from the estimate in `direction` (the
    /// face from the room on).
    fn value_at(&self, distance: f64, direction: f64) -> f64 {
        if distance >= self.room {
            self.face
        } else {
            self.estimate + direction * distance
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn probe(distance: f64, height: f64) -> Probe {
        Probe {
            distance,
            height,
            theta: Vec::new(),
            rechecked: false,
        }
    }

    /// Probes `h` from `first` as a walk does (stopping within
    /// [`END_TOLERANCE`] of the level 1, or on a bracket narrower than
    /// [`BRACKET_TOLERANCE`]), with the face's probe at 2 already taken;
    /// returns the probes taken and the final bracket.
    fn search(h: impl Fn(f64) -> f64, first: f64) -> (usize, f64, f64) {
        let mut probes = vec![probe(0.0, 0.0), probe(2.0, h(2.0))];
        let before = probes.len();
        let mut d = first;
        for _ in 0..MOST_STEPS {
            probes.push(probe(d, h(d)));
            if (h(d) - 1.0).abs() <= END_TOLERANCE {
                break;
            }
            let (near, above) = bracket(&probes, 1.0);
            let above = above.expect("the face is above");
            if above.distance - near.distance <= BRACKET_TOLERANCE * above.distance {
                break;
            }
            d = next_distance(&probes, probes.len() - before, 1.0, None);
            assert!(
                d > near.distance && d < above.distance,
                "{d} outside the bracket"
            );
        }
        let (near, above) = bracket(&probes, 1.0);
        (
            probes.len() - before,
            near.distance,
            above.unwrap().distance,
        )
    }

    #[test]
    fn a_bracket_with_a_steep_far_end_shrinks_from_both_ends() {
        // The profile crosses 1 at d = 1.5 and rises to 40 at the face
        // (d = 2): plain false position between (1.2, 0.8) and (2, 40)
        // steps to 1.204, then keeps creeping up from below.
        let steep = |d: f64| {
            if d <= 1.5 {
                d / 1.5
            } else {
                1.0 + 78.0 * (d - 1.5)
            }
        };
        let (taken, near, _) = search(steep, 1.2);
        assert!(taken <= 3, "{taken} probes to come within 5% of the level");
        assert!((near - 1.5).abs() < 0.1, "ended near {near}");
    }

    #[test]
    fn a_jump_across_the_level_ends_on_a_narrow_bracket() {
        // Below the level up to d = 1.5, far above it beyond (another
        // valley takes over): no probe comes near the level.
        let jump = |d: f64| if d < 1.5 { 0.5 * d / 1.5 } else { 40.0 };
        let (taken, near, above) = search(jump, 1.2);
        // Within the step budget (plain false position would still be 17%
        // of the distance short of the jump after 12 probes).
        assert!(taken <= MOST_STEPS, "{taken} probes for the jump");
        assert!(near < 1.5 && above >= 1.5);
        assert!(
            above - near <= BRACKET_TOLERANCE * above,
            "[{near}, {above}]"
        );
    }
}
