//! The `outlinefit` command line: a thin layer over the library.

mod cli;

fn main() {
    // An interrupted run (Ctrl-C, SIGTERM) removes the temporary files it is writing, so
    // that no half-written output is left behind. Exit status 130, as shells report SIGINT.
    cli::interrupt::install();
    // A panic is a bug: the panic hook has printed where it happened; the user still gets
    // the one error line, the temporaries are removed, and the status is 1 like every
    // other failure (not the runtime's 101).
    let outcome = std::panic::catch_unwind(cli::run).unwrap_or_else(|panic| {
        outlinefit::io::remove_live_temporaries();
        Err(anyhow::anyhow!(
            "internal error ({}); please report it with the input and the command",
            cli::panic_message(panic.as_ref())
        ))
    });
    // A signal during a short run (see `cli::interrupt`) ends it here if no output did.
    cli::interrupt::check();
    match outcome {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            // One line, the whole cause chain.
            eprintln!("error: {}", cli::error_line(e.as_ref()));
            std::process::exit(1);
        }
    }
}
