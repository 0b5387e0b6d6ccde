//! Cross-sections (annex D).
