//! `gonio`: evaluate, check and plot reflection models from the command line.
//!
//! Exit status: 0 success; 1 a property a model claims failed (`check`, `demo`); 2 an error.

/// `println!` that ends the program quietly when stdout is closed (`gonio models | head`)
/// instead of panicking, with the status a shell gives a process killed by SIGPIPE.
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if writeln!(std::io::stdout(), $($arg)*).is_err() {
            std::process::exit(141);
        }
    }};
}

mod cli;
mod cmd;
mod converge;
mod demo_scene;
mod explore;
mod font;
mod label;
mod modelarg;
mod output;
mod plot;

use clap::Parser;
use cli::{Cli, Command};
use std::process::ExitCode;

fn main() -> ExitCode {
    let argv: Vec<String> = std::env::args_os().map(|a| a.to_string_lossy().into_owned()).collect();
    let (clap_args, model_params) = match cli::split_args(argv) {
        Ok(split) => split,
        Err(e) => {
            eprintln!("gonio: error: {e}");
            return ExitCode::from(2);
        }
    };
    // clap prints its own usage errors (exit 2) and help (exit 0).
    let cli = Cli::try_parse_from(clap_args).unwrap_or_else(|e| e.exit());
    let result = match &cli.command {
        Command::Models(a) => cmd::models::run(a).map(|()| true),
        Command::Eval(a) => cmd::eval::run(a, &model_params).map(|()| true),
        Command::Check(a) => cmd::check::run(a, &model_params),
        Command::Plot(a) => cmd::plot::run(a, &model_params).map(|()| true),
        Command::Demo(a) => cmd::demo::run(a),
        Command::Measure(a) => cmd::measure::run(a, &model_params).map(|()| true),
        Command::Envmap(a) => cmd::envmap::run(a).map(|()| true),
        Command::Render(a) => cmd::render::run(a).map(|()| true),
        Command::Compare(a) => cmd::compare::run(a).map(|()| true),
        Command::Fit(a) => cmd::fit::run(a).map(|()| true),
        Command::Explore(a) => explore::run(a).map(|()| true),
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("gonio: error: {e:#}");
            ExitCode::from(2)
        }
    }
}
