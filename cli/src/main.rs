//! `laminar`: fit, predict with, export, check and reproduce the absorptive
//! scattering model for rough laminar surfaces.

mod commands;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "laminar",
    version,
    about = "Fit measured reflectance with the absorptive scattering model for rough laminar surfaces (Dahlan & Hancock 2016)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    Fit(commands::fit::FitArgs),
    FitBatch(commands::fit_batch::FitBatchArgs),
    FitJoint(commands::fit_joint::FitJointArgs),
    Predict(commands::predict::PredictArgs),
    Export(commands::export::ExportArgs),
    Albedo(commands::albedo::AlbedoArgs),
    Render(commands::render::RenderArgs),
    Eval(commands::eval::EvalArgs),
    Parity(commands::parity::ParityArgs),
    /// Reports on the search paths.
    #[command(subcommand)]
    Report(commands::report::ReportKind),
    Reproduce(commands::reproduce::ReproduceArgs),
}

/// `command` with every option of it and of its subcommands taking a
/// negative number as its value (`--size -3`), so that the option's own
/// check, not the parser's "unexpected argument", names what is wrong.
fn negatives_are_values(command: clap::Command) -> clap::Command {
    command
        .mut_args(|a| {
            let takes_values = a.get_action().takes_values();
            a.allow_negative_numbers(takes_values)
        })
        .mut_subcommands(negatives_are_values)
}

fn main() -> ExitCode {
    // An empty CURET_DIR means "no CUReT directory", as if it were unset
    // (clap would otherwise read it as `--data` without a value).
    if std::env::var_os("CURET_DIR").is_some_and(|v| v.is_empty()) {
        std::env::remove_var("CURET_DIR");
    }
    // clap's errors quote the arguments: they pass through the escaping
    // every other message gets (help and version go to stdout unchanged).
    let parsed = negatives_are_values(Cli::command())
        .try_get_matches()
        .and_then(|m| Cli::from_arg_matches(&m));
    let cli = match parsed {
        Ok(cli) => cli,
        Err(e) if e.use_stderr() => {
            eprint!(
                "{}",
                laminar_brdf::terminal::escaped(&e.render().to_string())
            );
            return ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(2));
        }
        Err(e) => e.exit(),
    };
    // An unusable LAMINAR_SIMD is refused before any work (the kernels
    // would otherwise quietly take the portable lanes).
    if let Err(e) = laminar_brdf_fit::simd::from_env() {
        laminar_brdf::note!("error: {}", laminar_brdf::CliError::from(e));
        return ExitCode::from(2);
    }
    let result = match &cli.command {
        Command::Fit(args) => commands::fit::run(args).map(|_| true),
        Command::FitBatch(args) => commands::fit_batch::run(args).map(|_| true),
        Command::FitJoint(args) => commands::fit_joint::run(args).map(|_| true),
        Command::Predict(args) => commands::predict::run(args).map(|_| true),
        Command::Export(args) => commands::export::run(args).map(|_| true),
        Command::Albedo(args) => commands::albedo::run(args).map(|_| true),
        Command::Render(args) => commands::render::run(args).map(|_| true),
        Command::Eval(args) => commands::eval::run(args).map(|_| true),
        Command::Parity(args) => commands::parity::run(args),
        Command::Report(kind) => commands::report::run(kind).map(|_| true),
        Command::Reproduce(args) => commands::reproduce::run(args).map(|_| true),
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            laminar_brdf::note!("error: {e}");
            ExitCode::from(2)
        }
    }
}
