//! Jump-in, jump-out and pull-off of an adhesive indentation, read off the converged rows.
//!
//! - **Pull-off** is the minimum load along the curve (the load-control pull-off, as in the
//!   half-space solver, `crate::halfspace`), reported only if the curve has passed it (a later
//!   row carries a larger load), so a run that stops while the load still falls reports none.
//! - **Jumps.** Under displacement control or through a spring, the equilibrium curve folds and
//!   the state jumps (carried through by contact damping). An increment is part of a jump when
//!   the central gap (at the surface point nearest the axis) changes by more than
//!   [`JUMP_RATIO`] times the change of the drive; consecutive such increments form one jump,
//!   reported by the rows before and after it. The first closing jump is the jump-in, the first
//!   opening one the jump-out (its start is the displacement-controlled pull-off, −5/6 πγR
//!   in the JKR limit).
//! - **Limit points.** A curve traced by arc-length continuation ([`super::arclength`]) has no
//!   jumps: it turns back at the folds of the S-curve. A fold is a row inside a schedule segment
//!   where the drive reaches a local extremum (the drive reverses between its neighbours of the
//!   same segment): the first local maximum is the jump-in fold (the approach can go no
//!   deeper on the out-of-contact branch), the first local minimum the jump-out fold (the
//!   retraction can go no further on the contact branch: the pull-off under this drive). An
//!   elastic S-curve is one curve: the approach, traced through, already passes both. A curve with folds is reported
//!   without jumps (near a fold the gap changes much faster than the drive, which the jump
//!   test would misread).
//! - **Contact radius** (every row): the outermost radius where the gap is below the law's
//!   equilibrium gap z₀, i.e. where the LJ pressure changes sign from repulsive to attractive
//!   ([`super::contact::Contact::contact_radius`]), as in the half-space solver.

use super::indent::Row;
use serde::Serialize;

/// Change of the central gap per change of the drive above which an increment is a jump: on a
/// quasi-static branch the ratio is of order one (−1 for a rigid surface), during a damped
/// jump at a nearly fixed drive it is orders of magnitude larger.
pub const JUMP_RATIO: f64 = 10.0;

/// A jump: the converged rows before and after it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Jump {
    /// the last row before the jump
    pub before: Row,
    /// the first row after it
    pub after: Row,
}

/// What was detected.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Events {
    /// the row of minimum load, if passed
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pull_off: Option<Row>,
    /// the first closing jump
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_in: Option<Jump>,
    /// the first opening jump
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_out: Option<Jump>,
    /// on a traced curve: the first local maximum of the drive within a segment
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fold_in: Option<Row>,
    /// on a traced curve: the first local minimum of the drive within a segment
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fold_out: Option<Row>,
}

/// The rows where the drive reaches a local extremum inside a segment: (row, is a maximum).
pub fn limit_points(rows: &[Row]) -> Vec<(Row, bool)> {
    rows.windows(3)
        .filter(|w| w[0].segment == w[1].segment && w[1].segment == w[2].segment)
        .filter_map(|w| {
            let (before, after) = (w[1].drive_nm - w[0].drive_nm, w[2].drive_nm - w[1].drive_nm);
            (before * after < 0.0).then_some((w[1], before > 0.0))
        })
        .collect()
}

/// True if the increment from row `a` to row `b` is part of a jump.
pub fn jumping(a: &Row, b: &Row) -> bool {
    let dg = b.gap_nm - a.gap_nm;
    dg.abs() > JUMP_RATIO * (b.drive_nm - a.drive_nm).abs() && dg != 0.0
}

/// The largest difference of load between a curve stepped by Newton (`stepped`, its jump
/// increments left out) and one traced by arc-length (`traced`) at the same drive and on the
/// same branch (of the traced rows bracketing the drive, those whose interpolated central gap
/// is nearest), nN; with the number of rows compared. Rows outside the traced range are skipped.
pub fn branch_difference(stepped: &[Row], traced: &[Row]) -> (f64, usize) {
    let (mut worst, mut compared) = (0.0f64, 0);
    for (i, r) in stepped.iter().enumerate() {
        if i > 0 && jumping(&stepped[i - 1], r) {
            continue;
        }
        let nearest = traced
            .windows(2)
            .filter(|w| w[0].segment == w[1].segment)
            .filter_map(|w| {
                let (d0, d1) = (w[0].drive_nm, w[1].drive_nm);
                if (r.drive_nm - d0) * (r.drive_nm - d1) > 0.0 || d0 == d1 {
                    return None;
                }
                let f = (r.drive_nm - d0) / (d1 - d0);
                let gap = w[0].gap_nm + f * (w[1].gap_nm - w[0].gap_nm);
                let load = w[0].load_nN + f * (w[1].load_nN - w[0].load_nN);
                Some(((gap - r.gap_nm).abs(), load))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((_, load)) = nearest {
            worst = worst.max((load - r.load_nN).abs());
            compared += 1;
        }
    }
    (worst, compared)
}

/// Detect the events along `rows`.
pub fn detect(rows: &[Row]) -> Events {
    let mut ev = Events::default();
    if let Some((i, min)) = rows
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.load_nN.total_cmp(&b.1.load_nN))
    {
        if min.load_nN < 0.0 && rows[i + 1..].iter().any(|r| r.load_nN > min.load_nN) {
            ev.pull_off = Some(*min);
        }
    }
    let folds = limit_points(rows);
    ev.fold_in = folds.iter().find(|f| f.1).map(|f| f.0);
    ev.fold_out = folds.iter().find(|f| !f.1).map(|f| f.0);
    if !folds.is_empty() {
        return ev;
    }
    let mut i = 1;
    while i < rows.len() {
        if !jumping(&rows[i - 1], &rows[i]) {
            i += 1;
            continue;
        }
        let start = i - 1;
        let closing = rows[i].gap_nm < rows[i - 1].gap_nm;
        while i < rows.len()
            && jumping(&rows[i - 1], &rows[i])
            && (rows[i].gap_nm < rows[i - 1].gap_nm) == closing
        {
            i += 1;
        }
        let jump = Jump {
            before: rows[start],
            after: rows[i - 1],
        };
        let slot = if closing {
            &mut ev.jump_in
        } else {
            &mut ev.jump_out
        };
        if slot.is_none() {
            *slot = Some(jump);
        }
    }
    ev
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(segment: usize, drive: f64, gap: f64, load: f64) -> Row {
        Row {
            time_s: 0.0,
            depth_nm: drive,
            load_nN: load,
            contact_radius_nm: 0.0,
            iterations: 1,
            drive_nm: drive,
            gap_nm: gap,
            strain_energy_aJ: 0.0,
            damping_dissipated_aJ: 0.0,
            segment,
        }
    }

    #[test]
    fn finds_the_jumps_and_the_passed_minimum() {
        // approach: gap follows −drive, then snaps from 2 to 0.9 at drive ≈ −2
        let rows = vec![
            row(0, -3.0, 3.0, 0.0),
            row(0, -2.5, 2.5, -0.1),
            row(0, -2.0, 2.0, -0.3),
            row(0, -1.99, 1.3, -1.0),
            row(0, -1.98, 0.9, -0.8),
            row(0, -1.5, 0.8, 1.0),
            // retraction: the load passes a minimum, then the gap opens fast
            row(1, -2.5, 1.0, -1.6),
            row(1, -3.0, 1.1, -1.2),
            row(1, -3.01, 2.9, -0.05),
            row(1, -3.5, 3.5, 0.0),
        ];
        let e = detect(&rows);
        let ji = e.jump_in.unwrap();
        assert_eq!((ji.before.drive_nm, ji.after.drive_nm), (-2.0, -1.98));
        let jo = e.jump_out.unwrap();
        assert_eq!((jo.before.drive_nm, jo.after.drive_nm), (-3.0, -3.01));
        assert_eq!(e.pull_off.unwrap().load_nN, -1.6);
        // the schedule's turn between the segments is no fold
        assert!(e.fold_in.is_none() && e.fold_out.is_none());
        // a curve still falling at its end has no pull-off
        assert!(detect(&rows[..7]).pull_off.is_none());
    }

    #[test]
    fn a_traced_s_curve_has_folds_not_jumps() {
        // one elastic S-curve traced both ways: the approach turns at the jump-in fold
        // (−3.5), comes back along the unstable branch to the jump-out fold (−4.3) and goes on
        // into contact; the retraction passes the same folds in the other order
        let rows = vec![
            row(0, -6.0, 6.0, 0.0),
            row(0, -3.5, 3.4, -0.3),
            row(0, -4.3, 1.5, -0.9),
            row(0, -1.0, 0.7, 1.0),
            row(1, -2.5, 1.0, -1.6),
            row(1, -4.3, 1.5, -0.9),
            row(1, -3.5, 3.4, -0.3),
            row(1, -6.0, 6.0, 0.0),
        ];
        let e = detect(&rows);
        assert_eq!(e.fold_in.unwrap().drive_nm, -3.5);
        assert_eq!(e.fold_out.unwrap().drive_nm, -4.3);
        assert!(e.jump_in.is_none() && e.jump_out.is_none());
        assert_eq!(limit_points(&rows).len(), 4);
    }
}
