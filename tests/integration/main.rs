//! The integration tests, one module per engine benchmark or user-facing behaviour, linked into
//! a single test binary (the usual layout of a large Rust suite: one link of the crate instead of
//! one per file). Run one module with `cargo test --test integration MODULE::`, e.g.
//! `cargo test --test integration continuum_hertz::`.

mod common;

mod cli_run;
mod continuum_adhesion;
mod continuum_adhesion_riks;
mod continuum_berkovich_foam;
mod continuum_hertz;
mod continuum_homogeneous;
mod continuum_load_frame;
mod continuum_localisation;
mod continuum_stick;
mod discrete_compression;
mod discrete_ensemble;
mod discrete_peeling;
mod discrete_rod_cantilever;
mod discrete_rod_euler;
mod discrete_rod_postbuckling;
mod discrete_rod_solvers;
mod discrete_rods_scene;
mod discrete_rve;
mod discrete_sphere_pulloff;
mod discrete_vdw_broadphase;
mod discrete_vdw_two_tubes;
mod extremes;
mod fit_indentation;
mod halfspace_large_mu;
mod halfspace_limits;
mod homogenize_calculix;
mod homogenize_cards;
mod homogenize_synthetic;
mod homogenize_table51;
mod homogenize_transverse;
mod pipeline_chain;
mod reader_fuzz;
mod run_report;
mod run_robustness;
mod scale_out;
mod scene_errors;
mod scene_examples;
mod scene_props;
mod theory_cli;
mod theory_closed_forms;
mod theory_indentation_law;
