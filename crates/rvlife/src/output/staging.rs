//! All-or-nothing outputs: a results directory is written into a temporary directory beside
//! its target and renamed onto it only when complete (a single file likewise), a `--force`
//! replaces only a directory rvlife wrote (its `MARKER`), and an interrupted run leaves
//! nothing behind ([`remove_pending`]).

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// Name of the marker file in every results directory rvlife writes: `--force` replaces only a
/// directory that has it.
pub(crate) const MARKER: &str = ".rvlife-results";

/// First words of the [`MARKER`] file; the lines after its first list the files of the
/// results directory, relative to it, `/`-separated.
const MARKER_HEADER: &str = "rvlife results directory, written by rvlife";

/// Prefix of the temporary directories and files beside an output, followed by the process id
/// of the run that owns them.
const TMP_PREFIX: &str = ".rvlife-tmp-";

/// Temporary outputs of this process not yet renamed into place, removed by
/// [`remove_pending`] (the command line calls it on SIGINT/SIGTERM).
static PENDING: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

fn pending() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    PENDING
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

fn unregister(p: &Path) {
    pending().retain(|x| x != p);
}

/// Set by [`remove_pending`]: the process is being interrupted.
static INTERRUPTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether [`remove_pending`] has started: the process is ending on a signal, so an error a
/// writer meets now (its temporary directory removed under it) is not the run's result.
pub fn interrupted() -> bool {
    INTERRUPTED.load(std::sync::atomic::Ordering::SeqCst)
}

/// Set by [`stop_on_signal`]: the next signal asks the running work to stop and keep what it
/// has (a design search), instead of ending the process.
static STOP_ON_SIGNAL: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Set by [`take_signal`] when a signal asked the running work to stop.
static STOP_REQUESTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Makes the next SIGINT/SIGTERM ask the running work to stop ([`stop_requested`]) instead
/// of ending the process; a second signal ends it as before ([`take_signal`]).
pub fn stop_on_signal(on: bool) {
    STOP_ON_SIGNAL.store(on, std::sync::atomic::Ordering::SeqCst);
}

/// Whether a signal has asked the running work to stop ([`stop_on_signal`]).
pub fn stop_requested() -> bool {
    STOP_REQUESTED.load(std::sync::atomic::Ordering::SeqCst)
}

/// What a signal handler calls first: `true` if the signal is taken as a request to stop
/// ([`stop_on_signal`] on and no request yet), so the process goes on; `false` if it should
/// end (remove the pending outputs and exit).
pub fn take_signal() -> bool {
    STOP_ON_SIGNAL.load(std::sync::atomic::Ordering::SeqCst)
        && !STOP_REQUESTED.swap(true, std::sync::atomic::Ordering::SeqCst)
}

/// Removes every temporary output of this process that is not yet in place (a signal handler
/// calls it before the process exits, so that an interrupted run leaves nothing behind).
///
/// The list stays locked when it returns, so that no writer registers a new temporary output
/// before the caller ends the process; call it only on the way out.
pub fn remove_pending() {
    INTERRUPTED.store(true, std::sync::atomic::Ordering::SeqCst);
    let mut guard = pending();
    let list = std::mem::take(&mut *guard);
    // Held until the process exits.
    std::mem::forget(guard);
    for (i, p) in list.into_iter().enumerate() {
        // Moved aside first, under a name no writer knows: the writer threads still running
        // address the output by its old path, so none can add a file to it while it is
        // removed (removed in place, a directory that a writer adds a file to between the
        // removal's listing and its last step stays behind).
        let aside = parent_of(&p).join(format!(
            "{TMP_PREFIX}{}-interrupted-{i}",
            std::process::id()
        ));
        let p = if std::fs::rename(&p, &aside).is_ok() {
            aside
        } else {
            p
        };
        // Twice: where the move failed, a writer thread may add a file while the first pass
        // runs.
        for _ in 0..2 {
            if p.is_dir() {
                let _ = std::fs::remove_dir_all(&p);
            } else {
                let _ = std::fs::remove_file(&p);
            }
        }
    }
}

/// Whether the process `pid` is alive (unix: `kill(pid, 0)`; elsewhere assumed alive).
fn alive(pid: u32) -> bool {
    #[cfg(unix)]
    {
        let Ok(pid) = libc::pid_t::try_from(pid) else {
            return false;
        };
        // SAFETY: signal 0 only checks that the process exists; nothing is sent.
        let r = unsafe { libc::kill(pid, 0) };
        r == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
    }
    #[cfg(not(unix))]
    {
        let _ = pid;
        true
    }
}

/// Removes the temporary outputs in `folder` left by runs that died (killed during their write
/// phase): `.rvlife-tmp-<pid>-*` whose process no longer exists.
fn remove_stale(folder: &Path) {
    let Ok(entries) = std::fs::read_dir(folder) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(rest) = name.to_str().and_then(|n| n.strip_prefix(TMP_PREFIX)) else {
            continue;
        };
        let Some(pid) = rest.split('-').next().and_then(|p| p.parse::<u32>().ok()) else {
            continue;
        };
        if pid != std::process::id() && !alive(pid) {
            let p = e.path();
            let _ = if p.is_dir() {
                std::fs::remove_dir_all(&p)
            } else {
                std::fs::remove_file(&p)
            };
        }
    }
}

/// Renames `from` onto `to` only if `to` does not exist, atomically where the system allows
/// (Linux `renameat2(RENAME_NOREPLACE)`); `Ok(false)` if `to` exists.
fn rename_no_replace(from: &Path, to: &Path) -> Result<bool> {
    #[cfg(target_os = "linux")]
    {
        use std::ffi::CString;
        use std::os::unix::ffi::OsStrExt;
        let c = |p: &Path| {
            CString::new(p.as_os_str().as_bytes())
                .map_err(|e| Error::io(p, std::io::Error::other(e)))
        };
        let (a, b) = (c(from)?, c(to)?);
        // SAFETY: both paths are valid NUL-terminated strings for the duration of the call.
        let r = unsafe {
            libc::renameat2(
                libc::AT_FDCWD,
                a.as_ptr(),
                libc::AT_FDCWD,
                b.as_ptr(),
                libc::RENAME_NOREPLACE,
            )
        };
        if r == 0 {
            return Ok(true);
        }
        let e = std::io::Error::last_os_error();
        match e.raw_os_error() {
            Some(libc::EEXIST) | Some(libc::ENOTEMPTY) => Ok(false),
            // File systems without the flag: check, then rename.
            Some(libc::EINVAL) | Some(libc::ENOSYS) => {
                if to.exists() {
                    Ok(false)
                } else {
                    std::fs::rename(from, to).map_err(|e| Error::io(to, e))?;
                    Ok(true)
                }
            }
            _ => Err(Error::io(to, e)),
        }
    }
    #[cfg(not(target_os = "linux"))]
    {
        if to.exists() {
            return Ok(false);
        }
        std::fs::rename(from, to).map_err(|e| Error::io(to, e))?;
        Ok(true)
    }
}

/// The folder that holds `out` (`.` for a bare name).
fn parent_of(out: &Path) -> PathBuf {
    match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// A results directory being written: a temporary directory beside the target, created before
/// any computing starts (so that an unwritable target is found at once), renamed onto the target
/// when complete. Dropped without [`Staging::commit`], it is removed.
#[derive(Debug)]
pub struct Staging {
    out: PathBuf,
    replace: bool,
    dir: Option<PathBuf>,
}

impl Staging {
    /// Checks `out` (`check_output_dir`), creates its folder if missing, removes temporary
    /// directories of dead runs beside it, and creates this run's temporary directory there.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `--out` (see `check_output_dir`, and a folder that cannot be
    /// written).
    pub fn prepare(out: &Path, replace: bool) -> Result<Staging> {
        check_output_dir(out, replace)?;
        let parent = parent_of(out);
        let unwritable = |e: std::io::Error| {
            Error::invalid(
                "--out",
                out.display(),
                format!("its folder {} cannot be written: {e}", parent.display()),
            )
        };
        std::fs::create_dir_all(&parent).map_err(unwritable)?;
        remove_stale(&parent);
        let tmp = tempfile::Builder::new()
            .prefix(&format!("{TMP_PREFIX}{}-", std::process::id()))
            .tempdir_in(&parent)
            .map_err(unwritable)?
            .keep();
        pending().push(tmp.clone());
        Ok(Staging {
            out: out.to_path_buf(),
            replace,
            dir: Some(tmp),
        })
    }

    /// Runs `write` on the temporary directory, adds the `MARKER` file, and renames the
    /// directory onto the target: without `replace`, only if the target is still absent or an
    /// empty directory (never over what another run put there meanwhile); with `replace`, the
    /// old results directory is moved aside first and removed after.
    ///
    /// # Errors
    /// Any error of `write`; [`Error::Invalid`] naming `--out` if another run wrote the target
    /// meanwhile, or it stopped being replaceable; [`Error::Io`] on file-system failures. In
    /// every case the temporary directory is removed and the target is as it was.
    pub fn commit(mut self, write: impl FnOnce(&Path) -> Result<()>) -> Result<PathBuf> {
        let dir = self
            .dir
            .clone()
            .expect("a staging directory until committed");
        write(&dir)?;
        let marker = dir.join(MARKER);
        let mut text = format!(
            "{MARKER_HEADER} {}; `--force` may replace it. Its files:\n",
            env!("CARGO_PKG_VERSION")
        );
        for f in tree_under(&dir).map_err(|e| Error::io(&dir, e))?.0 {
            text.push_str(&f);
            text.push('\n');
        }
        std::fs::write(&marker, text).map_err(|e| Error::io(&marker, e))?;
        let out = self.out.clone();
        let taken = || {
            Error::invalid(
                "--out",
                out.display(),
                "was written by another run while this one computed; nothing was replaced \
                 (choose another directory, or pass --force to replace results of rvlife)",
            )
        };
        if out.exists() {
            // Re-checked: the target may have changed while this run computed.
            check_output_dir(&out, self.replace)?;
            let empty = std::fs::read_dir(&out)
                .map_err(|e| Error::io(&out, e))?
                .next()
                .is_none();
            if empty {
                std::fs::remove_dir(&out).map_err(|_| taken())?;
            } else {
                let old = parent_of(&out).join(format!(
                    "{TMP_PREFIX}{}-old-{}",
                    std::process::id(),
                    std::time::SystemTime::now()
                        .duration_since(std::time::UNIX_EPOCH)
                        .map_or(0, |d| d.as_nanos())
                ));
                std::fs::rename(&out, &old).map_err(|e| Error::io(&out, e))?;
                pending().push(old.clone());
                if !rename_no_replace(&dir, &out)? {
                    // Another run took the name in between: put the old results back.
                    let _ = std::fs::rename(&old, &out);
                    unregister(&old);
                    return Err(taken());
                }
                self.finish();
                let removed = std::fs::remove_dir_all(&old);
                unregister(&old);
                return match removed {
                    Ok(()) => Ok(out),
                    Err(e) => Err(Error::invalid(
                        "--out",
                        out.display(),
                        format!(
                            "now holds the new results, but the old ones, moved aside to {}, \
                             could not be removed ({e}); remove that folder by hand",
                            old.display()
                        ),
                    )),
                };
            }
        }
        if !rename_no_replace(&dir, &out)? {
            return Err(taken());
        }
        self.finish();
        Ok(out)
    }

    /// The temporary directory is in place: nothing to remove any more.
    fn finish(&mut self) {
        if let Some(d) = self.dir.take() {
            unregister(&d);
        }
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if let Some(d) = self.dir.take() {
            let _ = std::fs::remove_dir_all(&d);
            unregister(&d);
        }
    }
}

/// Writes a file all-or-nothing: `write` fills a temporary file beside `out`, which is renamed
/// onto `out` (over an existing file only with `replace`; never over a file another run put
/// there meanwhile without it). The temporary file is removed on failure or on a signal
/// ([`remove_pending`]).
///
/// # Errors
/// As [`check_output_file`]; [`Error::Invalid`] naming `--out` if another run wrote `out`
/// meanwhile; any error of `write`.
pub fn write_file_atomically(
    out: &Path,
    replace: bool,
    write: impl FnOnce(&Path) -> Result<()>,
) -> Result<()> {
    check_output_file(out, replace)?;
    let parent = parent_of(out);
    remove_stale(&parent);
    let ext = out
        .extension()
        .and_then(|e| e.to_str())
        .map_or(String::new(), |e| format!(".{e}"));
    let tmp = tempfile::Builder::new()
        .prefix(&format!("{TMP_PREFIX}{}-", std::process::id()))
        .suffix(&ext)
        .tempfile_in(&parent)
        .map_err(|e| {
            Error::invalid(
                "--out",
                out.display(),
                format!("its folder {} cannot be written: {e}", parent.display()),
            )
        })?
        .into_temp_path();
    let path = tmp.to_path_buf();
    pending().push(path.clone());
    let result = write(&path).and_then(|()| {
        if replace {
            std::fs::rename(&path, out).map_err(|e| Error::io(out, e))
        } else if rename_no_replace(&path, out)? {
            Ok(())
        } else {
            Err(Error::invalid(
                "--out",
                out.display(),
                "was written by another run meanwhile; pass --force to replace it",
            ))
        }
    });
    // Renamed: nothing left to remove; otherwise the temporary file goes with `tmp`.
    if result.is_ok() {
        let _ = tmp.keep();
    }
    unregister(&path);
    result
}

/// The tree under `dir`: its files (recursively; the marker itself excluded), relative to it,
/// `/`-separated, sorted, symbolic links counted as files and not followed; and its folders,
/// `dir` first.
fn tree_under(dir: &Path) -> std::io::Result<(Vec<String>, Vec<PathBuf>)> {
    fn walk(
        root: &Path,
        dir: &Path,
        files: &mut Vec<String>,
        folders: &mut Vec<PathBuf>,
    ) -> std::io::Result<()> {
        folders.push(dir.to_path_buf());
        for e in std::fs::read_dir(dir)? {
            let e = e?;
            let p = e.path();
            if e.file_type()?.is_dir() {
                walk(root, &p, files, folders)?;
            } else {
                let rel = p.strip_prefix(root).unwrap_or(&p);
                let name: Vec<String> = rel
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect();
                files.push(name.join("/"));
            }
        }
        Ok(())
    }
    let (mut files, mut folders) = (Vec::new(), Vec::new());
    walk(dir, dir, &mut files, &mut folders)?;
    files.retain(|f| f != MARKER);
    files.sort();
    Ok((files, folders))
}

/// `ELOOP`: too many levels of symbolic links.
#[cfg(unix)]
const ELOOP: i32 = libc::ELOOP;
#[cfg(not(unix))]
const ELOOP: i32 = -1;

/// Refuses an output path whose last component is a symbolic link, saying what it is: a loop,
/// a link to nothing, or a link (rvlife renames the finished output onto the name, which would
/// replace the link, not what it points to).
fn check_not_a_link(out: &Path) -> Result<()> {
    let Ok(meta) = std::fs::symlink_metadata(out) else {
        return Ok(());
    };
    if !meta.file_type().is_symlink() {
        return Ok(());
    }
    let to = std::fs::read_link(out).map_or_else(|_| "?".to_string(), |t| t.display().to_string());
    let what = match std::fs::metadata(out) {
        Ok(_) => format!(
            "is a symbolic link (to {to}); rvlife renames its finished output onto this name, \
             which would replace the link and not write where it points: name the target itself"
        ),
        Err(e) if e.raw_os_error() == Some(ELOOP) => format!(
            "is a symbolic link that loops (to {to}, which leads back to it); name a real path"
        ),
        Err(_) => format!("is a symbolic link to {to}, which does not exist; name a real path"),
    };
    Err(Error::invalid("--out", out.display(), what))
}

/// Whether this process may create and remove entries in `dir` (`access(W_OK | X_OK)`; a
/// read-only file system or an unwritable folder fails it; elsewhere assumed).
fn writable(dir: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt;
        let Ok(c) = std::ffi::CString::new(dir.as_os_str().as_bytes()) else {
            return false;
        };
        // SAFETY: `c` is a valid NUL-terminated string for the duration of the call.
        unsafe { libc::access(c.as_ptr(), libc::W_OK | libc::X_OK) == 0 }
    }
    #[cfg(not(unix))]
    {
        let _ = dir;
        true
    }
}

/// Checks that the file `out` can be written: not a directory or a symbolic link, in a folder
/// that exists and can be written, and absent unless `replace`.
///
/// # Errors
/// [`Error::Invalid`] naming `--out`.
pub fn check_output_file(out: &Path, replace: bool) -> Result<()> {
    check_not_a_link(out)?;
    if out.is_dir() {
        return Err(Error::invalid(
            "--out",
            out.display(),
            "is a directory; name a file",
        ));
    }
    let parent = parent_of(out);
    if !parent.is_dir() {
        return Err(Error::invalid(
            "--out",
            out.display(),
            "its folder does not exist",
        ));
    }
    if out.exists() && !replace {
        return Err(Error::invalid(
            "--out",
            out.display(),
            "exists; pass --force to replace it",
        ));
    }
    if !writable(&parent) {
        return Err(Error::invalid(
            "--out",
            out.display(),
            format!("its folder {} cannot be written", parent.display()),
        ));
    }
    Ok(())
}

/// Checks that the non-empty directory `out` holds results of rvlife and nothing else, and
/// that this process can remove them: its [`MARKER`] file (a regular file with rvlife's
/// header) lists every file in it, and it and every folder in it can be written.
///
/// # Errors
/// [`Error::Invalid`] naming `--out`.
fn check_own_results(out: &Path) -> Result<()> {
    let refuse = |why: String| {
        Error::invalid(
            "--out",
            out.display(),
            format!(
                "{why}; --force replaces only results directories of rvlife that hold nothing \
                 else, so this directory is left as it is: choose another"
            ),
        )
    };
    let marker = out.join(MARKER);
    let listed: Vec<String> = match crate::input::read_text(&marker) {
        Ok(text) if text.starts_with(MARKER_HEADER) => {
            text.lines().skip(1).map(str::to_string).collect()
        }
        Ok(_) => {
            return Err(refuse(format!(
                "is not a results directory of rvlife (its {MARKER} file was not written by \
                 rvlife, or by a version that did not list its files)"
            )))
        }
        Err(_) => {
            return Err(refuse(format!(
                "is not a results directory of rvlife (it has no {MARKER} file)"
            )))
        }
    };
    let (present, folders) = tree_under(out).map_err(|e| Error::io(out, e))?;
    if let Some(extra) = present.iter().find(|f| !listed.contains(f)) {
        return Err(refuse(format!(
            "holds {extra}, which the run that wrote it did not write"
        )));
    }
    match folders.iter().find(|d| !writable(d)) {
        None => Ok(()),
        Some(d) => Err(Error::invalid(
            "--out",
            out.display(),
            format!(
                "holds results this user cannot remove ({} cannot be written); nothing was \
                 replaced",
                d.display()
            ),
        )),
    }
}

/// Checks that `out` can receive results: absent, an empty directory, or (with `replace`) a
/// results directory that rvlife wrote (it holds the [`MARKER`] file). The current folder, a
/// folder that holds it, and `.`/`..` are refused, as is a directory of other files: `--force`
/// never deletes what rvlife did not write.
///
/// # Errors
/// [`Error::Invalid`] naming `--out`.
pub fn check_output_dir(out: &Path, replace: bool) -> Result<()> {
    let last = out.components().next_back();
    if matches!(
        last,
        None | Some(std::path::Component::CurDir)
            | Some(std::path::Component::ParentDir)
            | Some(std::path::Component::RootDir)
            | Some(std::path::Component::Prefix(_))
    ) {
        return Err(Error::invalid(
            "--out",
            out.display(),
            "names the current, a parent or the root folder; name a results directory",
        ));
    }
    check_not_a_link(out)?;
    if out.exists() {
        if !out.is_dir() {
            return Err(Error::invalid(
                "--out",
                out.display(),
                "exists and is not a directory",
            ));
        }
        if let (Ok(target), Ok(here)) = (out.canonicalize(), std::env::current_dir()) {
            if here.starts_with(&target) {
                return Err(Error::invalid(
                    "--out",
                    out.display(),
                    "is the current folder or holds it; name a results directory",
                ));
            }
        }
        let empty = std::fs::read_dir(out)
            .map_err(|e| Error::io(out, e))?
            .next()
            .is_none();
        if !empty {
            if !replace {
                return Err(Error::invalid(
                    "--out",
                    out.display(),
                    "exists and is not empty; pass --force to replace results of rvlife",
                ));
            }
            check_own_results(out)?;
        }
    }
    Ok(())
}
