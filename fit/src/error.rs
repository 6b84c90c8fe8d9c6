//! Typed errors of the fitting library, one enum per layer: grids
//! ([`GridError`]), measurement sets ([`MeasurementError`]), fitted models
//! ([`ModelError`]) and fitting ([`FitError`], which wraps the others).

use laminar_brdf_core::InputError;
use thiserror::Error;

/// A name that is none of a fixed set of choices (an objective, an
/// uncertainty, a search path, a quantity).
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("unknown {what} `{given}` (expected {expected})")]
pub struct UnknownName {
    /// What was named (`objective`, …).
    pub what: &'static str,
    /// The name given.
    pub given: String,
    /// The choices, as a phrase.
    pub expected: String,
}

/// Names as a phrase of choices: `a`, `a or b`, `a, b or c`.
pub fn choices(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => one.to_string(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}

/// The one of `all` whose `name` is `given`, or [`UnknownName`] naming
/// `what` and listing the names ([`choices`]): every option's parser.
///
/// # Errors
/// [`UnknownName`] when no name matches.
pub fn find_named<T: Copy, N: AsRef<str>>(
    what: &'static str,
    all: &[T],
    name: impl Fn(T) -> N,
    given: &str,
) -> Result<T, UnknownName> {
    all.iter()
        .copied()
        .find(|&t| name(t).as_ref() == given)
        .ok_or_else(|| {
            let names: Vec<N> = all.iter().map(|&t| name(t)).collect();
            let names: Vec<&str> = names.iter().map(AsRef::as_ref).collect();
            UnknownName {
                what,
                given: given.to_string(),
                expected: choices(&names),
            }
        })
}

/// A search grid that cannot be used.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum GridError {
    /// The text is not `start:stop:count` or a single value.
    #[error("axis `{text}` is not `start:stop:count` or a single value")]
    Syntax {
        /// The axis text.
        text: String,
    },
    /// A bound is not a finite number.
    #[error("`{field}` in axis `{text}` is not a finite number")]
    NotANumber {
        /// The axis text.
        text: String,
        /// The offending field.
        field: String,
    },
    /// A log-spaced axis with an end that is not positive.
    #[error("axis `{text}` is log-spaced, so both ends must be positive")]
    LogNotPositive {
        /// The axis text.
        text: String,
    },
    /// The count is not a positive integer.
    #[error("count `{field}` in axis `{text}` is not a positive integer")]
    BadCount {
        /// The axis text.
        text: String,
        /// The offending field.
        field: String,
    },
    /// An axis longer than [`crate::grid::MAX_AXIS_LEN`] (refused before anything is allocated).
    #[error("axis `{text}` has {count} values, more than the limit of {limit}")]
    AxisTooLong {
        /// The axis text.
        text: String,
        /// Values asked for.
        count: u128,
        /// The limit.
        limit: usize,
    },
    /// An axis with no value.
    #[error("axis {axis} is empty")]
    Empty {
        /// The axis.
        axis: laminar_brdf_core::Param,
    },
    /// A value outside the model's domain.
    #[error("axis {axis}: {error}")]
    OutOfDomain {
        /// The axis.
        axis: laminar_brdf_core::Param,
        /// The core's description of the value and its domain.
        error: InputError,
    },
    /// More parameter sets than [`crate::grid::MAX_GRID_SIZE`].
    #[error("the grid has {size} parameter sets ({shape}), more than the limit of {limit}")]
    TooLarge {
        /// Parameter sets asked for.
        size: u128,
        /// The axis lengths, `slope×n×a×beta`.
        shape: String,
        /// The limit.
        limit: u128,
    },
    /// A table over the grid (e.g. an error surface) could not be allocated.
    #[error("cannot allocate {bytes} bytes for {size} grid values")]
    Allocation {
        /// Grid values.
        size: usize,
        /// Bytes asked for.
        bytes: u128,
    },
}

/// A measurement set that cannot be built or fitted.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MeasurementError {
    /// A measurement's angle is outside its domain (row is 1-based, in the source's numbering).
    #[error("{set}: row {row}: {error}")]
    Angle {
        /// The set's name.
        set: String,
        /// Source row of the measurement.
        row: usize,
        /// What is wrong.
        error: InputError,
    },
    /// A value or uncertainty is NaN or infinite.
    #[error("{set}: row {row}: channel `{channel}`: {what} {value} is not a finite number")]
    NotFinite {
        /// The set's name.
        set: String,
        /// Source row.
        row: usize,
        /// The channel.
        channel: String,
        /// `value` or `sigma`.
        what: &'static str,
        /// The value.
        value: f64,
    },
    /// An uncertainty that is not positive.
    #[error("{set}: row {row}: channel `{channel}`: sigma {value} is not positive")]
    BadSigma {
        /// The set's name.
        set: String,
        /// Source row.
        row: usize,
        /// The channel.
        channel: String,
        /// The value.
        value: f64,
    },
    /// A channel, row list or uncertainty list whose length is not the number of measurements.
    #[error("{set}: {what} has {found} entries for {expected} measurements")]
    Length {
        /// The set's name.
        set: String,
        /// What had the wrong length.
        what: String,
        /// Entries given.
        found: usize,
        /// Measurements in the set.
        expected: usize,
    },
    /// Two channels with one name.
    #[error("{set}: channel `{channel}` is given twice")]
    DuplicateChannel {
        /// The set's name.
        set: String,
        /// The channel.
        channel: String,
    },
    /// A channel name the set does not have.
    #[error("{set}: no channel `{channel}` (channels: {available})")]
    NoChannel {
        /// The set's name.
        set: String,
        /// The channel asked for.
        channel: String,
        /// The channels the set has, comma-separated.
        available: String,
    },
    /// A set without measurements, or whose every measurement is specular.
    #[error("{set}: no non-specular measurement to fit ({measurements} measurements, {specular} specular)")]
    NothingToFit {
        /// The set's name.
        set: String,
        /// Measurements in the set.
        measurements: usize,
        /// Measurements excluded as specular.
        specular: usize,
    },
    /// A channel whose kept values are all zero or negative.
    #[error("{set}: channel `{channel}` has no positive value among its {kept} non-specular measurements; nothing to normalise by")]
    NoPositiveValue {
        /// The set's name (the sample).
        set: String,
        /// The channel.
        channel: String,
        /// Non-specular measurements.
        kept: usize,
    },
    /// A value that cannot be normalised with the others: every error measure
    /// stays finite only when `−max ≤ D ≤ max` and positive values are at
    /// least 1e-100 of the max (docs/conventions.md §8).
    #[error("{set}: row {row}: channel `{channel}`: value {value} cannot be fitted with the others: {why}")]
    OutOfScale {
        /// The set's name.
        set: String,
        /// Source row.
        row: usize,
        /// The channel.
        channel: String,
        /// The value as given.
        value: f64,
        /// Why.
        why: &'static str,
    },
    /// A negative specular tolerance, or NaN.
    #[error("specular tolerance {0} is not a finite non-negative angle")]
    BadTolerance(f64),
}

/// A fitted model that cannot predict (e.g. one read from a file and edited by hand).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ModelError {
    /// A name that is not a model.
    #[error("unknown model `{given}` (expected one of {expected})")]
    UnknownModel {
        /// The name given.
        given: String,
        /// The models' names ([`crate::Model::names`]).
        expected: String,
    },
    /// Parameters of another model.
    #[error("model {model} takes parameters {expected}")]
    WrongParameters {
        /// The model.
        model: String,
        /// Its parameter names.
        expected: String,
    },
    /// A parameter outside its domain.
    #[error("{0}")]
    OutOfDomain(InputError),
    /// A prediction that is not a finite number: the model's constants
    /// (amplitude, maxima, data scale) overflow or underflow it there.
    #[error("prediction {index} is {value}, not a finite number (the fitted model's constants overflow it there)")]
    NonFinitePrediction {
        /// Its position among the geometries asked for (0-based).
        index: usize,
        /// The value.
        value: f64,
    },
    /// A normalisation constant that is negative, NaN or infinite.
    #[error("normalisation constant {name} = {value} is not a finite non-negative number")]
    BadConstant {
        /// The constant.
        name: &'static str,
        /// Its value.
        value: f64,
    },
}

/// A fit that cannot run.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FitError {
    /// The grid.
    #[error(transparent)]
    Grid(#[from] GridError),
    /// The measurements.
    #[error(transparent)]
    Measurements(#[from] MeasurementError),
    /// The model or its parameters.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A model named twice among the models to compare (each would take
    /// half of its Akaike weight).
    #[error("model {model} is named twice: name each model once")]
    ModelTwice {
        /// The model's name.
        model: &'static str,
    },
    /// An untied model under the paper's objective, whose exhaustive
    /// search ties σ′/T′ to σ/T.
    #[error(
        "model {model} frees the subsurface slope, which the paper objective's search ties to \
         the surface's: fit {tied} under the paper objective, or {model} under the free one"
    )]
    UntiedUnderPaper {
        /// The untied model's name.
        model: &'static str,
        /// Its tied model's name.
        tied: &'static str,
    },
    /// An uncertainty the objective does not compute.
    #[error("uncertainty {uncertainty} is not computed under the {objective} objective: {hint}")]
    UncertaintyOfObjective {
        /// The uncertainty's name.
        uncertainty: &'static str,
        /// The objective's name.
        objective: &'static str,
        /// What to ask for instead.
        hint: &'static str,
    },
    /// A noise model under the paper objective, which weighs every
    /// measurement alike.
    #[error("noise {noise} weighs the free objective; the paper objective's Δ_RMS weighs every measurement alike: fit under the free objective")]
    NoiseOfObjective {
        /// The noise model's name.
        noise: &'static str,
    },
    /// The noise model.
    #[error(transparent)]
    Noise(#[from] NoiseError),
    /// A joint fit across channels that cannot be made.
    #[error("joint fit: {0}")]
    Joint(JointError),
    /// The worker threads.
    #[error("cannot start {threads} worker threads: {message}")]
    Threads {
        /// Threads asked for (0 is refused).
        threads: usize,
        /// Why.
        message: String,
    },
}

/// A noise model a set cannot take ([`crate::Noise`]).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NoiseError {
    /// A floor outside (0, 1].
    #[error("noise floor `{floor}` is not in (0, 1] (a fraction of the median positive value)")]
    Floor {
        /// The floor given.
        floor: f64,
    },
    /// Relative noise on a set without a positive value to scale the floor.
    #[error("{sample} {channel}: relative noise needs a positive value")]
    NoPositiveValue {
        /// The set's sample.
        sample: String,
        /// Its channel.
        channel: String,
    },
}

/// Why channels cannot be fitted jointly ([`crate::Fitter::fit_joint`]).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum JointError {
    /// A model without the layered geometry to share.
    #[error("{model} is not a layered model; the channels share a layered model's σ/T and n")]
    NotLayered {
        /// The model's name.
        model: &'static str,
    },
    /// Fewer than two channels.
    #[error("{count} channel given; a joint fit needs at least two")]
    TooFewChannels {
        /// Channels given.
        count: usize,
    },
    /// Channels measured at different geometries.
    #[error("channel `{channel}` is not on the geometry of `{first}`; the channels must share their measurements' directions")]
    GeometryDiffers {
        /// The channel that differs.
        channel: String,
        /// The first channel.
        first: String,
    },
    /// The paper objective.
    #[error(
        "the paper objective fits one channel at a time; a joint fit needs the free objective"
    )]
    PaperObjective,
}
