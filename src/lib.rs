//! strandkit: geometrically exact dynamic spline rods (facade crate).
pub use strandkit_builders as builders;
pub use strandkit_core as core;
pub use strandkit_core::*;
