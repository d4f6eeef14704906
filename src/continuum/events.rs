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
//! - **Hold and loading figures** ([`hold_figures`], [`loading_slope`]), for comparison with the
//!   quasi-rheological model (seed §2.3): during a hold the load relaxes and the depth creeps,
//!   along dQ/dδ = −K through a spring K or −χ through the transducer (seed 2.6); the loading
//!   branch's slope dQ/dδ stands for the specimen's instantaneous stiffness K₁ (seed 2.7).
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
    let jumping = |a: &Row, b: &Row| {
        let dg = b.gap_nm - a.gap_nm;
        dg.abs() > JUMP_RATIO * (b.drive_nm - a.drive_nm).abs() && dg != 0.0
    };
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

/// What a hold did.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[allow(non_snake_case)] // field names carry their units
pub struct HoldFigures {
    /// load at the start minus load at the end (> 0: relaxation), nN
    pub load_drop_nN: f64,
    /// depth at the end minus depth at the start (> 0: creep into the specimen), nm
    pub creep_nm: f64,
    /// dQ/dδ between start and end, nN/nm; none when the depth did not move (rigid drive)
    pub slope_nN_per_nm: Option<f64>,
}

/// The figures of a hold from its rows, the row it starts from first (none for fewer than 2).
pub fn hold_figures(rows: &[Row]) -> Option<HoldFigures> {
    let (first, last) = (rows.first()?, rows.last()?);
    if rows.len() < 2 {
        return None;
    }
    let creep = last.depth_nm - first.depth_nm;
    let drop = first.load_nN - last.load_nN;
    Some(HoldFigures {
        load_drop_nN: drop,
        creep_nm: creep,
        slope_nN_per_nm: (creep != 0.0).then(|| -drop / creep),
    })
}

/// The least-squares slope dQ/dδ of the compressive part (Q ≥ 0) of a loading branch, nN/nm;
/// none with fewer than two such rows or no spread in depth.
pub fn loading_slope(rows: &[Row]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.load_nN >= 0.0)
        .map(|r| (r.depth_nm, r.load_nN))
        .collect();
    let n = pts.len() as f64;
    if pts.len() < 2 {
        return None;
    }
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(drive: f64, gap: f64, load: f64) -> Row {
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
        }
    }

    #[test]
    fn finds_the_jumps_and_the_passed_minimum() {
        // approach: gap follows −drive, then snaps from 2 to 0.9 at drive ≈ −2
        let rows = vec![
            row(-3.0, 3.0, 0.0),
            row(-2.5, 2.5, -0.1),
            row(-2.0, 2.0, -0.3),
            row(-1.99, 1.3, -1.0),
            row(-1.98, 0.9, -0.8),
            row(-1.5, 0.8, 1.0),
            // retraction: the load passes a minimum, then the gap opens fast
            row(-2.5, 1.0, -1.6),
            row(-3.0, 1.1, -1.2),
            row(-3.01, 2.9, -0.05),
            row(-3.5, 3.5, 0.0),
        ];
        let e = detect(&rows);
        let ji = e.jump_in.unwrap();
        assert_eq!((ji.before.drive_nm, ji.after.drive_nm), (-2.0, -1.98));
        let jo = e.jump_out.unwrap();
        assert_eq!((jo.before.drive_nm, jo.after.drive_nm), (-3.0, -3.01));
        assert_eq!(e.pull_off.unwrap().load_nN, -1.6);
        // a curve still falling at its end has no pull-off
        assert!(detect(&rows[..7]).pull_off.is_none());
    }

    #[test]
    fn hold_and_loading_figures() {
        // a hold along Q = 100 − 4δ: drop 8 nN over 2 nm of creep, slope −4
        let hold = [
            row(10.0, 0.0, 60.0),
            row(11.0, 0.0, 56.0),
            row(12.0, 0.0, 52.0),
        ];
        let h = hold_figures(&hold).unwrap();
        assert_eq!((h.load_drop_nN, h.creep_nm), (8.0, 2.0));
        assert_eq!(h.slope_nN_per_nm, Some(-4.0));
        // a rigid drive does not creep: no slope
        let rigid = [row(10.0, 0.0, 60.0), row(10.0, 0.0, 50.0)];
        assert_eq!(hold_figures(&rigid).unwrap().slope_nN_per_nm, None);
        assert!(hold_figures(&hold[..1]).is_none());
        // the tensile start is left out: Q = 3δ − 6 for δ ≥ 2
        let load = [
            row(0.0, 0.0, -5.0),
            row(2.0, 0.0, 0.0),
            row(4.0, 0.0, 6.0),
            row(6.0, 0.0, 12.0),
        ];
        assert_eq!(loading_slope(&load), Some(3.0));
        assert_eq!(loading_slope(&load[..2]), None);
    }
}
