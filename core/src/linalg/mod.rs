//! Linear algebra kernels (band LU). Owned by the linalg/spline helper.
