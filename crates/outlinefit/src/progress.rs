//! Progress of one trace, for a program that shows it ([`crate::trace_bitmap_with_progress`]).
//!
//! The trace reports each stage as it starts, with the amount of work it holds, and the
//! work done as it goes: the fit in data points (a page's contours are fitted on several
//! threads, so the reports come from any of them), the check in rounds. A display that
//! is not wanted costs nothing: [`NoProgress`] ignores every report.

/// A stage of the trace.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Stage {
    /// Finding the borders of the shapes and placing their sub-pixel points.
    Borders,
    /// Fitting curves to the contours; work in data points.
    Fitting,
    /// Checking the drawn outline against the pixels and repairing what it lost or
    /// invented; work in rounds of check and repair, each counted as it starts (at most
    /// [`CHECK_ROUNDS`], usually one).
    Checking,
}

impl Stage {
    /// The stage in a few words, for a progress line.
    pub fn describe(self) -> &'static str {
        match self {
            Stage::Borders => "finding borders",
            Stage::Fitting => "fitting curves",
            Stage::Checking => "checking against the pixels",
        }
    }
}

/// Most rounds of the check: the first check and one after each of up to twelve repair
/// rounds.
pub const CHECK_ROUNDS: u64 = 13;

/// Receives the progress of a trace. Both methods may be called from any thread.
pub trait Progress: Sync {
    /// `stage` starts, with `total` units of work (0: not known in advance).
    fn stage(&self, stage: Stage, total: u64);
    /// `done` more units of the current stage are finished.
    fn advance(&self, done: u64);
}

/// Shows nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoProgress;

impl Progress for NoProgress {
    fn stage(&self, _: Stage, _: u64) {}
    fn advance(&self, _: u64) {}
}
