//! One typed error for the whole core (faer-style typed outcomes): callers
//! match on variants and read their fields; no code path parses a message.
//! The `Display` text is written for users and crosses the Python boundary
//! as the exception message, with the fields as exception attributes.
use crate::handles::{ConstraintHandle, RodHandle};
use serde::{Deserialize, Serialize};
use std::fmt;
use thiserror::Error;

/// An unknown of the KKT system, named for error messages (SPEC §5).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Unknown {
    /// Row/column `index` of a linear system (kernel level, before the KKT
    /// layer names it).
    Index { index: usize },
    /// Coordinate `axis` (0–2: x, y, z; 3: roll θ) of control point `ctrl` of `rod`.
    Coordinate { rod: RodHandle, ctrl: usize, axis: usize },
    /// The sliding abscissa of a slider constraint.
    Abscissa { constraint: ConstraintHandle },
    /// The abscissa of a bead (statics).
    BeadAbscissa { bead: usize },
    /// Multiplier `row` of a constraint.
    Multiplier { constraint: ConstraintHandle, row: usize },
    /// A contact pair's multiplier (index in the step's contact set).
    Contact { pair: usize },
}

impl fmt::Display for Unknown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Unknown::Coordinate { rod, ctrl, axis } => {
                let a = ["x", "y", "z", "roll"].get(*axis).copied().unwrap_or("?");
                write!(f, "coordinate {a} of control point {ctrl} of rod {}", rod.index)
            }
            Unknown::Abscissa { constraint } => write!(
                f,
                "the sliding abscissa of constraint {} (its rows cannot fix it: tangent ⟂ all rows?)",
                constraint.index
            ),
            Unknown::Index { index } => write!(f, "unknown {index}"),
            Unknown::BeadAbscissa { bead } => write!(f, "the abscissa of bead {bead}"),
            Unknown::Multiplier { constraint, row } => write!(
                f,
                "multiplier {row} of constraint {} (duplicate or linearly dependent constraints?)",
                constraint.index
            ),
            Unknown::Contact { pair } => write!(f, "the multiplier of contact pair {pair}"),
        }
    }
}

#[derive(Debug, Error, Clone, PartialEq)]
pub enum Error {
    /// A user-supplied value is out of its valid range, NaN or infinite, or
    /// inconsistent with the rest of the input. `what` names the argument,
    /// `value` shows what was given, `expected` says what is accepted.
    #[error("invalid input: {}", input_message(what, value, expected))]
    InvalidInput { what: String, value: String, expected: String },
    /// A handle that does not (or no longer does) name an object of the world.
    #[error("invalid handle: {what} does not exist (removed, broken, or from another world)")]
    InvalidHandle { what: String },
    /// A linear system that cannot be solved (zero pivot, rigid-body mode,
    /// contradictory constraints): the unknown where it failed, if known, and
    /// the constraints involved.
    #[error("singular system: {detail}{}{}", unknown_suffix(unknown), constraints_suffix(constraints))]
    Singular { unknown: Option<Unknown>, constraints: Vec<ConstraintHandle>, detail: String },
    /// An iterative solve that did not reach its tolerance.
    #[error("no convergence after {iterations} iterations (residual {residual:.3e}): {detail}")]
    NotConverged { iterations: usize, residual: f64, detail: String },
    /// A solve produced a non-finite state; nothing was committed.
    #[error("non-finite state{}: {detail}", rod_suffix(rod))]
    NonFinite { rod: Option<RodHandle>, detail: String },
    /// A step whose energy or increment jumped by more than the allowed factor.
    #[error("diverged at step {step}{}: {detail}", rod_suffix(rod))]
    Diverged { step: u64, rod: Option<RodHandle>, factor: f64, detail: String },
    /// Reading or writing a file failed, or its content is not what we write.
    #[error("i/o error: {}{message}", path_prefix(path))]
    Io { path: String, message: String },
}

fn input_message(what: &str, value: &str, expected: &str) -> String {
    match (value.is_empty(), expected.is_empty()) {
        (true, true) => what.to_string(),
        (true, false) => format!("{what}: expected {expected}"),
        (false, true) => format!("{what}, got {value}"),
        (false, false) => format!("{what} must be {expected}, got {value}"),
    }
}

fn unknown_suffix(u: &Option<Unknown>) -> String {
    u.as_ref().map_or(String::new(), |u| format!(": unknown is {u}"))
}

fn constraints_suffix(c: &[ConstraintHandle]) -> String {
    if c.is_empty() {
        return String::new();
    }
    let ids: Vec<String> = c.iter().map(|h| h.index.to_string()).collect();
    format!(" (constraints involved: {})", ids.join(", "))
}

fn rod_suffix(r: &Option<RodHandle>) -> String {
    r.map_or(String::new(), |r| format!(" in rod {}", r.index))
}

fn path_prefix(p: &str) -> String {
    if p.is_empty() {
        String::new()
    } else {
        format!("{p}: ")
    }
}

impl Error {
    /// `what` must be `expected`, got `value`.
    pub fn invalid(what: impl Into<String>, value: impl fmt::Display, expected: impl Into<String>) -> Error {
        Error::InvalidInput { what: what.into(), value: value.to_string(), expected: expected.into() }
    }
    /// An invalid input described by one sentence (no single value to show).
    pub fn input(what: impl Into<String>) -> Error {
        Error::InvalidInput { what: what.into(), value: String::new(), expected: String::new() }
    }
    pub fn handle(what: impl Into<String>) -> Error {
        Error::InvalidHandle { what: what.into() }
    }
    /// A singular system with no unknown or constraint to name.
    pub fn singular(detail: impl Into<String>) -> Error {
        Error::Singular { unknown: None, constraints: Vec::new(), detail: detail.into() }
    }
    pub fn io(path: impl Into<String>, message: impl fmt::Display) -> Error {
        Error::Io { path: path.into(), message: message.to_string() }
    }
    pub fn not_converged(iterations: usize, residual: f64, detail: impl Into<String>) -> Error {
        Error::NotConverged { iterations, residual, detail: detail.into() }
    }
    /// A singular system at row/column `index` of a linear system.
    pub fn pivot(index: usize, detail: impl Into<String>) -> Error {
        Error::Singular { unknown: Some(Unknown::Index { index }), constraints: Vec::new(), detail: detail.into() }
    }
    /// The same error with `prefix` put in front of what it names (the
    /// argument of an input error, the detail of the others).
    pub fn context(self, prefix: impl fmt::Display) -> Error {
        match self {
            Error::InvalidInput { what, value, expected } => Error::InvalidInput { what: format!("{prefix}: {what}"), value, expected },
            Error::InvalidHandle { what } => Error::InvalidHandle { what: format!("{prefix}: {what}") },
            Error::Singular { unknown, constraints, detail } => Error::Singular { unknown, constraints, detail: format!("{prefix}: {detail}") },
            Error::NotConverged { iterations, residual, detail } => Error::NotConverged { iterations, residual, detail: format!("{prefix}: {detail}") },
            Error::NonFinite { rod, detail } => Error::NonFinite { rod, detail: format!("{prefix}: {detail}") },
            Error::Diverged { step, rod, factor, detail } => Error::Diverged { step, rod, factor, detail: format!("{prefix}: {detail}") },
            Error::Io { path, message } => Error::Io { path, message: format!("{prefix}: {message}") },
        }
    }
    /// The variant's name (for Python exception classes and logs).
    pub fn kind(&self) -> &'static str {
        match self {
            Error::InvalidInput { .. } => "InvalidInput",
            Error::InvalidHandle { .. } => "InvalidHandle",
            Error::Singular { .. } => "Singular",
            Error::NotConverged { .. } => "NotConverged",
            Error::NonFinite { .. } => "NonFinite",
            Error::Diverged { .. } => "Diverged",
            Error::Io { .. } => "Io",
        }
    }
}

pub type Result<T> = std::result::Result<T, Error>;

/// Error unless `x` is finite.
pub fn finite(name: &str, x: f64) -> Result<f64> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(Error::invalid(name, x, "finite"))
    }
}

/// Error unless `x` is finite and strictly positive.
pub fn positive(name: &str, x: f64) -> Result<f64> {
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(Error::invalid(name, x, "finite and > 0"))
    }
}

/// Error unless `x` is finite and non-negative.
pub fn non_negative(name: &str, x: f64) -> Result<f64> {
    if x.is_finite() && x >= 0.0 {
        Ok(x)
    } else {
        Err(Error::invalid(name, x, "finite and >= 0"))
    }
}

/// Error unless a size read from a user or a file is within its documented
/// cap, checked before anything of that size is allocated.
pub fn size(name: &str, n: usize, max: usize) -> Result<usize> {
    if n <= max {
        Ok(n)
    } else {
        Err(Error::invalid(name, n, format!("at most {max}")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn messages_read_as_sentences() {
        assert_eq!(positive("dt", -1.0).unwrap_err().to_string(), "invalid input: dt must be finite and > 0, got -1");
        assert_eq!(Error::input("no axis selected").to_string(), "invalid input: no axis selected");
        let e = Error::Singular {
            unknown: Some(Unknown::Coordinate { rod: RodHandle { index: 2, generation: 0 }, ctrl: 5, axis: 3 }),
            constraints: vec![],
            detail: "zero pivot".into(),
        };
        assert_eq!(e.to_string(), "singular system: zero pivot: unknown is coordinate roll of control point 5 of rod 2");
    }
}
