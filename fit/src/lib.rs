//! # laminar-brdf-fit
//!
//! The fitting engine of laminar: fit the absorptive scattering model for
//! rough laminar surfaces (H. A. Dahlan and E. R. Hancock, ICPR 2016), the
//! Ragheb–Hancock model it extends and the Jensen and Oren–Nayar baselines
//! to any measurement set — by a weighted free-amplitude estimator inside a
//! stated box ([`Objective::Free`]: the default of [`Fitter`], [`Settings`]
//! and every front end) or by the paper's exhaustive grid search
//! ([`Objective::Paper`]) — and carry the
//! fit anywhere. It names no file format (readers and writers are in
//! `laminar-brdf-io`); every front end (the `laminar` command, and later the C,
//! WebAssembly and Python bindings) calls it.
//!
//! * [`MeasurementSet`]: measurements from any source (angles in the lab or
//!   the paper frame, named channels, optional uncertainties, BRDF or
//!   radiance), turned into a [`Scene`] per channel in one place.
//! * [`Grid`] and [`Axis`]: the search grid (paper preset by default).
//! * [`Fitter`]: objective, grid, [`SearchPath`], threads, progress; [`Fitter::fit`]
//!   returns a [`Fit`], [`Fitter::fit_all`] every model on every scene.
//! * [`Settings`]: every option by name, as each front end hands it over.
//! * [`Model`] and [`Param`]: the model descriptor every list derives from.
//! * [`FittedModel`]: model, parameters and normalisation constants, which
//!   predict at any geometry exactly what the fit predicted at its own.
//!
//! Choices the paper leaves open are stated in the repository's
//! `docs/conventions.md`; "§N" in this crate refers to its sections.
//!
//! ```
//! use laminar_brdf_fit::{Fitter, Grid, MeasurementAngles, MeasurementSet, Model, Objective, Param, Quantity};
//! use laminar_brdf_core::{total_radiance, Correlation, Geometry, Params};
//! // Radiance made by eq. 8 at known parameters, on a 12 × 12 grid of angles.
//! let truth = Params::new(0.6, 0.4, 1.4, 0.2)?;
//! let mut angles = Vec::new();
//! let mut values = Vec::new();
//! for i in 0..12 {
//!     for j in 0..12 {
//!         let (ti, ts, ps) = (0.1 * i as f64, 0.12 * j as f64, 0.5 * j as f64 - 2.0);
//!         let a = laminar_brdf_core::Angles::new(ti, ts, ps)?;
//!         angles.push(MeasurementAngles::Paper { theta_i: ti, theta_s: ts, phi_s: ps });
//!         values.push(total_radiance(&Geometry::<f64>::splat(&a), Correlation::Exponential, &truth));
//!     }
//! }
//! let set = MeasurementSet::new("made-up", angles, Quantity::Radiance)?
//!     .with_channel("value", values, None)?;
//! // The default fitter: the free amplitude inside the default box.
//! let fit = Fitter::new(Grid::user())?.fit(&set.scene("value")?, Model::Exp);
//! assert_eq!(fit.objective, Objective::Free);
//! // Every parameter recovered, β as eq. 8's own balance.
//! for (name, want) in [(Param::Slope, 0.6), (Param::Beta, 0.4), (Param::N, 1.4), (Param::A, 0.2)] {
//!     let p = fit.parameters.iter().find(|p| p.name == name).unwrap();
//!     assert!((p.value() - want).abs() < 1e-6, "{name}: {}", p.value());
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod adequacy;
pub mod albedo;
pub mod analysis;
mod baseline;
pub mod choice;
mod covariance;
pub mod coverage;
mod cube_root;
mod edges;
mod error;
mod estimate;
pub mod fit;
pub mod fitted;
mod free;
pub mod graphics_metrics;
pub mod grid;
pub mod measurements;
pub mod misspecified;
pub mod model;
pub mod noise;
mod objective;
pub mod paper;
pub mod preview;
pub mod profile;
pub mod report;
mod scene;
pub mod settings;
pub mod simd;
pub mod synthetic;

pub use analysis::{Analysis, Uncertainty};
pub use covariance::Covariance;
pub use edges::Edge;
pub use error::{FitError, GridError, JointError, MeasurementError, ModelError, UnknownName};
pub use estimate::Estimate;
pub use fit::Fitter;
pub use fitted::{FittedModel, ModelParams, NormalisationConstants};
pub use free::joint::{ChannelTest, JointChannel, JointFit, JointValue, Variant, VariantFit};
pub use grid::{Axis, Grid};
pub use measurements::{Channel, MeasurementAngles, MeasurementSet, Quantity};
pub use model::{Baseline, Model, Param};
pub use noise::{Noise, NoiseError};
pub use objective::Objective;
pub use paper::profiles::ProfileCurve;
pub use report::{Fit, Parameter};
pub use scene::Scene;
pub use settings::{Arith, Method, Precision, SearchPath, SettingError, Settings};
