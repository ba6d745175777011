//! The `rollphase` binary: parse the command line, run one command, map errors to exit codes
//! (0 success, 1 a failed command with its reason on standard error, 2 bad usage from clap).

use clap::Parser;

fn main() {
    let cli = rollphase::cli::Cli::parse();
    if let Err(e) = rollphase::cli::run(cli) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
