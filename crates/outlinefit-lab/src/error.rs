//! The lab's error type: the tracer's errors unchanged, and the lab's own: an input file it
//! cannot read, an option out of its domain, a data file or expression that is readable but
//! not valid, a chart that cannot be drawn. An error about an option names the options
//! field, as the tracer's do.

/// Everything that can go wrong in the lab.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// An error of the tracer library (reading, writing, an option out of its domain …),
    /// with its own message.
    #[error(transparent)]
    Tracer(#[from] outlinefit::Error),
    /// An input file could not be read.
    #[error("cannot read {}: {source}", path.display())]
    Read {
        /// The file.
        path: std::path::PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// An option has a value outside its domain.
    #[error("invalid option {name}: {message}")]
    InvalidOption {
        /// The options field, e.g. `budget` (`omega/lambda/mu` when several fields are at
        /// fault together).
        name: &'static str,
        /// What is wrong with it.
        message: String,
    },
    /// A data file or value (JSON curve description, expression …) that is readable but
    /// not valid.
    #[error("{what}: {message}")]
    InvalidInput {
        /// What was read, e.g. the file's path.
        what: String,
        /// What is wrong with it.
        message: String,
    },
    /// A chart could not be drawn.
    #[error("cannot draw {what}: {message}")]
    Plot {
        /// The chart.
        what: String,
        /// What went wrong.
        message: String,
    },
}

/// Shorthand for results whose error is [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
