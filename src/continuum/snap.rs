//! Snap-through at a fixed drive (issue 17, item 2): the jump to contact, and any other
//! instability of an adhesive contact, without contact damping.
//!
//! Past a fold of the depth (or of the load) the equilibrium the increments were following
//! ends; the solid jumps (seed §4.3: the jump-in and jump-out of the S-curve). Newton from the
//! last equilibrium then finds no solution however small the increment, and with contact damping
//! the jump is carried by the damper's viscous force (seed eq. 4.4), which adds to the load
//! wherever the gap changes. Instead, where an increment fails at its smallest size, the march
//! ([`super::march`]) holds the drive (loading under load control: the load) there and lets the
//! state *descend* ([`super::newton::descend`]) from the last equilibrium to the next strict
//! local minimum of the total potential Π (solid, law, machine springs, and for a rate-dependent
//! solid its incremental potential over the increment's time step): a state a dynamic snap can
//! come to rest in once its kinetic energy is dissipated (a lightly damped one may overshoot to
//! another), reached without modelling the dynamics. The energy the snap releases, Π before −
//! Π after at the same drive, is what the jump dissipates (in a test, into vibration and heat);
//! each snap is reported with it. Unlike the damper, the snap leaves the load on every branch
//! the increments follow untouched. It is not tried where the material has lost ellipticity
//! (no mesh-independent end state) nor on a load-controlled retraction (there the failure is
//! the pull-off). On an adaptive mesh a snap that ends outside the band goes on from its end
//! state, carried to a mesh whose band covers it (only it: the band need not span the edge
//! before the jump, which would put the whole contact at the smallest size); the energy
//! released is then Π where it started, on the first mesh, − Π at its end on the last.

use serde::Serialize;

/// One snap: where, from what to what, and the energy it released.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[allow(non_snake_case)] // field names carry their units, as the output columns do
pub struct Snap {
    /// schedule segment
    pub segment: usize,
    /// time of the increment that snapped, s
    pub time_s: f64,
    /// the drive held through the snap, as the rows' drive column: δ or the machine's drive
    /// Δ, nm (under load control, the load, nN)
    pub drive_nm: f64,
    /// the indenter's depth before and after, nm
    pub depth_before_nm: f64,
    /// after the snap, nm
    pub depth_after_nm: f64,
    /// the load on the specimen before, nN
    pub load_before_nN: f64,
    /// after the snap, nN
    pub load_after_nN: f64,
    /// Π at the held drive, from the last equilibrium to the minimum the descent reached, aJ
    pub energy_released_aJ: f64,
    /// the descent's Newton iterations
    pub iterations: usize,
}
