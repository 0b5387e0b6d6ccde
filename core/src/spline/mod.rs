//! Cubic B-splines. Owned by the linalg/spline helper.
