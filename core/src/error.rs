//! One error type for the whole core. Messages are written for users: they
//! say what was wrong and with which value, and cross the Python boundary as-is.
use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum Error {
    /// A user-supplied value is out of its valid range, NaN or infinite.
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// A handle that does not (or no longer does) name an object of the world.
    #[error("invalid handle: {0}")]
    InvalidHandle(String),
    /// A linear system that cannot be solved (zero pivot, rigid-body mode).
    #[error("singular system: {0}")]
    Singular(String),
    /// An iterative solve that did not reach its tolerance.
    #[error("no convergence: {0}")]
    NoConvergence(String),
    /// Reading or writing a file failed.
    #[error("i/o error: {0}")]
    Io(String),
}

pub type Result<T> = std::result::Result<T, Error>;

/// Error unless `x` is finite.
pub fn finite(name: &str, x: f64) -> Result<f64> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(Error::InvalidInput(format!("{name} must be finite, got {x}")))
    }
}

/// Error unless `x` is finite and strictly positive.
pub fn positive(name: &str, x: f64) -> Result<f64> {
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(Error::InvalidInput(format!("{name} must be finite and > 0, got {x}")))
    }
}

/// Error unless `x` is finite and non-negative.
pub fn non_negative(name: &str, x: f64) -> Result<f64> {
    if x.is_finite() && x >= 0.0 {
        Ok(x)
    } else {
        Err(Error::InvalidInput(format!("{name} must be finite and >= 0, got {x}")))
    }
}
