//! Cubic B-splines on general knot vectors (SPEC §1.1; thesis II.10–II.15):
//! basis functions with derivatives, Boehm knot insertion and splitting,
//! and collocation (interpolation) with the band solver.
pub mod insert;
pub mod interpolate;
pub mod knots;

pub use insert::{insert_knot, open_ring_at, split_at};
pub use interpolate::{default_params, fit, interpolate};
pub use knots::{eval, KnotKind, KnotVector, KnotVectorData};

/// Polynomial degree of the rod's B-spline.
pub const DEGREE: usize = 3;
/// Order (degree + 1) = number of control points per segment.
pub const ORDER: usize = 4;

/// Fixtures shared by the spline tests.
#[cfg(test)]
pub(crate) mod test_fixtures {
    use super::KnotVector;

    /// Non-uniform, a double and a triple interior knot, unclamped start, clamped end.
    pub fn general() -> KnotVector {
        KnotVector::from_knots(vec![-1.0, 0.0, 0.5, 1.0, 1.7, 2.0, 2.0, 3.5, 3.5, 3.5, 4.0, 4.2, 5.0, 5.0, 5.0, 5.0], 12)
            .expect("valid knot vector") // a fixed, valid test fixture
    }
}
