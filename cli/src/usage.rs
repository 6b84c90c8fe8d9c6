//! What a command refuses before it works: options that do not fit together,
//! values out of their range, inputs that do not match. One variant per
//! case, each with the values its message names.

use laminar_brdf_core::InputError;
use laminar_brdf_fit::Model;
use std::path::PathBuf;
use thiserror::Error;

/// Why a command's options or inputs cannot be used.
#[derive(Debug, Error)]
pub enum UsageError {
    /// `--samples` names something other than positive integers or `all`.
    #[error("--samples: sample `{0}` is not a positive integer")]
    Sample(String),
    /// `--brdf` or `--samples` without a CUReT directory.
    #[error(
        "--brdf and --samples select from a CUReT directory: give --data DIR (or set CURET_DIR)"
    )]
    CuretOptionsWithoutData,
    /// `--sample-at` with an input that is not a MERL file.
    #[error("--sample-at samples a MERL file: give --measurements FILE.binary")]
    SampleAtWithoutMerl,
    /// A MERL file without `--sample-at`.
    #[error("{}: a MERL file is a dense table; give --sample-at GEOMETRY.csv with the geometries to fit at", .0.display())]
    MerlWithoutSampleAt(PathBuf),
    /// Neither `--input-format` nor the extension names a format.
    #[error("{}: cannot tell the format from the extension (.csv or .binary); give --input-format csv|merl", .0.display())]
    UnknownFormat(PathBuf),
    /// A CUReT directory without a BRDF file.
    #[error("{}: no BRDF file (abrdf.dat, rbrdf.dat, gbrdf.dat, bbrdf.dat) found", .0.display())]
    NoBrdfFile(PathBuf),
    /// `reproduce` without a CUReT directory.
    #[error("reproduce needs --data DIR (or CURET_DIR) with table.txt and abrdf.dat")]
    ReproduceWithoutData,
    /// `reproduce --out` holds files it would not write.
    #[error("{} holds entries reproduce does not write ({}); it replaces its output directory whole, so choose a new or empty one", .dir.display(), .entries.join(", "))]
    ForeignEntries {
        /// The output directory.
        dir: PathBuf,
        /// What it holds that `reproduce` does not write, sorted.
        entries: Vec<String>,
    },
    /// `--threads` out of range.
    #[error("--threads {given}: give 1 to {most} threads")]
    Threads {
        /// The count given.
        given: usize,
        /// The most allowed.
        most: usize,
    },
    /// The thread pool could not be built.
    #[error(transparent)]
    ThreadPool(#[from] rayon::ThreadPoolBuildError),
    /// `fit --albedo` without JSON output.
    #[error("--albedo: the albedo goes into the fitted-model file; add --format json")]
    AlbedoWithoutJson,
    /// `fit-batch --out` of another kind.
    #[error("{}: --out must end in .csv or .json", .0.display())]
    BatchOutExtension(PathBuf),
    /// `fit-batch` values that do not match the geometry.
    #[error("{} has {per_set} values per set but {} has {geometries} geometries", .values.display(), .geometry.display())]
    ValuesAgainstGeometry {
        /// The values file.
        values: PathBuf,
        /// Its values per set.
        per_set: usize,
        /// The geometry file.
        geometry: PathBuf,
        /// Its geometries.
        geometries: usize,
    },
    /// `eval` of a model that is not layered.
    #[error("eval supports the layered models ({layered}), not {0}", layered = Model::names(Model::layered()))]
    EvalModel(Model),
    /// `eval` of a Ragheb–Hancock model with absorption.
    #[error("{model} is the a = 0 model; --a {a} is not accepted (use exp or gauss)")]
    AbsorptionOfRaghebHancock {
        /// The model.
        model: Model,
        /// The `--a` given.
        a: f64,
    },
    /// `eval` of an untied model without `--sub-slope`, or of a tied one
    /// with it.
    #[error("{model} {}", if model.is_untied() {
        "frees the subsurface slope σ′/T′: give --sub-slope".to_string()
    } else {
        format!("ties σ′/T′ to σ/T: --sub-slope is for {}", untied_names())
    })]
    SubSlopeOfModel {
        /// The model.
        model: Model,
    },
    /// `fit-joint --plot`/`--plot-fit` of more or fewer than one sample.
    #[error("--plot and --plot-fit draw one sample; the input has {0} samples (give one file, or one CUReT sample)")]
    PlotOfSamples(usize),
    /// Parameters or angles outside their domain.
    #[error(transparent)]
    Input(#[from] InputError),
    /// A geometry of a file outside the domain.
    #[error("{}: geometry {row}: {source}", .file.display())]
    Geometry {
        /// The geometry file.
        file: PathBuf,
        /// The geometry's row, from 1.
        row: usize,
        /// What is wrong with it.
        source: InputError,
    },
    /// `predict --measurements` names a channel the file lacks.
    #[error("{}: no channel `{channel}` among {}; choose one with --channel", .file.display(), .channels.join(", "))]
    NoChannel {
        /// The measurement file.
        file: PathBuf,
        /// The channel asked for.
        channel: String,
        /// The file's channels.
        channels: Vec<String>,
    },
    /// `predict --data` on a fit whose sample is not a CUReT number.
    #[error("the fit's sample `{0}` is not a CUReT sample number")]
    NotCuretSample(String),
    /// `predict` without anywhere to predict at.
    #[error("give --geometry FILE.csv, --measurements FILE or --data DIR")]
    NothingToPredictAt,
    /// `export`: the fitted BRDF overflows at a bin.
    #[error("{} ({label}): the BRDF at θi = {theta_i:.4}, θv = {theta_v:.4}, φv − φi = {phi:.4} is not a finite number (the fit's constants overflow it); nothing was written to {}", .fits.display(), .out.display())]
    ExportOverflow {
        /// The fitted-model file.
        fits: PathBuf,
        /// The fit's label.
        label: String,
        /// The bin's θi.
        theta_i: f64,
        /// Its θv.
        theta_v: f64,
        /// Its φv − φi.
        phi: f64,
        /// The MERL file not written.
        out: PathBuf,
    },
    /// `albedo --theta-v` out of range.
    #[error("--theta-v: {0}° is outside [0, 90]")]
    ThetaV(f64),
    /// `render --size` out of range.
    #[error("--size {0}: must lie in [16, 4096]")]
    Size(i64),
    /// `--out` whose extension names another format than the one written.
    #[error("{}: --out names a {named} file, but this writes {writes}: give a name ending in .{extension}", .out.display())]
    OutExtension {
        /// The output.
        out: PathBuf,
        /// The format its extension names.
        named: &'static str,
        /// The format written.
        writes: &'static str,
        /// The extension of the format written.
        extension: &'static str,
    },
    /// `render --light-polar` out of range.
    #[error("--light-polar {0}: must lie in [0, 89] degrees")]
    LightPolar(f64),
    /// `render --light-azimuth` not finite.
    #[error("--light-azimuth {0}: must be a finite number of degrees")]
    LightAzimuth(f64),
    /// `render --environment` negative or not finite.
    #[error("--environment {0}: must be a finite number ≥ 0")]
    Environment(f64),
    /// `render --select` given neither once nor three times.
    #[error("--select given {0} times: give it once (grey) or three times (red, green, blue)")]
    SelectCount(usize),
    /// `report scaling` counts that are not positive.
    #[error("--ks, --scales, --sets and --batch-sets must be positive")]
    ScalingCounts,
    /// A fitted-model file holds no fit.
    #[error("{}: holds no fit", .0.display())]
    NoFit(PathBuf),
    /// A fitted-model file holds several fits and none was selected.
    #[error("{} holds {count} fits; choose one with --select SAMPLE/CHANNEL/MODEL: {}", .file.display(), .labels.join(", "))]
    SelectOne {
        /// The fitted-model file.
        file: PathBuf,
        /// How many fits it holds.
        count: usize,
        /// Their labels.
        labels: Vec<String>,
    },
    /// `--select` matches no fit of the file.
    #[error("{}: {source}", .file.display())]
    NoMatch {
        /// The fitted-model file.
        file: PathBuf,
        /// What the selection rule says.
        source: laminar_brdf_io::selection::SelectError,
    },
}

/// The untied models' names, from the descriptor.
fn untied_names() -> String {
    let names: Vec<&str> = (Model::ALL.into_iter().filter(|m| m.is_untied()))
        .map(Model::name)
        .collect();
    names.join(", ")
}
