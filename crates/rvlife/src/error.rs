//! Error type of the library.
//!
//! Every input problem is reported as [`Error::Invalid`] (or [`Error::Config`] for TOML that does
//! not parse), naming the field, the value and the allowed range, so that the command line can
//! print it and exit with code 2. Numerical failures that a valid input should never produce are
//! [`Error::Numerical`]; file-system failures are [`Error::Io`].

use std::path::PathBuf;

/// Result alias used throughout the crate.
pub type Result<T> = std::result::Result<T, Error>;

/// Everything that can go wrong in rvlife.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A value is outside its allowed range.
    #[error("invalid {field} = {value}: {allowed}")]
    Invalid {
        /// Dotted path of the offending field, as written in the config (`cycloid.pins`).
        field: String,
        /// The value as given.
        value: String,
        /// The allowed range or the reason, in words.
        allowed: String,
    },
    /// The configuration file could not be read or parsed (syntax, unknown key, wrong type).
    #[error("config {path}: {message}")]
    Config {
        /// The file (or `<built-in>`).
        path: String,
        /// What the parser said, with the key path where known.
        message: String,
    },
    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file or directory concerned.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A solver did not converge or produced a non-finite number.
    #[error("numerical failure in {context}: {message}")]
    Numerical {
        /// Which computation.
        context: std::borrow::Cow<'static, str>,
        /// What happened.
        message: String,
    },
}

/// A value for a message: a plain number of more than 16 characters (`1e300` printed by
/// `f64`'s `Display` as 301 digits, `1e-300` as 302) in exponent notation, anything else as
/// it is.
fn readable(v: String) -> String {
    let plain = v
        .trim_start_matches('-')
        .chars()
        .all(|c| c.is_ascii_digit() || c == '.');
    match v.parse::<f64>() {
        Ok(x) if plain && v.len() > 16 && x.is_finite() => format!("{x:e}"),
        _ => v,
    }
}

impl Error {
    /// Shorthand for [`Error::Invalid`]; a long plain number in `value` is written in exponent
    /// notation.
    pub fn invalid(
        field: impl Into<String>,
        value: impl std::fmt::Display,
        allowed: impl Into<String>,
    ) -> Self {
        Error::Invalid {
            field: field.into(),
            value: readable(value.to_string()),
            allowed: allowed.into(),
        }
    }

    /// Shorthand for [`Error::Numerical`].
    pub fn numerical(context: &'static str, message: impl Into<String>) -> Self {
        Error::Numerical {
            context: context.into(),
            message: message.into(),
        }
    }

    /// Wraps an I/O error with the path it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }

    /// The error with `context` (`(design 3: ...)`) appended to an [`Error::Invalid`]'s
    /// allowed range, so the message also says where the value was met; other errors as they
    /// are.
    pub fn in_context(self, context: impl std::fmt::Display) -> Self {
        match self {
            Error::Invalid {
                field,
                value,
                allowed,
            } => Error::Invalid {
                field,
                value,
                allowed: format!("{allowed} {context}"),
            },
            other => other,
        }
    }

    /// True when the error is the user's input (bad value, bad config, missing input file):
    /// the command line exits with code 2 for these.
    pub fn is_input_error(&self) -> bool {
        matches!(self, Error::Invalid { .. } | Error::Config { .. })
    }
}
