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
//!   in the JKR limit). An increment at a fixed drive (a hold) is creep, never a jump: the
//!   gap moves there with time, not with the drive.
//! - **Limit points.** A curve traced by arc-length continuation ([`super::arclength`]) has no
//!   jumps: it turns back at the folds of the S-curve. A fold is a row inside a schedule segment
//!   where the drive reaches a local extremum (the drive reverses between its neighbours of the
//!   same segment): the first local maximum is the jump-in fold (the approach can go no
//!   deeper on the out-of-contact branch), the first local minimum the jump-out fold (the
//!   retraction can go no further on the contact branch: the pull-off under this drive). An
//!   elastic S-curve is one curve: the approach, traced through, already passes both. A curve with folds is reported
//!   without jumps (near a fold the gap changes much faster than the drive, which the jump
//!   test would misread).
//! - **Hold and loading figures** ([`hold_figures`], [`loading_slope`]), for comparison with the
//!   quasi-rheological model (seed §2.3): during a hold the load relaxes and the depth creeps,
//!   along dQ/dδ = −K through a spring K or −χ through the transducer (seed 2.6); the loading
//!   branch's slope dQ/dδ stands for the specimen's instantaneous stiffness K₁ (seed 2.7).
//! - **Contact radius** (every row): the outermost radius where the gap is below the law's
//!   equilibrium gap z₀, i.e. where the LJ pressure changes sign from repulsive to attractive
//!   ([`super::contact::Contact::contact_radius`]), as in the half-space solver.

use super::indent::{IndentResult, Row};
use serde::Serialize;
use std::f64::consts::PI;

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
    let dd = b.drive_nm - a.drive_nm;
    dg.abs() > JUMP_RATIO * dd.abs() && dg != 0.0 && dd != 0.0
}

/// The distance of row `r` from the polyline of `traced` in the plane (drive/`length`,
/// load/`force`); infinite for a traced curve of fewer than two rows.
fn distance_from(r: &Row, traced: &[Row], length: f64, force: f64) -> f64 {
    let xy = |r: &Row| (r.drive_nm / length, r.load_nN / force);
    let p = xy(r);
    traced
        .windows(2)
        .map(|w| {
            let (a, b) = (xy(&w[0]), xy(&w[1]));
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let len2 = dx * dx + dy * dy;
            let f = if len2 > 0.0 {
                (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (p.0 - a.0 - f * dx).hypot(p.1 - a.1 - f * dy)
        })
        .fold(f64::INFINITY, f64::min)
}

/// How far a curve stepped by Newton (`stepped`, its jump increments left out) lies from one
/// traced by arc-length (`traced`): the largest distance of a stepped row from the traced
/// polyline in the plane (drive/`length`, load/`force`), with that row and the number of rows
/// compared. A distance rather than a load difference at equal drive, since near a fold the
/// load is steep in the drive (infinitely so at the fold).
pub fn curve_distance(
    stepped: &[Row],
    traced: &[Row],
    length: f64,
    force: f64,
) -> (f64, Option<Row>, usize) {
    let (mut worst, mut at, mut compared) = (0.0f64, None, 0);
    for (i, r) in stepped.iter().enumerate() {
        if i > 0 && jumping(&stepped[i - 1], r) {
            continue;
        }
        let nearest = distance_from(r, traced, length, force);
        if nearest.is_finite() {
            compared += 1;
            if nearest > worst {
                worst = nearest;
                at = Some(*r);
            }
        }
    }
    (worst, at, compared)
}

/// Where a damped run dissipated its damping energy: (on the stable branches, off them), aJ.
/// An increment is on a branch if the row it ends at lies within `tol` of the `traced` curve
/// (in the scaled plane of [`curve_distance`]); the others are the jumps and the viscous
/// relaxation after them, where the state is off the equilibrium curve.
pub fn dissipation_split(
    stepped: &[Row],
    traced: &[Row],
    length: f64,
    force: f64,
    tol: f64,
) -> (f64, f64) {
    stepped.windows(2).fold((0.0, 0.0), |(on, off), w| {
        let d = w[1].damping_dissipated_aJ - w[0].damping_dissipated_aJ;
        if distance_from(&w[1], traced, length, force) <= tol {
            (on + d, off)
        } else {
            (on, off + d)
        }
    })
}

/// The pull-off through a machine spring of stiffness `k` from a traced curve: along `path`,
/// the (δ, P) points of a retraction in order, the first local minimum of the drive
/// Δ = δ + P/K (dP/dδ = −K there: the spring can hold the state no further), or of P itself
/// for `k` = None (load control). The minimum is refined by the parabola through it and its
/// neighbours against the chord length of the path; returns (Δ, P) there (for load control,
/// (δ, P)). Any consistent units (scaled: δ/z₀, P/(πγR), K z₀/(πγR)).
pub fn spring_pull_off(path: &[(f64, f64)], k: Option<f64>) -> Option<(f64, f64)> {
    let value = |&(d, p): &(f64, f64)| match k {
        Some(k) => d + p / k,
        None => p,
    };
    let i = (1..path.len().saturating_sub(1)).find(|&i| {
        value(&path[i]) <= value(&path[i - 1]) && value(&path[i]) < value(&path[i + 1])
    })?;
    let w = [path[i - 1], path[i], path[i + 1]];
    let s1 = (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1);
    let s2 = s1 + (w[2].0 - w[1].0).hypot(w[2].1 - w[1].1);
    let s = [0.0, s1, s2];
    let v = w.map(|q| value(&q));
    // vertex of the parabola through (s_j, v_j)
    let (d1, d2) = ((v[1] - v[0]) / s1, (v[2] - v[1]) / (s2 - s1));
    let curvature = (d2 - d1) / s2;
    let at = if curvature > 0.0 {
        (0.5 * (s1 - d1 / curvature)).clamp(0.0, s2)
    } else {
        s1
    };
    let lagrange = |f: [f64; 3]| {
        (0..3)
            .map(|j| {
                let basis: f64 = (0..3)
                    .filter(|&m| m != j)
                    .map(|m| (at - s[m]) / (s[j] - s[m]))
                    .product();
                f[j] * basis
            })
            .sum::<f64>()
    };
    let load = lagrange(w.map(|q| q.1));
    let drive = match k {
        Some(k) => lagrange(w.map(|q| q.0)) + load / k,
        None => lagrange(w.map(|q| q.0)),
    };
    Some((drive, load))
}

/// Detect the events along `rows`.
pub fn detect(rows: &[Row]) -> Events {
    let mut ev = Events::default();
    // the pull-off is a retraction event: search from the deepest point on, so that a tensile
    // load on the approach (a damped jump-in carries the viscous force of the snap) is not
    // taken for it
    let turn = rows
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.depth_nm.total_cmp(&b.1.depth_nm))
        .map_or(0, |(i, _)| i);
    if let Some((i, min)) = rows
        .iter()
        .enumerate()
        .skip(turn)
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

/// The normalised pull-off P/(πγR) of a run: the passed load minimum, or under load control
/// the load where the indenter separated (None if neither was reached).
pub fn normalised_pull_off(r: &IndentResult) -> Option<f64> {
    let a = r.params.adhesion?;
    let p = match r.separated_nN {
        Some(p) => p,
        None => detect(&r.rows).pull_off?.load_nN,
    };
    Some(p / (PI * a.law.gamma() * r.params.indenter.radius()))
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
    fn a_tensile_spike_on_the_approach_is_no_pull_off() {
        // a damped jump-in carries the viscous force of the snap (−99 nN on the turf_indent
        // card, docs/chain.md) — more tensile than the retraction's −24 nN
        let rows = vec![
            row(0, -3.3, 3.0, -7.3),
            row(0, -3.15, 0.34, -99.0),
            row(0, -3.0, 0.34, -96.0),
            row(1, 10.0, -10.0, 300.0),
            row(2, 2.0, -2.0, -24.4),
            row(2, -10.0, 10.0, -0.4),
        ];
        assert_eq!(detect(&rows).pull_off.unwrap().load_nN, -24.4);
    }

    #[test]
    fn a_hold_at_a_fixed_drive_is_no_jump() {
        // load to drive 10, hold there while the gap creeps, retract: the hold is creep
        let rows = vec![
            row(0, 8.0, -8.0, 8.0),
            row(0, 10.0, -10.0, 10.5),
            row(1, 10.0, -10.002, 9.0),
            row(1, 10.0, -10.003, 8.0),
            row(2, 9.0, -9.0, 6.0),
        ];
        let e = detect(&rows);
        assert!(e.jump_in.is_none() && e.jump_out.is_none(), "{e:?}");
    }

    #[test]
    fn curve_distance_is_the_distance_to_the_traced_polyline() {
        let traced = vec![row(0, 0.0, 1.0, 0.0), row(0, 2.0, 1.0, 2.0)];
        // (1, 0) lies √2/2 from the diagonal, (3, 2) 1 beyond its end; a jump increment is left out
        let stepped = vec![
            row(0, 1.0, 1.0, 0.0),
            row(0, 3.0, 1.0, 2.0),
            row(0, 3.01, 5.0, 9.0),
        ];
        let (d, at, n) = curve_distance(&stepped, &traced, 1.0, 1.0);
        assert!((d - 1.0).abs() < 1e-15 && at.unwrap().drive_nm == 3.0 && n == 2);
        let (d, _, _) = curve_distance(&stepped[..1], &traced, 1.0, 2.0);
        assert!((d - 0.5 / 1.25f64.sqrt()).abs() < 1e-15, "{d}");
    }

    #[test]
    fn dissipation_is_split_by_the_distance_from_the_traced_curve() {
        let traced = vec![row(0, 0.0, 1.0, 0.0), row(0, 2.0, 1.0, 2.0)];
        let mut stepped = vec![
            row(0, 0.5, 1.0, 0.5),
            row(0, 1.0, 1.0, 1.0),
            row(0, 1.0, 0.2, 1.5),
            row(0, 1.5, 0.2, 1.75),
        ];
        for (r, w) in stepped.iter_mut().zip([0.0, 1.0, 11.0, 111.0]) {
            r.damping_dissipated_aJ = w;
        }
        // on the curve: 0.5 → 1 (1 aJ); off it (0.354 and 0.177 away): 10 + 100 aJ
        let (on, off) = dissipation_split(&stepped, &traced, 1.0, 1.0, 0.01);
        assert_eq!((on, off), (1.0, 110.0));
        // a tolerance of 0.3 takes in the last row (0.177 away), not the jump (0.354)
        let (on, off) = dissipation_split(&stepped, &traced, 1.0, 1.0, 0.3);
        assert_eq!((on, off), (101.0, 10.0));
    }

    #[test]
    fn spring_pull_off_finds_the_point_of_slope_minus_k() {
        // a retraction along P = (δ − 1)² − 1 (δ decreasing from 3 to −1): dP/dδ = 2(δ − 1)
        // = −K at δ = 1 − K/2, where P = K²/4 − 1; load control: the minimum −1 at δ = 1
        let path: Vec<(f64, f64)> = (0..=400)
            .map(|i| 3.0 - 0.01 * i as f64)
            .map(|d| (d, (d - 1.0) * (d - 1.0) - 1.0))
            .collect();
        for k in [0.5, 1.0, 2.0] {
            let (drive, load) = spring_pull_off(&path, Some(k)).unwrap();
            let d = 1.0 - k / 2.0;
            // the parabola in chord length matches one in δ to O(h²) with steps h = 0.01
            assert!((load - (k * k / 4.0 - 1.0)).abs() < 1e-4, "{k}: {load}");
            assert!(
                (drive - (d + (k * k / 4.0 - 1.0) / k)).abs() < 1e-4,
                "{k}: {drive}"
            );
        }
        let (d, p) = spring_pull_off(&path, None).unwrap();
        assert!((d - 1.0).abs() < 1e-4 && (p + 1.0).abs() < 1e-8, "{d} {p}");
        // a path that only falls has no pull-off
        assert!(spring_pull_off(&path[..150], None).is_none());
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

    #[test]
    fn hold_and_loading_figures() {
        // a hold along Q = 100 − 4δ: drop 8 nN over 2 nm of creep, slope −4
        let hold = [
            row(0, 10.0, 0.0, 60.0),
            row(0, 11.0, 0.0, 56.0),
            row(0, 12.0, 0.0, 52.0),
        ];
        let h = hold_figures(&hold).unwrap();
        assert_eq!((h.load_drop_nN, h.creep_nm), (8.0, 2.0));
        assert_eq!(h.slope_nN_per_nm, Some(-4.0));
        // a rigid drive does not creep: no slope
        let rigid = [row(0, 10.0, 0.0, 60.0), row(0, 10.0, 0.0, 50.0)];
        assert_eq!(hold_figures(&rigid).unwrap().slope_nN_per_nm, None);
        assert!(hold_figures(&hold[..1]).is_none());
        // the tensile start is left out: Q = 3δ − 6 for δ ≥ 2
        let load = [
            row(0, 0.0, 0.0, -5.0),
            row(0, 2.0, 0.0, 0.0),
            row(0, 4.0, 0.0, 6.0),
            row(0, 6.0, 0.0, 12.0),
        ];
        assert_eq!(loading_slope(&load), Some(3.0));
        assert_eq!(loading_slope(&load[..2]), None);
    }
}
