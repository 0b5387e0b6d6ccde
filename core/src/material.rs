//! Materials (annex C).
