//! Safe output: every file the library or the CLI writes goes through [`write_atomic`].
//!
//! The bytes are written to a temporary file next to the target (same directory, so the
//! final rename cannot cross file systems) and then renamed over the target. A reader, or a
//! crash of this process halfway through, therefore sees either the old file or the whole
//! new one, never a truncated mix. On any failure the temporary file is removed.
//!
//! Limits: the data is not `fsync`ed, so a power loss right after the rename may still lose
//! the new content on some file systems (the cost of an fsync per file would dominate batch
//! runs over many small glyphs). Folders are never created here: a missing output folder is
//! reported as an error, usually a typo the user wants to hear about. The path `-`
//! (standard output) is the CLI's business, not this module's.

use crate::error::{Error, Result};
use std::fs::{self, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// Distinguishes temporary files of concurrent writes within one process.
static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// The temporary files being written right now, for [`remove_live_temporaries`].
static LIVE_TEMPS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The longest file name (in bytes) that common file systems accept.
const NAME_MAX: usize = 255;

/// The temporary file's name for an output named `name`: `name` + `TEMP_MARK` +
/// `<pid>-<n>`, with `name` shortened (at a character boundary) when the whole would pass
/// [`NAME_MAX`], so that every output name the file system accepts can be written.
fn temp_name(name: &std::ffi::OsStr) -> std::ffi::OsString {
    let suffix = format!(
        "{TEMP_MARK}{}-{}",
        std::process::id(),
        TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
    );
    let keep = NAME_MAX.saturating_sub(suffix.len());
    let mut temp = if name.len() <= keep {
        name.to_os_string()
    } else {
        let lossy = name.to_string_lossy();
        let mut end = keep.min(lossy.len());
        while !lossy.is_char_boundary(end) {
            end -= 1;
        }
        std::ffi::OsString::from(&lossy[..end])
    };
    temp.push(suffix);
    temp
}

/// What every temporary file's name contains: `<name>` + `TEMP_MARK` + `<pid>-<n>`.
pub(crate) const TEMP_MARK: &str = ".outlinefit-tmp-";

/// Writes `bytes` to `path` atomically: to a temporary file `<name>.outlinefit-tmp-<pid>-<n>`
/// in the same directory, then renamed over `path`, replacing an existing regular file
/// whole (its permissions are kept).
///
/// Only regular files are written: a `path` that exists as anything else (a symbolic link,
/// a device such as `/dev/null`, a FIFO, a folder) is refused, since the rename would
/// replace it. To write through a link, resolve it first.
///
/// Errors: [`Error::Write`] naming `path` when the parent folder does not exist, `path` has
/// no file name or is not a regular file, or any step fails; the temporary file is removed
/// in every failure case.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

/// [`write_atomic`] for content produced piece by piece: `fill` writes into a buffered
/// temporary file, so a large document (a report of many contours) never needs to be held
/// in memory whole. Same rules and errors; an error from `fill` removes the temporary and
/// leaves `path` as it was.
pub fn write_atomic_with<F>(path: &Path, fill: F) -> Result<()>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    let fail = |source: io::Error| Error::Write {
        path: path.to_path_buf(),
        source,
    };
    let Some(name) = path.file_name() else {
        return Err(fail(io::Error::new(
            io::ErrorKind::InvalidInput,
            "the output path does not name a file",
        )));
    };
    let dir = parent_dir(path);
    ensure_output_dir_exists(dir).map_err(|e| match e {
        Error::Write { source, .. } => fail(source),
        other => other,
    })?;
    check_replaceable(path).map_err(fail)?;
    let temp = dir.join(temp_name(name));
    track(&temp, true);
    let result = write_new(&temp, fill).and_then(|()| {
        if let Ok(meta) = fs::metadata(path) {
            // Best effort: a replaced file keeps its permissions.
            let _ = fs::set_permissions(&temp, meta.permissions());
        }
        fs::rename(&temp, path)
    });
    let result = result.map_err(|source| {
        // The temporary may or may not exist, depending on which step failed.
        let _ = fs::remove_file(&temp);
        fail(source)
    });
    track(&temp, false);
    result
}

/// Refuses a target that exists and is not a regular file.
pub fn check_replaceable(path: &Path) -> io::Result<()> {
    let meta = match fs::symlink_metadata(path) {
        Ok(meta) => meta,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(e),
    };
    let what = file_kind(&meta.file_type());
    if what == "regular file" {
        return Ok(());
    }
    Err(io::Error::new(
        io::ErrorKind::InvalidInput,
        format!("it is a {what}, not a regular file; outputs never replace one"),
    ))
}

/// A file type in words.
pub fn file_kind(t: &fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "FIFO";
        }
        if t.is_char_device() || t.is_block_device() {
            return "device";
        }
        if t.is_socket() {
            return "socket";
        }
    }
    if t.is_symlink() {
        "symbolic link"
    } else if t.is_dir() {
        "folder"
    } else if t.is_file() {
        "regular file"
    } else {
        "special file"
    }
}

/// Adds (`live`) or removes a temporary file from the registry of those being written.
fn track(temp: &Path, live: bool) {
    let mut temps = LIVE_TEMPS.lock().unwrap_or_else(|e| e.into_inner());
    if live {
        temps.push(temp.to_path_buf());
    } else {
        temps.retain(|t| t != temp);
    }
}

/// Removes every temporary file this process is writing: for a signal handler that is
/// about to end the process, so that an interrupted run leaves no debris.
pub fn remove_live_temporaries() {
    let temps = LIVE_TEMPS.lock().unwrap_or_else(|e| e.into_inner());
    for t in temps.iter() {
        let _ = fs::remove_file(t);
    }
}

/// Removes the temporary files that an earlier run killed mid-write left in `dir` (names
/// containing the temporary mark (`.outlinefit-tmp-`) of a process that no longer runs; on systems without `/proc`,
/// of any other process). Returns how many were removed.
pub fn remove_stale_temporaries(dir: &Path) -> usize {
    let Ok(entries) = fs::read_dir(dir) else {
        return 0;
    };
    let me = std::process::id();
    let proc_fs = Path::new("/proc/self").exists();
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let Some((_, tail)) = name.rsplit_once(TEMP_MARK) else {
            continue;
        };
        let Some(pid) = tail.split('-').next().and_then(|p| p.parse::<u32>().ok()) else {
            continue;
        };
        let running = pid == me || (proc_fs && Path::new(&format!("/proc/{pid}")).exists());
        let regular = entry.file_type().is_ok_and(|t| t.is_file());
        if !running && regular && fs::remove_file(entry.path()).is_ok() {
            removed += 1;
        }
    }
    removed
}

/// Checks that the folder `dir` exists and is a folder, so that a run can fail before doing
/// any work. An empty path means the current directory. For an output file, pass its
/// folder: `Path::parent`, which is empty for a bare file name.
///
/// Errors: [`Error::Write`] naming `dir`, with a `NotFound` or `NotADirectory` source.
pub fn ensure_output_dir_exists(dir: &Path) -> Result<()> {
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    let fail = |source: io::Error| Error::Write {
        path: dir.to_path_buf(),
        source,
    };
    match fs::metadata(dir) {
        Ok(meta) if meta.is_dir() => Ok(()),
        Ok(_) => Err(fail(io::Error::new(
            io::ErrorKind::NotADirectory,
            "not a folder",
        ))),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Err(fail(io::Error::new(
            io::ErrorKind::NotFound,
            "the output folder does not exist (it is not created automatically)",
        ))),
        Err(e) => Err(fail(e)),
    }
}

/// The folder holding `path`; `.` for a bare file name.
fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Creates `temp` (which must not exist yet) and lets `fill` write into it, buffered.
fn write_new<F>(temp: &Path, fill: F) -> io::Result<()>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    let file = OpenOptions::new().write(true).create_new(true).open(temp)?;
    let mut out = io::BufWriter::with_capacity(1 << 16, file);
    fill(&mut out)?;
    out.flush()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    #[test]
    fn an_output_name_of_250_bytes_is_written() {
        // The temporary's suffix must not push a name the file system accepts past its
        // 255-byte limit (it did: "File name too long").
        let dir = scratch("longname");
        for name in ["a".repeat(251) + ".svg", "é".repeat(123) + ".svg"] {
            assert!(
                name.len() >= 250 && name.len() <= NAME_MAX,
                "{}",
                name.len()
            );
            let path = dir.join(&name);
            write_atomic(&path, b"<svg/>").unwrap();
            assert_eq!(fs::read(&path).unwrap(), b"<svg/>");
            let temp = temp_name(std::ffi::OsStr::new(&name));
            assert!(temp.len() <= NAME_MAX && temp.to_string_lossy().contains(TEMP_MARK));
        }
        // Nothing but the two outputs is left behind.
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 2);
        let _ = fs::remove_dir_all(&dir);
    }

    /// A fresh, empty folder under the system temp dir, unique per test.
    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("outlinefit-io-{}-{}", name, std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn writes_and_replaces_whole_file_without_leftovers() {
        let dir = scratch("replace");
        let target = dir.join("out.svg");
        write_atomic(&target, b"a long first version of the file").unwrap();
        assert_eq!(
            fs::read(&target).unwrap(),
            b"a long first version of the file"
        );
        write_atomic(&target, b"short").unwrap();
        // Replaced whole: no tail of the longer old content survives.
        assert_eq!(fs::read(&target).unwrap(), b"short");
        assert_eq!(entries(&dir), vec!["out.svg".to_string()]);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn missing_folder_is_a_write_error_and_is_not_created() {
        let dir = scratch("missing");
        let target = dir.join("no-such-folder").join("out.svg");
        match write_atomic(&target, b"x") {
            Err(Error::Write { path, source }) => {
                assert_eq!(path, target);
                assert_eq!(source.kind(), io::ErrorKind::NotFound);
            }
            other => panic!("expected Error::Write, got {other:?}"),
        }
        assert!(!dir.join("no-such-folder").exists());
        assert!(entries(&dir).is_empty());
        assert!(matches!(
            ensure_output_dir_exists(&dir.join("no-such-folder")),
            Err(Error::Write { .. })
        ));
        ensure_output_dir_exists(&dir).unwrap();
        ensure_output_dir_exists(Path::new("")).unwrap();
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn failed_rename_removes_the_temporary() {
        let dir = scratch("failed");
        // The target is a non-empty folder: the temporary is written, the rename fails.
        let target = dir.join("taken");
        fs::create_dir(&target).unwrap();
        fs::write(target.join("keep"), b"k").unwrap();
        let err = write_atomic(&target, b"data").unwrap_err();
        assert!(matches!(err, Error::Write { ref path, .. } if path == &target));
        assert_eq!(entries(&dir), vec!["taken".to_string()]);
        assert_eq!(fs::read(target.join("keep")).unwrap(), b"k");
        // A file used as a folder is reported too, and nothing is left behind.
        let file = dir.join("plain");
        fs::write(&file, b"p").unwrap();
        assert!(matches!(
            write_atomic(&file.join("out.svg"), b"x"),
            Err(Error::Write { .. })
        ));
        assert!(matches!(
            ensure_output_dir_exists(&file),
            Err(Error::Write { .. })
        ));
        assert_eq!(
            entries(&dir),
            vec!["plain".to_string(), "taken".to_string()]
        );
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn path_without_file_name_is_rejected() {
        assert!(matches!(
            write_atomic(Path::new("/"), b"x"),
            Err(Error::Write { .. })
        ));
    }

    #[test]
    fn concurrent_writes_use_distinct_temporaries() {
        let dir = scratch("concurrent");
        let handles: Vec<_> = (0..8)
            .map(|i| {
                let target = dir.join(format!("f{i}.txt"));
                std::thread::spawn(move || write_atomic(&target, format!("{i}").as_bytes()))
            })
            .collect();
        for h in handles {
            h.join().unwrap().unwrap();
        }
        assert_eq!(entries(&dir).len(), 8);
        for i in 0..8 {
            assert_eq!(
                fs::read_to_string(dir.join(format!("f{i}.txt"))).unwrap(),
                i.to_string()
            );
        }
        fs::remove_dir_all(&dir).unwrap();
    }
}
