//! The scene file: serde structs of its sections, validation, and the resolved plan.
