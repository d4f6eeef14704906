//! Writing an indentation's results (DESIGN.md): `load_depth.csv`
//! (`time_s, depth_nm, load_nN, contact_radius_nm`, then `drive_nm`, `gap_nm`, `strain_energy_aJ`,
//! `damping_dissipated_aJ`; through a two-spring transducer also `applied_load_nN`, the
//! controlled P̂, with `drive_nm` the plate position h), `summary.json`, `plots/load_depth.{svg,png}`
//! and `vtk/indent_<segment>.vtu` (the deformed mesh with displacements and Cauchy stresses, for
//! ParaView), all through [`crate::report`].

use super::indent::IndentResult;
use super::machine::Machine;
use crate::report::csv::Table;
use crate::report::plot::{Plot, Series};
use crate::report::vtk::{CellKind, DataArray, Grid};
use crate::report::{write_json, ReportError};
use serde::Serialize;
use std::path::Path;

/// The headline numbers of a run (`summary.json`).
#[derive(Debug, Clone, Serialize)]
#[allow(non_snake_case)] // field names carry their units
pub struct Summary<'a> {
    /// which engine
    pub engine: &'static str,
    /// true if every segment finished
    pub completed: bool,
    /// why the run stopped, if it did
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failure: Option<&'a str>,
    /// largest load, nN
    pub max_load_nN: f64,
    /// depth at the largest load, nm
    pub depth_at_max_load_nm: f64,
    /// contact radius at the largest load, nm
    pub contact_radius_at_max_load_nm: f64,
    /// load at the end, nN
    pub final_load_nN: f64,
    /// pull-off, jump-in and jump-out (adhesion)
    pub events: super::events::Events,
    /// under load control: the load beyond which the indenter separated, nN
    #[serde(skip_serializing_if = "Option::is_none")]
    pub separated_nN: Option<f64>,
    /// energy dissipated by contact damping over the run, aJ
    pub damping_dissipated_aJ: f64,
    /// largest strain energy of the run, aJ (to compare the damping with)
    pub max_strain_energy_aJ: f64,
    /// the derived sizes
    pub resolved: &'a super::indent::Resolved,
    /// mesh figures
    pub mesh: &'a super::mesh::MeshReport,
    /// work and time
    pub cost: &'a super::indent::RunStats,
    /// the parameters, internal units
    pub params: &'a super::indent::IndentParams,
    /// adaptive meshing: every mesh of the run (increment it took over at, edge, elements)
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub adaptation: &'a [super::indent::Adaptation],
    /// arc-length: the folds and bifurcations the traced curve passed (kind, depth, load,
    /// negative eigenvalues of K_uu before and after, the critical mode's eigenvalue, its load
    /// alignment and where it moves most)
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub critical_points: &'a [super::bifurcation::CriticalPoint],
    /// Newton: the snaps through instabilities at a fixed drive (segment, time, drive, depth
    /// and load before and after, the energy released, the descent's iterations)
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub snaps: &'a [super::snap::Snap],
}

/// What [`IndentResult::write`] wrote besides the CSV, the summary and the VTU files.
#[derive(Debug, Default)]
pub struct Written {
    /// the plots written, relative to the output folder given
    pub plots: Vec<String>,
    /// the plots that could not be written, with the reason
    pub warnings: Vec<String>,
}

impl IndentResult {
    /// The summary of this run.
    pub fn summary(&self) -> Summary<'_> {
        let best = self
            .rows
            .iter()
            .max_by(|a, b| a.load_nN.total_cmp(&b.load_nN))
            .copied()
            .unwrap_or(self.rows[0]);
        Summary {
            engine: "continuum",
            completed: self.failure.is_none(),
            failure: self.failure.as_deref(),
            max_load_nN: best.load_nN,
            depth_at_max_load_nm: best.depth_nm,
            contact_radius_at_max_load_nm: best.contact_radius_nm,
            final_load_nN: self.rows.last().map_or(0.0, |r| r.load_nN),
            events: super::events::detect(&self.rows),
            separated_nN: self.separated_nN,
            damping_dissipated_aJ: self.rows.last().map_or(0.0, |r| r.damping_dissipated_aJ),
            max_strain_energy_aJ: self
                .rows
                .iter()
                .map(|r| r.strain_energy_aJ)
                .fold(0.0, f64::max),
            resolved: &self.resolved,
            mesh: &self.mesh_report,
            cost: &self.stats,
            params: &self.params,
            adaptation: &self.adaptation,
            critical_points: &self.critical_points,
            snaps: &self.snaps,
        }
    }

    /// Write the CSV, summary, plots and VTU files into `dir`. A plot that cannot be written
    /// is a warning, not an error: returns the plots written (relative to `dir`) and the
    /// warnings.
    pub fn write(&self, dir: &Path) -> Result<Written, ReportError> {
        let col = |f: fn(&super::indent::Row) -> f64| self.rows.iter().map(f).collect::<Vec<_>>();
        let mut table = Table::new()
            .column("time_s", col(|r| r.time_s))
            .column("depth_nm", col(|r| r.depth_nm))
            .column("load_nN", col(|r| r.load_nN))
            .column("contact_radius_nm", col(|r| r.contact_radius_nm))
            .column("drive_nm", col(|r| r.drive_nm))
            .column("gap_nm", col(|r| r.gap_nm))
            .column("strain_energy_aJ", col(|r| r.strain_energy_aJ))
            .column("damping_dissipated_aJ", col(|r| r.damping_dissipated_aJ));
        let m = self.params.machine;
        if let Machine::LoadFrame { .. } = m {
            // through a transducer the controlled force P̂ differs from the specimen's Q
            table = table.column(
                "applied_load_nN",
                self.rows
                    .iter()
                    .map(|r| m.applied_load(r.load_nN, r.depth_nm))
                    .collect(),
            );
        }
        table.write(&dir.join("load_depth.csv"))?;
        write_json(&dir.join("summary.json"), &self.summary())?;
        let plots = dir.join("plots");
        let mut written = Written::default();
        let load_depth = Plot::new("Load–depth", "depth δ (nm)", "load P (nN)").with(Series::line(
            "FE",
            col(|r| r.depth_nm),
            col(|r| r.load_nN),
        ));
        let radius = Plot::new("Contact radius", "depth δ (nm)", "contact radius a (nm)").with(
            Series::points("FE", col(|r| r.depth_nm), col(|r| r.contact_radius_nm)),
        );
        for (plot, stem) in [(load_depth, "load_depth"), (radius, "contact_radius")] {
            let files = plot.write_or_warn(&plots, stem, "plots", &mut written.warnings);
            written.plots.extend(files);
        }
        for s in &self.snapshots {
            self.grid(
                s.mesh.as_ref().unwrap_or(&self.mesh),
                &s.displacement,
                &s.stress,
            )
            .write(&dir.join("vtk").join(format!("indent_{}.vtu", s.label)))?;
        }
        Ok(written)
    }

    /// The deformed mesh as a VTK grid (points at x = X + u in the (r, z) plane).
    fn grid(&self, m: &super::mesh::Mesh, u: &[f64], stress: &[[f64; 4]]) -> Grid {
        let names = [
            "stress_rr_GPa",
            "stress_zz_GPa",
            "stress_tt_GPa",
            "stress_rz_GPa",
        ];
        let mut cell_data: Vec<DataArray> = names
            .iter()
            .enumerate()
            .map(|(k, n)| DataArray {
                name: (*n).into(),
                components: 1,
                values: stress.iter().map(|s| s[k]).collect(),
            })
            .collect();
        cell_data.push(DataArray {
            name: "mises_GPa".into(),
            components: 1,
            values: stress
                .iter()
                .map(|s| {
                    let (a, b, c) = (s[0] - s[1], s[1] - s[2], s[2] - s[0]);
                    (0.5 * (a * a + b * b + c * c) + 3.0 * s[3] * s[3]).sqrt()
                })
                .collect(),
        });
        Grid {
            points: m
                .nodes
                .iter()
                .enumerate()
                .map(|(n, x)| [x[0] + u[2 * n], x[1] + u[2 * n + 1], 0.0])
                .collect(),
            cells: m
                .triangles
                .iter()
                .map(|t| (CellKind::Triangle, t.to_vec()))
                .collect(),
            point_data: vec![DataArray {
                name: "displacement_nm".into(),
                components: 3,
                values: (0..m.nodes.len())
                    .flat_map(|n| [u[2 * n], u[2 * n + 1], 0.0])
                    .collect(),
            }],
            cell_data,
        }
    }
}
