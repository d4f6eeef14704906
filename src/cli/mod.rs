//! Subcommand handlers: each turns parsed arguments into library calls and prints the result.

pub mod bench;
pub mod fit_indentation;
pub mod homogenize;
pub mod run;
pub mod theory;
pub mod theory_law;
