//! The `rollphase` binary: parse the command line, run one command, map errors to exit codes
//! (0 success, 1 a failed command with its reason on standard error, 2 bad usage from clap). A
//! reader that closes the pipe early (`rollphase … | head`) ends the command quietly with 0, as
//! Unix tools do; any other failure to write standard output (a full disk) is an error. Ctrl-C
//! removes the outputs still being written and exits with 130 (a commit under way is let
//! finish first, so no file is ever cut).

use std::io::Write;

use clap::Parser;

fn main() {
    let cli = rollphase::cli::Cli::parse();
    // Ctrl-C (or a termination signal): remove the outputs still being written, then stop with
    // the conventional status 130. The destinations are untouched until a command succeeds.
    // A commit under way when the signal comes is let finish (see `output::remove_partial_outputs`),
    // and the message says which of the two happened.
    // The window app is asked to close from its own event loop instead (rollphase::app).
    let _ = ctrlc::set_handler(|| {
        #[cfg(feature = "app")]
        if rollphase::app::request_close() {
            return;
        }
        interrupted();
    });
    let result = rollphase::cli::run(cli).and_then(|()| {
        std::io::stdout()
            .flush()
            .map_err(|e| anyhow::Error::new(e).context("cannot write to standard output"))
    });
    #[cfg(feature = "app")]
    if rollphase::app::closed_by_signal() {
        interrupted();
    }
    // The command finished while the handler ran: its exit (130, with its message) is the one.
    if rollphase::output::interrupt_pending() {
        loop {
            std::thread::park();
        }
    }
    if let Err(e) = result {
        let broken_pipe = e.chain().any(|c| {
            c.downcast_ref::<std::io::Error>()
                .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
                || c.downcast_ref::<rollphase::output::OutputError>()
                    .is_some_and(|o| o.is_broken_pipe())
        });
        if broken_pipe {
            std::process::exit(0);
        }
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

/// Ends the process on Ctrl-C or a termination signal: the outputs still being written are
/// removed (a commit under way is let finish) and the status is 130.
fn interrupted() -> ! {
    let when = rollphase::output::remove_partial_outputs();
    eprintln!("{}", when.message());
    std::process::exit(130);
}
