//! # laminar-runner
//!
//! Fits measured BRDF data (CUReT format) with the absorptive scattering
//! model of Dahlan & Hancock (ICPR 2016) and its baselines, by the paper's
//! exhaustive grid search, and checks the SIMD path bit for bit against its
//! scalar twin. The `laminar` binary is the command-line front end.

pub mod data;
pub mod figures;
pub mod fit;
pub mod grid;
pub mod model;
pub mod report;
pub mod reproduce;
pub mod scene;
pub mod search;
pub mod selection;
pub mod speed;
pub mod synthetic;
pub mod tables;
