//! VTK unstructured-grid files (`.vtu`, ASCII XML) for ParaView: FE meshes (triangles) and tubes
//! (polylines), with point and cell data. Written atomically.

use super::{write_atomic, ReportError};
use std::fmt::Write as _;
use std::path::Path;

/// VTK cell types used by turf.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CellKind {
    /// 3-node triangle (VTK_TRIANGLE = 5)
    Triangle,
    /// polyline through its nodes (VTK_POLY_LINE = 4)
    PolyLine,
}

impl CellKind {
    fn code(self) -> u8 {
        match self {
            CellKind::Triangle => 5,
            CellKind::PolyLine => 4,
        }
    }
}

/// A data array on points or cells: 1 (scalar) or 3 (vector) components, flat.
#[derive(Debug, Clone)]
pub struct DataArray {
    /// name shown in ParaView, with unit (`stress_rr_GPa`)
    pub name: String,
    /// 1 or 3
    pub components: usize,
    /// values, `components` per point or cell
    pub values: Vec<f64>,
}

/// An unstructured grid: points in 3D, cells as lists of point indices.
#[derive(Debug, Clone, Default)]
pub struct Grid {
    /// point coordinates (x, y, z), nm
    pub points: Vec<[f64; 3]>,
    /// cells: kind and point indices
    pub cells: Vec<(CellKind, Vec<usize>)>,
    /// arrays with one entry per point
    pub point_data: Vec<DataArray>,
    /// arrays with one entry per cell
    pub cell_data: Vec<DataArray>,
}

impl Grid {
    /// Render as VTU XML, checking array sizes and finiteness.
    pub fn to_vtu(&self, path: &Path) -> Result<String, ReportError> {
        let p = path.display().to_string();
        let invalid = |reason: String| ReportError::Invalid {
            path: p.clone(),
            reason,
        };
        let np = self.points.len();
        let nc = self.cells.len();
        for (arrays, n) in [(&self.point_data, np), (&self.cell_data, nc)] {
            for a in arrays {
                if a.values.len() != a.components * n {
                    return Err(invalid(format!(
                        "array {} has {} values, expected {}",
                        a.name,
                        a.values.len(),
                        a.components * n
                    )));
                }
                if a.values.iter().any(|v| !v.is_finite()) {
                    return Err(ReportError::NonFinite {
                        path: p.clone(),
                        what: a.name.clone(),
                    });
                }
            }
        }
        if let Some((_, c)) = self.cells.iter().find(|(_, c)| c.iter().any(|&i| i >= np)) {
            return Err(invalid(format!("cell {c:?} refers to a missing point")));
        }
        if self.points.iter().flatten().any(|v| !v.is_finite()) {
            return Err(ReportError::NonFinite {
                path: p,
                what: "points".into(),
            });
        }
        let mut s = String::new();
        let _ = writeln!(s, r#"<?xml version="1.0"?>"#);
        let _ = writeln!(
            s,
            r#"<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">"#
        );
        let _ = writeln!(s, "<UnstructuredGrid>");
        let _ = writeln!(s, r#"<Piece NumberOfPoints="{np}" NumberOfCells="{nc}">"#);
        let _ = writeln!(s, "<Points>");
        let coords: Vec<f64> = self.points.iter().flatten().copied().collect();
        write_array(
            &mut s,
            "Float64",
            "points_nm",
            3,
            coords.iter().map(|v| format!("{v:e}")),
        );
        let _ = writeln!(s, "</Points>");
        let _ = writeln!(s, "<Cells>");
        let conn = self
            .cells
            .iter()
            .flat_map(|(_, c)| c.iter().map(|i| i.to_string()));
        write_array(&mut s, "Int64", "connectivity", 1, conn);
        let offsets = self.cells.iter().scan(0usize, |acc, (_, c)| {
            *acc += c.len();
            Some(acc.to_string())
        });
        write_array(&mut s, "Int64", "offsets", 1, offsets);
        write_array(
            &mut s,
            "UInt8",
            "types",
            1,
            self.cells.iter().map(|(k, _)| k.code().to_string()),
        );
        let _ = writeln!(s, "</Cells>");
        for (tag, arrays) in [
            ("PointData", &self.point_data),
            ("CellData", &self.cell_data),
        ] {
            let _ = writeln!(s, "<{tag}>");
            for a in arrays {
                write_array(
                    &mut s,
                    "Float64",
                    &a.name,
                    a.components,
                    a.values.iter().map(|v| format!("{v:e}")),
                );
            }
            let _ = writeln!(s, "</{tag}>");
        }
        let _ = writeln!(s, "</Piece>\n</UnstructuredGrid>\n</VTKFile>");
        Ok(s)
    }

    /// Write atomically to `path` (conventionally `vtk/<name>_<step>.vtu`).
    pub fn write(&self, path: &Path) -> Result<(), ReportError> {
        let text = self.to_vtu(path)?;
        write_atomic(path, text.as_bytes())
    }
}

fn write_array(
    s: &mut String,
    ty: &str,
    name: &str,
    comps: usize,
    vals: impl Iterator<Item = String>,
) {
    let _ = writeln!(
        s,
        r#"<DataArray type="{ty}" Name="{name}" NumberOfComponents="{comps}" format="ascii">"#
    );
    let v: Vec<String> = vals.collect();
    for chunk in v.chunks(12) {
        let _ = writeln!(s, "{}", chunk.join(" "));
    }
    let _ = writeln!(s, "</DataArray>");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_triangle_and_a_polyline_render_with_offsets_and_types() {
        let g = Grid {
            points: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 2.0],
            ],
            cells: vec![
                (CellKind::Triangle, vec![0, 1, 2]),
                (CellKind::PolyLine, vec![0, 3]),
            ],
            point_data: vec![DataArray {
                name: "u_nm".into(),
                components: 1,
                values: vec![0.0, 1.0, 2.0, 3.0],
            }],
            cell_data: vec![DataArray {
                name: "id".into(),
                components: 1,
                values: vec![0.0, 1.0],
            }],
        };
        let s = g.to_vtu(Path::new("x.vtu")).unwrap();
        assert!(s.contains(
            r#"Name="offsets" NumberOfComponents="1" format="ascii">
3 5"#
        ));
        assert!(s.contains("\n5 4\n"));
        let mut bad = g.clone();
        bad.point_data[0].values[1] = f64::NAN;
        assert!(matches!(
            bad.to_vtu(Path::new("x.vtu")),
            Err(ReportError::NonFinite { .. })
        ));
        bad.cells.push((CellKind::PolyLine, vec![9]));
        assert!(bad.to_vtu(Path::new("x.vtu")).is_err());
    }
}
