//! Writing a study's results directory, all-or-nothing: everything is written into a temporary
//! directory beside the target, which is renamed onto the target only when complete.
//!
//! Contents:
//! - `summary.json`: [`crate::study::Summary`] (a `stages` array and the paper comparison);
//! - `stages.csv`: one row per stage with the summary numbers (the `dte_*` columns empty when
//!   dynamics are off);
//! - `wear.csv`: `mesh_angle_deg` and `wear_um_<H>h` for every stage;
//! - `te_mesh_cycle.csv`: per stage and crank angle, forward and reverse STE, lost motion and
//!   loaded TE (arcmin) over one mesh cycle;
//! - `te_revolution.csv`: `input_deg` and `ste_arcmin_<H>h` for every stage over one output
//!   revolution;
//! - `load.csv`: per stage, the pin forces, pressures and half-widths at the crank angle of the
//!   largest force;
//! - `profiles/worn_<H>h.dxf` (and `.csv`): the profile used for TE at every stage;
//! - `plots/*.svg`, `plots/*.png`: see [`crate::output::plot`].

pub mod export;
pub mod html;
pub mod plot;

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::output::export::{write_profile_sampled, ProfileFormat, EXPORT_POINTS_PER_TOOTH};
use crate::study::Study;
use crate::te::over_revolution;
use crate::units::ARCMIN_PER_RAD;

fn csv_err(path: &Path) -> impl Fn(csv::Error) -> Error + '_ {
    move |e| Error::io(path, std::io::Error::other(e.to_string()))
}

fn write_rows(path: &Path, header: &[String], rows: &[Vec<String>]) -> Result<()> {
    let mut w = csv::Writer::from_path(path).map_err(csv_err(path))?;
    w.write_record(header).map_err(csv_err(path))?;
    for r in rows {
        w.write_record(r).map_err(csv_err(path))?;
    }
    w.flush().map_err(|e| Error::io(path, e))
}

/// Writes `value` as pretty JSON with a final newline.
fn write_json(path: &Path, value: &impl serde::Serialize) -> Result<()> {
    let text = serde_json::to_string_pretty(value)
        .map_err(|e| Error::io(path, std::io::Error::other(e.to_string())))?;
    std::fs::write(path, text + "\n").map_err(|e| Error::io(path, e))
}

fn f(v: f64) -> String {
    format!("{v:.6}")
}

fn hours_tag(h: f64) -> String {
    if h.fract() == 0.0 {
        format!("{h:.0}h")
    } else {
        format!("{h}h").replace('.', "p")
    }
}

/// Writes all result files of `study` into the existing, empty directory `dir`, ending with
/// `report.html` ([`crate::output::html::write_report`]).
///
/// # Errors
/// [`Error::Io`] on any write failure.
pub fn write_files(study: &Study, dir: &Path) -> Result<()> {
    let summary = study.summary();
    write_json(&dir.join("summary.json"), &summary)?;

    // stages.csv: every quantity of the table.
    let (header, rows) = crate::quantities::stages_csv(&summary.stages);
    write_rows(&dir.join("stages.csv"), &header, &rows)?;

    // wear.csv
    let tags: Vec<String> = study.stages.iter().map(|s| hours_tag(s.hours)).collect();
    let mut header = vec!["mesh_angle_deg".to_string()];
    header.extend(tags.iter().map(|t| format!("wear_um_{t}")));
    let angles = study.wear.angles();
    let rows: Vec<Vec<String>> = angles
        .iter()
        .enumerate()
        .map(|(m, a)| {
            let mut r = vec![f(a.to_degrees())];
            r.extend(study.wear.maps.iter().map(|map| f(map[m] * 1e6)));
            r
        })
        .collect();
    write_rows(&dir.join("wear.csv"), &header, &rows)?;

    // te_mesh_cycle.csv
    let header: Vec<String> = [
        "hours",
        "crank_deg",
        "input_deg",
        "ste_forward_arcmin",
        "ste_reverse_arcmin",
        "backlash_arcmin",
        "loaded_te_arcmin",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let ratio = study.model.reducer.ratio;
    let zc = study.model.cycloid.geometry.disc_teeth() as f64;
    let mut rows = Vec::new();
    for s in &study.stages {
        for k in 0..s.ste.crank_angle.len() {
            let phi = s.ste.crank_angle[k];
            rows.push(vec![
                f(s.hours),
                f(phi.to_degrees()),
                f((ratio * phi / zc).to_degrees()),
                f(s.ste.forward[k] * ARCMIN_PER_RAD),
                f(s.ste.reverse[k] * ARCMIN_PER_RAD),
                f((s.ste.forward[k] + s.ste.reverse[k]) * ARCMIN_PER_RAD),
                f(s.loaded.te[k] * ARCMIN_PER_RAD),
            ]);
        }
    }
    write_rows(&dir.join("te_mesh_cycle.csv"), &header, &rows)?;

    // te_revolution.csv
    let pins = study.model.cycloid.geometry.pins;
    let curves: Vec<(Vec<f64>, Vec<f64>)> = study
        .stages
        .iter()
        .map(|s| over_revolution(&s.ste.crank_angle, &s.ste.forward, pins, ratio))
        .collect();
    let mut header = vec!["input_deg".to_string()];
    header.extend(tags.iter().map(|t| format!("ste_arcmin_{t}")));
    let rows: Vec<Vec<String>> = (0..curves[0].0.len())
        .map(|i| {
            let mut r = vec![format!("{:.4}", curves[0].0[i])];
            r.extend(
                curves
                    .iter()
                    .map(|c| format!("{:.5}", c.1[i] * ARCMIN_PER_RAD)),
            );
            r
        })
        .collect();
    write_rows(&dir.join("te_revolution.csv"), &header, &rows)?;

    // hysteresis.csv: the curve of every stage, averaged over a mesh cycle.
    let header: Vec<String> = ["hours", "torque_nm", "twist_arcmin"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let mut rows = Vec::new();
    for s in &study.stages {
        let c = s.hysteresis.curve();
        for (t, x) in c.torque.iter().zip(&c.twist) {
            rows.push(vec![f(s.hours), f(*t), f(x * ARCMIN_PER_RAD)]);
        }
    }
    write_rows(&dir.join("hysteresis.csv"), &header, &rows)?;

    // load.csv
    let header: Vec<String> = [
        "hours",
        "crank_deg",
        "disc",
        "pin",
        "mesh_angle_deg",
        "gap_um",
        "force_n",
        "lever_arm_mm",
        "half_width_um",
        "max_pressure_mpa",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let mut rows = Vec::new();
    for s in &study.stages {
        let w = s.loaded.worst();
        for (d, p) in w
            .discs
            .iter()
            .enumerate()
            .flat_map(|(d, disc)| disc.pins.iter().map(move |p| (d, p)))
        {
            rows.push(vec![
                f(s.hours),
                f(w.crank_angle.to_degrees()),
                (d + 1).to_string(),
                p.pin.to_string(),
                f(p.mesh_angle.to_degrees()),
                f(p.gap * 1e6),
                f(p.force),
                f(p.lever_arm * 1e3),
                f(p.half_width * 1e6),
                f(p.max_pressure * 1e-6),
            ]);
        }
    }
    write_rows(&dir.join("load.csv"), &header, &rows)?;

    // te_flexible.csv (flexible disc on)
    if study.stages.iter().any(|s| s.flexible.is_some()) {
        let header: Vec<String> = [
            "hours",
            "crank_deg",
            "rigid_ste_arcmin",
            "rigid_loaded_te_arcmin",
            "flexible_ste_arcmin",
            "flexible_loaded_te_arcmin",
            "max_force_n",
            "rigid_ste_reverse_arcmin",
            "flexible_ste_reverse_arcmin",
            "flexible_loaded_te_reverse_arcmin",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        let mut rows = Vec::new();
        for s in &study.stages {
            if let Some((fl, _)) = &s.flexible {
                for k in 0..fl.crank_angle.len() {
                    rows.push(vec![
                        f(s.hours),
                        f(fl.crank_angle[k].to_degrees()),
                        f(fl.rigid_ste[k] * ARCMIN_PER_RAD),
                        f(fl.rigid_loaded_te[k] * ARCMIN_PER_RAD),
                        f(fl.flexible_ste[k] * ARCMIN_PER_RAD),
                        f(fl.flexible_loaded_te[k] * ARCMIN_PER_RAD),
                        f(fl.max_force[k]),
                        f(fl.rigid_ste_reverse[k] * ARCMIN_PER_RAD),
                        f(fl.flexible_ste_reverse[k] * ARCMIN_PER_RAD),
                        f(fl.flexible_loaded_te_reverse[k] * ARCMIN_PER_RAD),
                    ]);
                }
            }
        }
        write_rows(&dir.join("te_flexible.csv"), &header, &rows)?;
        // hysteresis_flexible.csv: the flexible hysteresis curve of every stage.
        let header: Vec<String> = ["hours", "torque_nm", "twist_arcmin"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let mut rows = Vec::new();
        for s in &study.stages {
            if let Some((fl, _)) = &s.flexible {
                for (t, w) in fl.hysteresis_torque.iter().zip(&fl.hysteresis_twist) {
                    rows.push(vec![f(s.hours), f(*t), f(w * ARCMIN_PER_RAD)]);
                }
            }
        }
        write_rows(&dir.join("hysteresis_flexible.csv"), &header, &rows)?;
    }

    // Profiles and plots are independent: write them side by side.
    let pdir = dir.join("profiles");
    std::fs::create_dir(&pdir).map_err(|e| Error::io(&pdir, e))?;
    let plots = dir.join("plots");
    std::fs::create_dir(&plots).map_err(|e| Error::io(&plots, e))?;
    let (profiles, figures) = rayon::join(
        || -> Result<()> {
            study
                .stages
                .par_iter()
                .zip(tags.par_iter())
                .try_for_each(|(s, tag)| {
                    for (ext, format) in [("dxf", ProfileFormat::Dxf), ("csv", ProfileFormat::Csv)]
                    {
                        write_profile_sampled(
                            &s.profile,
                            &pdir.join(format!("worn_{tag}.{ext}")),
                            format,
                            EXPORT_POINTS_PER_TOOTH,
                        )?;
                    }
                    Ok(())
                })
        },
        || crate::output::plot::write_all(study, &plots),
    );
    profiles?;
    figures?;
    crate::output::html::write_report(study, &summary, dir)
}

/// Writes the results of `study` to `out` atomically: into a temporary directory beside `out`,
/// then renamed. If `out` exists it must be empty, unless `replace` is set, in which case the old
/// directory is replaced only after the new one is complete.
///
/// # Errors
/// [`Error::Invalid`] if `out` exists (non-empty) and `replace` is false; [`Error::Io`] on write
/// failures (the temporary directory is removed, `out` is untouched).
pub fn write_study(study: &Study, out: &Path, replace: bool) -> Result<PathBuf> {
    write_atomically(out, replace, |dir| write_files(study, dir))
}

/// Writes a dynamic simulation's results directory all-or-nothing (like [`write_study`]):
/// `summary.json` ([`crate::dynamics::DynamicsSummary`]), `dynamics.csv` (the time series),
/// `pin_forces.csv` (if computed: `time_s`, `disc<d>_pin<j>_n`), and `plots/speeds` and
/// `plots/te` (SVG and PNG).
///
/// # Errors
/// As [`write_study`].
pub fn write_dynamics(
    res: &crate::dynamics::DynamicsResult,
    out: &Path,
    replace: bool,
) -> Result<PathBuf> {
    write_atomically(out, replace, |dir| write_dynamics_files(res, dir))
}

/// The files of [`write_dynamics`], written into the existing directory `dir`.
///
/// # Errors
/// [`Error::Io`] on write failures.
pub fn write_dynamics_files(res: &crate::dynamics::DynamicsResult, dir: &Path) -> Result<()> {
    {
        write_json(&dir.join("summary.json"), &res.summary)?;
        let p = dir.join("dynamics.csv");
        let header: Vec<String> = [
            "time_s",
            "input_angle_deg",
            "output_angle_deg",
            "input_speed_deg_s",
            "output_speed_deg_s",
            "te_arcmin",
            "load_nm",
            "pins_in_contact_disc1",
            "pins_in_contact_disc2",
            "max_pin_force_n",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        let rows: Vec<Vec<String>> = res
            .samples
            .iter()
            .map(|s| {
                vec![
                    format!("{:.7}", s.time_s),
                    format!("{:.9}", s.input_angle_deg),
                    format!("{:.9}", s.output_angle_deg),
                    f(s.input_speed_deg_s),
                    f(s.output_speed_deg_s),
                    f(s.te_arcmin),
                    f(s.load_nm),
                    s.pins_in_contact[0].to_string(),
                    s.pins_in_contact[1].to_string(),
                    f(s.max_pin_force_n),
                ]
            })
            .collect();
        write_rows(&p, &header, &rows)?;
        if let Some(forces) = &res.pin_forces {
            let zp = forces.first().map_or(0, |r| r.len() / 2);
            let p = dir.join("pin_forces.csv");
            let mut header = vec!["time_s".to_string()];
            for d in 1..=2 {
                header.extend((0..zp).map(|j| format!("disc{d}_pin{j}_n")));
            }
            let rows: Vec<Vec<String>> = res
                .samples
                .iter()
                .zip(forces)
                .map(|(s, r)| {
                    std::iter::once(format!("{:.7}", s.time_s))
                        .chain(r.iter().map(|v| format!("{v:.3}")))
                        .collect()
                })
                .collect();
            write_rows(&p, &header, &rows)?;
        }
        let plots = dir.join("plots");
        std::fs::create_dir_all(&plots).map_err(|e| Error::io(&plots, e))?;
        crate::output::plot::dynamics(res, &plots)
    }
}

/// Runs `write` on a fresh temporary directory beside `out` and renames it onto `out` when it
/// succeeds ([`Staging::prepare`] then [`Staging::commit`]); on failure the temporary directory
/// is removed and `out` is untouched.
///
/// # Errors
/// As [`Staging::prepare`] and [`Staging::commit`]; any error of `write`.
pub fn write_atomically(
    out: &Path,
    replace: bool,
    write: impl FnOnce(&Path) -> Result<()>,
) -> Result<PathBuf> {
    Staging::prepare(out, replace)?.commit(write)
}

/// Name of the marker file in every results directory rvlife writes: `--force` replaces only a
/// directory that has it.
pub const MARKER: &str = ".rvlife-results";

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

/// Removes every temporary output of this process that is not yet in place (a signal handler
/// calls it before the process exits, so that an interrupted run leaves nothing behind).
pub fn remove_pending() {
    let list = std::mem::take(&mut *pending());
    for p in list {
        // Twice: a writer thread may add a file while the first pass runs.
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
    /// Checks `out` ([`check_output_dir`]), creates its folder if missing, removes temporary
    /// directories of dead runs beside it, and creates this run's temporary directory there.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `--out` (see [`check_output_dir`], and a folder that cannot be
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

    /// Runs `write` on the temporary directory, adds the [`MARKER`] file, and renames the
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
        std::fs::write(
            &marker,
            format!(
                "rvlife {} results directory; `rvlife run --force` may replace it\n",
                env!("CARGO_PKG_VERSION")
            ),
        )
        .map_err(|e| Error::io(&marker, e))?;
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
                let _ = std::fs::remove_dir_all(&old);
                unregister(&old);
                return Ok(out);
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

/// Checks that the file `out` can be written: not a directory, in a folder that exists, and
/// absent unless `replace`.
///
/// # Errors
/// [`Error::Invalid`] naming `--out`.
pub fn check_output_file(out: &Path, replace: bool) -> Result<()> {
    if out.is_dir() {
        return Err(Error::invalid(
            "--out",
            out.display(),
            "is a directory; name a file",
        ));
    }
    let parent = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
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
    Ok(())
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
            if !out.join(MARKER).is_file() {
                return Err(Error::invalid(
                    "--out",
                    out.display(),
                    format!(
                        "is not a results directory of rvlife (it has no {MARKER} file); \
                         --force replaces only those, so this directory is left as it is: \
                         choose another"
                    ),
                ));
            }
        }
    }
    Ok(())
}
