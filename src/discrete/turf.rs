//! Turf generation (placeholder while writing).
