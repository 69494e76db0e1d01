//! Command definitions (clap derive) and dispatch.

mod args;
mod batch;
mod bspline;
mod centerline;
mod colour;
mod compare;
mod format;
pub(crate) mod interrupt;
mod merge;
mod messages;
mod output;
mod progress;
mod reduce;
mod summary;
mod surface;
mod trace;

use clap::{CommandFactory, FromArgMatches as _, Parser, Subcommand};
pub(crate) use messages::{error_line, panic_message};

/// Trace bitmap outlines into G1-continuous rational cubic Bézier curves, with a
/// per-segment error report.
#[derive(Parser, Debug)]
#[command(
    name = "outlinefit",
    version,
    about,
    long_about = None,
    after_help = EXIT_STATUS,
    override_usage = "outlinefit <COMMAND>\n       outlinefit <IMAGE> [OPTIONS]   (short for: outlinefit trace <IMAGE> [OPTIONS])"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// What `trace` does, in the command list and at the top of its `--help`.
const TRACE_ABOUT: &str = "Trace one image into an outline: SVG, PDF, EPS, DXF or GeoJSON, \
                           with optional JSON/CSV reports and an overlay";

/// The command line of `outlinefit trace …` alone: the same program, with `trace` its only
/// command. A script that traces a folder one process per file pays for building the
/// parser each time; this tree has only `trace`'s arguments, not every command's (see
/// [`run`]). Its `--help`, usage and errors are those of the whole tree (tested); only
/// the name of the program shows in them, so that is all it takes from [`Cli`].
#[derive(Parser, Debug)]
#[command(name = "outlinefit")]
struct TraceCli {
    #[command(subcommand)]
    command: TraceOnly,
}

/// [`TraceCli`]'s one command.
#[derive(Subcommand, Debug)]
enum TraceOnly {
    #[command(about = TRACE_ABOUT, after_help = EXIT_STATUS)]
    Trace(trace::TraceArgs),
}

/// The exit statuses, shown under every command's `--help` (the README has the same table).
const EXIT_STATUS: &str = "\
Exit status:
  0    everything done
  1    an input, an output or an option's value was refused (batch: at least one
       file failed; the others are still done)
  2    the command line does not parse: unknown option, missing or malformed value
       (a negative or fractional count included)
  130  interrupted (SIGINT, SIGTERM); outputs not yet written are missing";

#[derive(Subcommand, Debug)]
enum Command {
    #[command(about = TRACE_ABOUT, after_help = EXIT_STATUS)]
    Trace(trace::TraceArgs),
    /// Trace every image of a folder in parallel into OUTDIR/<name>.svg (or another
    /// format) and <name>.json, with OUTDIR/summary.csv.
    #[command(after_help = EXIT_STATUS)]
    Batch(batch::BatchArgs),
    /// Work on batch summaries: `summary merge` joins the summary.csv files of a batch
    /// split into shards (--shard K/N) and checks that every input was traced once.
    #[command(subcommand)]
    Summary(summary::SummaryCommand),
    /// Compare optimizers on the same segmentation of one or more images: many seeded runs
    /// each, descriptive statistics, normality, F-, t-tests and ANOVA, charts.
    #[command(after_help = EXIT_STATUS)]
    Compare(compare::CompareArgs),
    /// Convert a parametric curve x(u), y(u) into a B-spline: curvature feature points plus
    /// auxiliary samples placed by the fireworks algorithm (or another optimizer); JSON on
    /// stdout.
    #[command(after_help = EXIT_STATUS)]
    Bspline(bspline::BsplineArgs),
    /// Merge two adjacent disk Wang–Ball curves into one of a given degree, exactly (least
    /// squares) or by a metaheuristic; prints the control disks and merging error as JSON.
    #[command(after_help = EXIT_STATUS)]
    Merge(merge::MergeArgs),
    /// Reduce the degree of an (SG-)Bézier curve from n to m < n (unconstrained, C0 or C1
    /// ends), exactly (least squares) or with a metaheuristic searching the shape
    /// parameters; prints the reduced control points and the L2 error as JSON.
    #[command(after_help = EXIT_STATUS)]
    Reduce(reduce::ReduceArgs),
    /// Fit a Bézier surface to a cloud of 3-D points (a grid or unorganized): parameters by
    /// correction (default), the classical rules or cuckoo search, poles by least squares;
    /// writes the poles and errors (JSON), a mesh (OBJ) and a picture (SVG). --rerun
    /// repeats the surface paper's experiment.
    #[command(after_help = EXIT_STATUS)]
    Surface(surface::SurfaceArgs),
}

/// Parses the command line and runs it; returns the exit code.
pub(crate) fn run() -> anyhow::Result<i32> {
    let args = with_default_command(std::env::args_os().collect());
    // `outlinefit trace …` (or the shorthand) builds only `trace`'s part of the parser:
    // the whole tree, with every command's arguments and help, is about a tenth of the
    // process's time on a 256 px glyph.
    if args.get(1).is_some_and(|a| a == "trace") {
        let mut matches = TraceCli::command().get_matches_from(args);
        let cli = TraceCli::from_arg_matches_mut(&mut matches)
            .unwrap_or_else(|e| e.format(&mut TraceCli::command()).exit());
        let TraceOnly::Trace(args) = cli.command;
        return trace::run(&args);
    }
    // `Cli::parse_from` is the same two steps, on a tree of its own for the error.
    let mut matches = Cli::command().get_matches_from(args);
    let cli = Cli::from_arg_matches_mut(&mut matches)
        .unwrap_or_else(|e| e.format(&mut Cli::command()).exit());
    if !matches!(cli.command, Command::Trace(_)) {
        // Every other command may run long; `trace` decides by its image.
        interrupt::watch();
    }
    match cli.command {
        Command::Trace(args) => trace::run(&args),
        Command::Batch(args) => batch::run(&args),
        Command::Summary(command) => summary::run(&command),
        Command::Compare(args) => compare::run(&args),
        Command::Reduce(args) => reduce::run(&args),
        Command::Bspline(args) => bspline::run(&args),
        Command::Merge(args) => merge::run(&args),
        Command::Surface(args) => surface::run(&args),
    }
}

/// The names of the commands (and `help`), known without building the parser (a test
/// checks them against it).
const COMMANDS: [&str; 9] = [
    "trace", "batch", "summary", "compare", "bspline", "merge", "reduce", "surface", "help",
];

/// `outlinefit FILE …` means `outlinefit trace FILE …`, as `potrace FILE` traces a file:
/// when the first argument is no command and is a path (an existing file or folder, a
/// name with a folder or an extension, or `-` for standard input), `trace` is put before
/// it. Anything else is left to the parser, so a misspelt command still gets its
/// "unrecognized subcommand" and suggestion.
fn with_default_command(mut args: Vec<std::ffi::OsString>) -> Vec<std::ffi::OsString> {
    let Some(first) = args.get(1) else {
        return args;
    };
    let is_command = first.to_str().is_some_and(|s| COMMANDS.contains(&s));
    // A name with a folder or an extension is a path even when it does not exist, so
    // that the error names the missing file rather than an unknown command.
    let path = std::path::Path::new(first);
    let is_input = first == "-"
        || path.exists()
        || path.extension().is_some()
        || path.components().count() > 1;
    if !is_command && is_input {
        args.insert(1, "trace".into());
    }
    args
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_command_names_are_the_parsers() {
        let command = Cli::command();
        let mut parsed: Vec<String> = command
            .get_subcommands()
            .flat_map(|c| std::iter::once(c.get_name()).chain(c.get_all_aliases()))
            .map(str::to_owned)
            .chain(["help".to_owned()])
            .collect();
        let mut listed: Vec<String> = COMMANDS.iter().map(|s| (*s).to_owned()).collect();
        parsed.sort();
        listed.sort();
        assert_eq!(parsed, listed);
    }
}
