//! Where the command line may write: regular files, standard output through `-`, never
//! two outputs of one run onto the same file.

use anyhow::{bail, Context};
use outlinefit::io::{check_replaceable, file_kind, write_atomic_with};
use std::io::Write;
use std::path::{Path, PathBuf};

/// True when `p` means standard input or output.
pub(crate) fn is_dash(p: &Path) -> bool {
    p.as_os_str() == "-"
}

/// The file an output path will replace: `p` itself, or with `follow_symlinks` the target
/// of a symbolic link. Fails, naming the path and what it is, when that is not a regular
/// file (or a file yet to be created).
pub(crate) fn resolve_output(p: &Path, follow_symlinks: bool) -> anyhow::Result<PathBuf> {
    let mut target = p.to_path_buf();
    if let Ok(meta) = std::fs::symlink_metadata(p) {
        if meta.file_type().is_symlink() {
            if !follow_symlinks {
                bail!(
                    "{} is a symbolic link; outputs never replace one (--follow-symlinks writes to its target)",
                    p.display()
                );
            }
            target = match p.canonicalize() {
                Ok(t) => t,
                // A dangling link: its target, relative to the link's folder.
                Err(_) => {
                    let link = std::fs::read_link(p)?;
                    p.parent().unwrap_or(Path::new("")).join(link)
                }
            };
        }
    }
    check_replaceable(&target).map_err(|e| anyhow::anyhow!("cannot write {}: {e}", p.display()))?;
    Ok(target)
}

/// A path's identity for comparing outputs: its folder canonicalised, and its file name.
/// Two paths with the same identity name the same file.
pub(crate) fn identity(p: &Path) -> PathBuf {
    if let Ok(c) = p.canonicalize() {
        return c;
    }
    let parent = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let dir = parent
        .canonicalize()
        .unwrap_or_else(|_| parent.to_path_buf());
    match p.file_name() {
        Some(name) => dir.join(name),
        None => dir,
    }
}

/// Refuses a list of (option, path) outputs in which two name the same file or more than
/// one is standard output (`-`), or one is the input.
pub(crate) fn check_distinct(
    outputs: &[(&str, &Path)],
    input: Option<&Path>,
) -> anyhow::Result<()> {
    let stdout: Vec<&str> = outputs
        .iter()
        .filter(|(_, p)| is_dash(p))
        .map(|(o, _)| *o)
        .collect();
    if stdout.len() > 1 {
        bail!(
            "{} would all write to standard output (-); give all but one a file",
            stdout.join(" and ")
        );
    }
    let files: Vec<(&str, &Path, PathBuf)> = outputs
        .iter()
        .filter(|(_, p)| !is_dash(p))
        .map(|(o, p)| (*o, *p, identity(p)))
        .collect();
    for (i, (oa, pa, ia)) in files.iter().enumerate() {
        if let Some(input) = input.filter(|i| !is_dash(i)) {
            if *ia == identity(input) {
                bail!("{oa} {} would overwrite the input", pa.display());
            }
        }
        for (ob, _, ib) in &files[i + 1..] {
            if ia == ib {
                bail!(
                    "{oa} and {ob} both name {}; each output needs its own file",
                    pa.display()
                );
            }
        }
    }
    Ok(())
}

/// Writes an output: to standard output for `-`, otherwise atomically to the file.
pub(crate) fn write_output<F>(target: &Path, fill: F) -> anyhow::Result<()>
where
    F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
{
    // A run interrupted while no thread waited for the signal ends before this output.
    super::interrupt::check();
    if is_dash(target) {
        write_stdout(fill)
    } else {
        Ok(write_atomic_with(target, fill)?)
    }
}

/// Lets `fill` write to standard output, failing when it is closed or the write fails (the
/// standard library's stdout quietly accepts writes to a closed descriptor).
fn write_stdout<F>(fill: F) -> anyhow::Result<()>
where
    F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
{
    #[cfg(unix)]
    {
        use std::os::fd::AsFd;
        if closed_at_start(std::io::stdout().as_fd()) {
            bail!("cannot write to standard output: it was closed when the program started");
        }
        let fd = std::io::stdout()
            .as_fd()
            .try_clone_to_owned()
            .context("cannot write to standard output (it is closed)")?;
        let mut out = std::io::BufWriter::new(std::fs::File::from(fd));
        fill(&mut out).context("cannot write to standard output")?;
        out.flush().context("cannot write to standard output")?;
        Ok(())
    }
    #[cfg(not(unix))]
    {
        let mut out = std::io::BufWriter::new(std::io::stdout().lock());
        fill(&mut out).context("cannot write to standard output")?;
        out.flush().context("cannot write to standard output")?;
        Ok(())
    }
}

/// True when descriptor `fd` is what the runtime puts in place of a standard descriptor
/// that was closed at start-up: `/dev/null` opened for reading and writing (a shell's
/// `> /dev/null` opens it write-only).
#[cfg(unix)]
#[allow(clippy::unnecessary_cast)] // st_rdev is u64 on Linux, i32 on macOS
fn closed_at_start(fd: std::os::fd::BorrowedFd<'_>) -> bool {
    use nix::fcntl::{fcntl, FcntlArg, OFlag};
    use nix::sys::stat::{fstat, SFlag};
    let (Ok(flags), Ok(st)) = (fcntl(fd, FcntlArg::F_GETFL), fstat(fd)) else {
        return false;
    };
    let mode = OFlag::from_bits_truncate(flags) & OFlag::O_ACCMODE;
    let null = std::fs::metadata("/dev/null").ok().map(|m| {
        use std::os::unix::fs::MetadataExt;
        m.rdev()
    });
    let is_char = SFlag::from_bits_truncate(st.st_mode) & SFlag::S_IFMT == SFlag::S_IFCHR;
    mode == OFlag::O_RDWR && is_char && Some(st.st_rdev as u64) == null
}

/// Describes what a path is when it is not a regular file, for input errors.
pub(crate) fn not_regular(p: &Path) -> Option<&'static str> {
    let meta = std::fs::metadata(p).ok()?;
    let kind = file_kind(&meta.file_type());
    (kind != "regular file").then_some(kind)
}
