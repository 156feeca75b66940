//! Reading the user's input files (configs, duty cycles, load tables, measured profiles and
//! measurements, Monte Carlo shards): only regular files of at most [`MAX_INPUT_BYTES`], so
//! that a FIFO, a device (`/dev/zero`) or a directory is refused at once, naming the path,
//! instead of blocking or reading until memory runs out.

use std::fs::File;
use std::io::Read;
use std::path::Path;

/// Largest input file, bytes (16 MiB): a config is a few kilobytes, a measured profile or a
/// duty cycle of a million rows a few tens of megabytes at most.
pub const MAX_INPUT_BYTES: u64 = 16 << 20;

/// Opens the input file `path` for reading, at most [`MAX_INPUT_BYTES`] of it.
///
/// # Errors
/// Why it cannot be read, in words for a message that names the path: it cannot be opened,
/// it is not a regular file (a FIFO, a device, a directory), or it is larger than the cap.
pub fn open(path: &Path) -> std::result::Result<std::io::Take<File>, String> {
    // Checked before opening: opening a FIFO blocks until a writer appears.
    let meta = std::fs::metadata(path).map_err(|e| format!("cannot read the file: {e}"))?;
    if !meta.is_file() {
        let what = if meta.is_dir() {
            "a directory"
        } else {
            "not a regular file (a FIFO, socket or device)"
        };
        return Err(format!(
            "is {what}; rvlife reads its inputs from regular files"
        ));
    }
    if meta.len() > MAX_INPUT_BYTES {
        return Err(too_large(meta.len()));
    }
    let f = File::open(path).map_err(|e| format!("cannot read the file: {e}"))?;
    Ok(f.take(MAX_INPUT_BYTES + 1))
}

fn too_large(len: u64) -> String {
    format!(
        "is {:.1} MiB, more than the {} MiB an input file may have",
        len as f64 / (1 << 20) as f64,
        MAX_INPUT_BYTES >> 20
    )
}

/// Reads the input file `path` as UTF-8 text ([`open`]'s checks; a file that grows beyond the
/// cap while it is read is refused too).
///
/// # Errors
/// As [`open`]; text that is not UTF-8.
pub fn read_text(path: &Path) -> std::result::Result<String, String> {
    let mut text = String::new();
    open(path)?
        .read_to_string(&mut text)
        .map_err(|e| format!("cannot read the file: {e}"))?;
    if text.len() as u64 > MAX_INPUT_BYTES {
        return Err(too_large(text.len() as u64));
    }
    Ok(text)
}
