//! One module per subcommand, each with only its own options.

pub mod albedo;
pub mod eval;
pub mod export;
pub mod fit;
pub mod fit_batch;
pub mod fit_joint;
pub mod options;
pub mod parity;
pub mod predict;
pub mod render;
pub mod report;
pub mod reproduce;
pub mod select;
