//! Helpers shared by the command-line test binaries.

use std::process::{Command, Output};

use serde_json::Value;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs rvlife, killing it after `secs` seconds (a watchdog thread; the output is read as it
/// comes, so a large output cannot block the child): a hang fails the test instead of
/// stalling it.
pub fn rvlife_within<I, S>(secs: u64, args: I) -> Output
where
    I: IntoIterator<Item = S>,
    S: AsRef<std::ffi::OsStr>,
{
    use std::process::Stdio;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    let child = Command::new(env!("CARGO_BIN_EXE_rvlife"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("cannot start the rvlife binary");
    let pid = child.id();
    let done = Arc::new(AtomicBool::new(false));
    let killed = Arc::new(AtomicBool::new(false));
    let (d, k) = (done.clone(), killed.clone());
    std::thread::spawn(move || {
        let start = std::time::Instant::now();
        while !d.load(Ordering::SeqCst) {
            if start.elapsed().as_secs() >= secs {
                k.store(true, Ordering::SeqCst);
                #[cfg(unix)]
                // SAFETY: kills our own child process, still unreaped (done is false).
                unsafe {
                    libc::kill(pid as libc::pid_t, libc::SIGKILL);
                }
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
    });
    let o = child.wait_with_output().expect("output");
    done.store(true, Ordering::SeqCst);
    assert!(
        !killed.load(Ordering::SeqCst),
        "rvlife did not finish within {secs} s (hang)\nstderr:\n{}",
        stderr(&o)
    );
    o
}

/// Walks a JSON tree and fails on any null (serde_json writes non-finite floats as null) or
/// non-finite number.
pub fn assert_all_finite(v: &Value, path: &str) {
    match v {
        Value::Null => panic!("null (NaN or infinity?) at {path}"),
        Value::Number(n) => {
            let x = n.as_f64().unwrap_or(f64::NAN);
            assert!(x.is_finite(), "non-finite number at {path}: {n}");
        }
        Value::String(s) => {
            let l = s.to_ascii_lowercase();
            assert!(
                l != "nan" && !l.contains("inf"),
                "non-finite string at {path}: {s}"
            );
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                assert_all_finite(x, &format!("{path}[{i}]"));
            }
        }
        Value::Object(o) => {
            for (k, x) in o {
                assert_all_finite(x, &format!("{path}.{k}"));
            }
        }
        Value::Bool(_) => {}
    }
}
