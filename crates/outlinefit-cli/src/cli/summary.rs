//! `outlinefit summary merge`: joins the `summary.csv` files of a batch split into shards
//! (`batch --shard K/N`, one per array job) into one, and checks that every input was
//! traced exactly once.

use super::batch::list_images;
use super::output::resolve_output;
use anyhow::{bail, Context};
use clap::{Args, Subcommand};
use outlinefit::io::write_atomic;
use std::collections::{BTreeMap, HashSet};
use std::path::{Path, PathBuf};

/// What `summary` does.
#[derive(Subcommand, Debug)]
pub(crate) enum SummaryCommand {
    /// Join the summary.csv files of sharded batch runs into one, in the order of one
    /// unsharded run; refuse a file that appears twice, a run that has not finished, and
    /// (with --input) an input that no shard traced.
    Merge(MergeArgs),
}

/// Arguments of `summary merge`.
#[derive(Args, Debug)]
pub(crate) struct MergeArgs {
    /// The shards' summary.csv files (or their output folders).
    #[arg(required = true, value_name = "SUMMARY")]
    summaries: Vec<PathBuf>,
    /// Where to write the joined summary (`-`: standard output).
    #[arg(short = 'o', long = "output", value_name = "OUT.csv")]
    output: PathBuf,
    /// The folder the shards traced, named as the batch runs named it: every image in it
    /// must appear in exactly one summary.
    #[arg(long, value_name = "INDIR")]
    input: Option<PathBuf>,
    /// The shards ran with --recursive (list sub-folders' images with --input too).
    #[arg(long, requires = "input")]
    recursive: bool,
    /// The shards ran with --follow-symlinks.
    #[arg(long, requires = "input")]
    follow_symlinks: bool,
}

pub(crate) fn run(command: &SummaryCommand) -> anyhow::Result<i32> {
    match command {
        SummaryCommand::Merge(args) => merge(args),
    }
}

fn merge(args: &MergeArgs) -> anyhow::Result<i32> {
    let mut header: Option<csv::StringRecord> = None;
    // Rows by input path, in path order (the order `batch` traces and lists them in).
    let mut rows: BTreeMap<PathBuf, (csv::StringRecord, PathBuf)> = BTreeMap::new();
    let mut twice: Vec<String> = Vec::new();
    for given in &args.summaries {
        let path = if given.is_dir() {
            given.join("summary.csv")
        } else {
            given.clone()
        };
        let mut reader = csv::Reader::from_path(&path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        let this_header = reader
            .headers()
            .with_context(|| format!("{}: not a summary", path.display()))?
            .clone();
        if this_header.get(0) != Some("file") || this_header.get(1) != Some("status") {
            bail!(
                "{}: not a batch summary (its first columns are not file, status)",
                path.display()
            );
        }
        match &header {
            None => header = Some(this_header.clone()),
            Some(h) if *h != this_header => bail!(
                "{}: its columns differ from {}'s (runs of different versions?)",
                path.display(),
                args.summaries[0].display()
            ),
            Some(_) => {}
        }
        for record in reader.records() {
            let record = record.with_context(|| format!("{}: malformed row", path.display()))?;
            if record.get(1) == Some("unfinished") {
                bail!(
                    "{}: that run has not finished (or was interrupted); run it again before merging",
                    path.display()
                );
            }
            let file = PathBuf::from(record.get(0).unwrap_or_default());
            if let Some((_, first)) = rows.get(&file) {
                twice.push(format!(
                    "{} (in {} and {})",
                    file.display(),
                    first.display(),
                    path.display()
                ));
                continue;
            }
            rows.insert(file, (record, path.clone()));
        }
    }
    if !twice.is_empty() {
        bail!(
            "{} inputs appear in more than one summary: {}",
            twice.len(),
            listing(&twice)
        );
    }
    if let Some(input) = &args.input {
        if !input.is_dir() {
            bail!("--input {} is not a folder", input.display());
        }
        let images = list_images(input, args.recursive, args.follow_symlinks)
            .with_context(|| format!("cannot list {}", input.display()))?;
        let listed: HashSet<&Path> = images.iter().map(PathBuf::as_path).collect();
        let missing: Vec<String> = images
            .iter()
            .filter(|p| !rows.contains_key(*p))
            .map(|p| p.display().to_string())
            .collect();
        let extra: Vec<String> = rows
            .keys()
            .filter(|p| !listed.contains(p.as_path()))
            .map(|p| p.display().to_string())
            .collect();
        if !missing.is_empty() {
            bail!(
                "{} of the {} images of {} are in no summary: {}",
                missing.len(),
                images.len(),
                input.display(),
                listing(&missing)
            );
        }
        if !extra.is_empty() {
            bail!(
                "{} summary rows name no image of {} (was it given as the shards were?): {}",
                extra.len(),
                input.display(),
                listing(&extra)
            );
        }
    }
    let Some(header) = header else {
        bail!("no summary given");
    };
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(&header)?;
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    for (record, _) in rows.values() {
        w.write_record(record)?;
        *counts
            .entry(record.get(1).unwrap_or_default().to_string())
            .or_default() += 1;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| anyhow::anyhow!("cannot build the summary: {e}"))?;
    if super::output::is_dash(&args.output) {
        use std::io::Write as _;
        std::io::stdout().lock().write_all(&bytes)?;
    } else {
        let target = resolve_output(&args.output, false)?;
        write_atomic(&target, &bytes)?;
    }
    let counts: Vec<String> = counts.iter().map(|(s, n)| format!("{n} {s}")).collect();
    eprintln!(
        "{} inputs from {} summaries: {}",
        rows.len(),
        args.summaries.len(),
        counts.join(", ")
    );
    let failed = rows.values().any(|(r, _)| r.get(1) == Some("failed"));
    Ok(i32::from(failed))
}

/// The first few items of a list, and how many more.
fn listing(items: &[String]) -> String {
    const SHOWN: usize = 5;
    let mut s = items
        .iter()
        .take(SHOWN)
        .cloned()
        .collect::<Vec<_>>()
        .join(", ");
    if items.len() > SHOWN {
        s.push_str(&format!(" and {} more", items.len() - SHOWN));
    }
    s
}
