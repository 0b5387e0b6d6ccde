//! strandkit-core: geometrically exact dynamic splines (SPEC §1–§5).
pub mod energy;
pub mod error;
pub mod linalg;
pub mod material;
pub mod section;
pub mod spline;

pub use error::{Error, Result};
