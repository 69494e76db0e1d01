//! The `outlinefit` command line: a thin layer over the library.

mod cli;

fn main() {
    // An interrupted run (Ctrl-C, SIGTERM) removes the temporary files it is writing, so
    // that no half-written output is left behind. Exit status 130, as shells report SIGINT.
    let _ = ctrlc::set_handler(|| {
        outlinefit::io::remove_live_temporaries();
        eprintln!("error: interrupted; outputs not yet written are missing");
        std::process::exit(130);
    });
    match cli::run() {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            // One line, the whole cause chain.
            eprintln!("error: {}", cli::error_line(e.as_ref()));
            std::process::exit(1);
        }
    }
}
