//! Interruption by SIGINT (Ctrl-C) or SIGTERM: the run ends with status 130, the message
//! "interrupted; outputs not yet written are missing", and no temporary file left behind.
//!
//! Two ways, chosen by how long the run may take:
//!
//! * **A thread that waits for the signal** ([`watch`]) ends the run at once, wherever it
//!   is. `batch` and the research commands start it first thing; so does `trace` of
//!   standard input (which may block), of a file over 1 MiB (long to decode), in colour
//!   or centre-line mode or with a metaheuristic; any other `trace` once it has run for
//!   50 ms.
//! * **A flag** ([`install`], [`check`]) until then: the signal only sets it, and the
//!   trace reads it at each report of progress, before each output it writes and when it
//!   ends. Starting and ending a second thread costs about 0.2 ms of a process's life on
//!   a virtual machine (creating it, then the other processor's memory mappings flushed
//!   at every unmap and at exit): a twelfth of tracing a 64 px glyph in its own process,
//!   nothing beside a run of 50 ms.
//!
//! Until the thread runs, a second signal ends the process at once with status 130 (the
//! first only set the flag); then the thread handles the first as it comes.

#[cfg(unix)]
mod imp {
    use signal_hook::consts::{SIGINT, SIGTERM};
    use signal_hook::flag;
    use signal_hook::SigId;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::{Arc, Mutex, OnceLock};

    /// Set by the first signal.
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    /// The actions that end the process at a second signal, while no thread waits; and
    /// whether one does.
    static SHUTDOWN: Mutex<(Vec<SigId>, bool)> = Mutex::new((Vec::new(), false));

    pub(crate) fn install() {
        let raised = FLAG.get_or_init(|| Arc::new(AtomicBool::new(false)));
        let mut shutdown = SHUTDOWN.lock().unwrap_or_else(|e| e.into_inner());
        for signal in [SIGINT, SIGTERM] {
            // A second signal (the flag already set) ends the process at once...
            if let Ok(id) = flag::register_conditional_shutdown(signal, 130, Arc::clone(raised)) {
                shutdown.0.push(id);
            }
            // ...the first only sets the flag.
            let _ = flag::register(signal, Arc::clone(raised));
        }
    }

    pub(crate) fn raised() -> bool {
        FLAG.get().is_some_and(|f| f.load(Ordering::SeqCst))
    }

    pub(crate) fn watch() {
        let mut shutdown = SHUTDOWN.lock().unwrap_or_else(|e| e.into_inner());
        if shutdown.1 {
            return;
        }
        let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else {
            return;
        };
        let started = std::thread::Builder::new()
            .name("signals".into())
            .spawn(move || {
                // A signal that came before the thread listened set the flag only.
                if super::raised() {
                    super::stop();
                }
                if signals.forever().next().is_some() {
                    super::stop();
                }
            });
        if started.is_ok() {
            // The thread removes the temporaries; a second signal must not cut it short.
            for id in shutdown.0.drain(..) {
                signal_hook::low_level::unregister(id);
            }
            shutdown.1 = true;
        }
    }
}

#[cfg(not(unix))]
mod imp {
    pub(crate) fn install() {
        let _ = ctrlc::set_handler(super::stop);
    }

    pub(crate) fn raised() -> bool {
        false
    }

    pub(crate) fn watch() {}
}

/// Makes SIGINT and SIGTERM set the flag that [`check`] reads (elsewhere than on Unix:
/// handled at once by a thread). The first thing the program does.
pub(crate) use imp::install;

/// Starts the thread that ends the run as soon as a signal comes (and at once if one
/// came already), for runs too long to wait for the next [`check`]. Idempotent.
pub(crate) use imp::watch;

/// Whether a signal came.
use imp::raised;

/// Ends the run with status 130 if a signal came: before an output is written and when
/// the command is done.
pub(crate) fn check() {
    if raised() {
        stop();
    }
}

/// Removes the temporary files being written, says so and ends the process.
fn stop() {
    outlinefit::io::remove_live_temporaries();
    eprintln!("error: interrupted; outputs not yet written are missing");
    std::process::exit(130);
}
