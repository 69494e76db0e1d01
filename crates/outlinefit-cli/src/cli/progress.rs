//! The progress line of a single `trace`: shown on a terminal once the trace has run for
//! [`SHOW_AFTER`], never on a pipe or a file (a script's log gets no control characters).
//! Each report of progress is also where a trace without a thread waiting for Ctrl-C
//! reads the signal's flag, and starts that thread once it has run for [`WATCH_AFTER`]
//! (see `interrupt`).

use super::interrupt;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use outlinefit::progress::{Progress, Stage};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How long a trace runs before its progress is shown: a quick one stays silent.
const SHOW_AFTER: Duration = Duration::from_secs(1);

/// How long a trace runs before a thread waits for Ctrl-C: from then on its cost (about
/// 0.2 ms) is under half a percent of the run's.
const WATCH_AFTER: Duration = Duration::from_millis(50);

/// A progress bar on standard error that appears only on a terminal, after
/// [`SHOW_AFTER`].
pub(crate) struct TerminalProgress {
    /// `None` when standard error is not a terminal: nothing is ever drawn, and the bar's
    /// styles and counts are not kept either.
    bar: Option<ProgressBar>,
    started: Instant,
    shown: AtomicBool,
    /// Whether the thread that waits for Ctrl-C was started.
    watched: AtomicBool,
}

impl TerminalProgress {
    pub(crate) fn new() -> TerminalProgress {
        let bar = std::io::stderr()
            .is_terminal()
            .then(|| ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::hidden()));
        TerminalProgress {
            bar,
            started: Instant::now(),
            shown: AtomicBool::new(false),
            watched: AtomicBool::new(false),
        }
    }

    /// Ends the run if Ctrl-C came; once the trace has run long enough, starts the thread
    /// that waits for it and draws the bar from now on.
    fn on_report(&self) {
        interrupt::check();
        if !self.watched.load(Ordering::Relaxed)
            && self.started.elapsed() >= WATCH_AFTER
            && !self.watched.swap(true, Ordering::Relaxed)
        {
            interrupt::watch();
        }
        if let Some(bar) = &self.bar {
            if !self.shown.load(Ordering::Relaxed)
                && self.started.elapsed() >= SHOW_AFTER
                && !self.shown.swap(true, Ordering::Relaxed)
            {
                bar.set_draw_target(ProgressDrawTarget::stderr());
            }
        }
    }

    /// Removes the bar (before warnings are printed).
    pub(crate) fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

impl Progress for TerminalProgress {
    fn stage(&self, stage: Stage, total: u64) {
        let Some(bar) = &self.bar else {
            self.on_report();
            return;
        };
        // The check counts its rounds (most traces need one; the most is a bound, not
        // an estimate); a stage of unknown length shows its name and the time only.
        let template = if stage == Stage::Checking {
            "{msg:28} round {pos:>2} {elapsed_precise}"
        } else if total == 0 {
            "{msg:28} {elapsed_precise}"
        } else {
            "{msg:28} {bar:30} {percent:>3}% {elapsed_precise}"
        };
        bar.set_style(
            ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar.set_message(stage.describe());
        bar.set_length(total);
        bar.set_position(0);
        self.on_report();
    }

    fn advance(&self, done: u64) {
        if let Some(bar) = &self.bar {
            bar.inc(done);
        }
        self.on_report();
    }
}

impl Drop for TerminalProgress {
    fn drop(&mut self) {
        self.finish();
    }
}
