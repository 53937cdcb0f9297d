//! The `prbfit` binary: the headless CLI of DESIGN §6 (and, with no arguments, the TUI).

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    cli::run()
}
