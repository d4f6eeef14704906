//! The quasi-rheological model of a force-controlled (Hysitron-type) indentation test
//! (seed §2.3, eqs. 2.1–2.7, Fig 2.1b).
//!
//! The transducer applies a force P(t) to the indenter's plate, which is held by the support
//! springs k₁ (to the frame) and reaches the specimen through the load-frame spring k₂. The
//! specimen is K₁ in series with a Kelvin element (K₂ ∥ η). Q is the true force on the specimen
//! and δ its indentation depth; the plate displacement is h = δ + Q/k₂ and P = k₁h + Q.
//! With δ₂ the Kelvin element's extension and (seed 2.4)
//!
//! 1/χ = 1/k₁ + 1/k₂,  ω = k₁(1/χ + 1/K₁),  1/ζ = 1 + χ/K₁,  ψ = 1 + K₂/K₁,
//!
//! the machine gives Q = χ(P/k₁ − δ) = (P − k₁δ₂)/ω and the dashpot
//!
//! ωη dδ₂/dt = P(t) − (k₁ + ωK₂)δ₂,  τ = ωη/(k₁ + ωK₂) = η/(k₁/ω + K₂)  (seed 2.5, its α = ω).
//!
//! For P = P₀ + Ṗt (2.1) this is solved exactly on each segment:
//! δ₂(t) = (P(t) − Ṗτ)/(k₁+ωK₂) + (δ₂(0) − (P₀ − Ṗτ)/(k₁+ωK₂)) e^(−t/τ). It reproduces the
//! seed's (2.2)–(2.3) (steady rates δ̇ = Ṗψ/(k₁+ωK₂), Q̇ = ṖK₂/(k₁+ωK₂)). Consequences checked in
//! the tests: during a hold (Ṗ = 0) Q and δ move along a line of slope dQ/dδ = −χ (seed 2.6
//! quotes its magnitude χ: the force relaxes while the depth creeps, a machine property); on
//! first loading dQ/dδ = K₁ at t = 0⁺ (2.7), tending to K₁K₂/(K₁+K₂) ≈ K₁ for K₂ ≫ K₁.
//!
//! Units: forces nN, lengths nm, stiffnesses nN/nm, η in nN·s/nm, times s.

use super::{positive, TheoryError};

/// Machine and specimen constants.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Rheology {
    /// k₁: transducer support springs, nN/nm
    pub machine_k1: f64,
    /// k₂: load-frame spring in series with the specimen, nN/nm
    pub machine_k2: f64,
    /// K₁: the specimen's instantaneous spring, nN/nm
    pub specimen_k1: f64,
    /// K₂: the spring of the specimen's Kelvin element, nN/nm
    pub specimen_k2: f64,
    /// η: the dashpot of the Kelvin element, nN·s/nm
    pub viscosity: f64,
}

/// One piece of the force schedule: P changes linearly to `end_load` over `duration`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Segment {
    /// length of the segment, s (> 0)
    pub duration: f64,
    /// applied force at its end, nN (equal to the start for a hold)
    pub end_load: f64,
}

impl Segment {
    /// The usual test: load to `peak` (nN) over `load` s, hold it for `hold` s, unload to zero
    /// over `unload` s.
    pub fn load_hold_unload(peak: f64, load: f64, hold: f64, unload: f64) -> [Segment; 3] {
        [
            Segment {
                duration: load,
                end_load: peak,
            },
            Segment {
                duration: hold,
                end_load: peak,
            },
            Segment {
                duration: unload,
                end_load: 0.0,
            },
        ]
    }
}

/// The state at one instant.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Sample {
    /// time, s
    pub t: f64,
    /// applied force P, nN
    pub p: f64,
    /// true force on the specimen Q, nN
    pub q: f64,
    /// indentation depth δ, nm
    pub delta: f64,
    /// displacement of the indenter plate h = δ + Q/k₂, nm
    pub h: f64,
}

impl Rheology {
    fn check(&self) -> Result<(), TheoryError> {
        positive("machine k₁", self.machine_k1)?;
        positive("machine k₂", self.machine_k2)?;
        positive("specimen K₁", self.specimen_k1)?;
        positive("specimen K₂", self.specimen_k2)?;
        positive("viscosity η", self.viscosity)?;
        Ok(())
    }

    /// χ = (1/k₁ + 1/k₂)⁻¹, nN/nm: the magnitude of dQ/dδ during a hold (seed 2.6).
    pub fn chi(&self) -> f64 {
        1.0 / (1.0 / self.machine_k1 + 1.0 / self.machine_k2)
    }

    /// ω = k₁(1/χ + 1/K₁) (dimensionless, seed 2.4).
    pub fn omega(&self) -> f64 {
        self.machine_k1 * (1.0 / self.chi() + 1.0 / self.specimen_k1)
    }

    /// Relaxation time τ = ωη/(k₁ + ωK₂), s (seed 2.5).
    pub fn tau(&self) -> f64 {
        self.omega() * self.viscosity / self.relaxed_stiffness()
    }

    fn relaxed_stiffness(&self) -> f64 {
        self.machine_k1 + self.omega() * self.specimen_k2
    }

    /// The state for applied force P and Kelvin extension δ₂.
    fn sample(&self, t: f64, p: f64, delta2: f64) -> Sample {
        let q = (p - self.machine_k1 * delta2) / self.omega();
        let delta = q / self.specimen_k1 + delta2;
        Sample {
            t,
            p,
            q,
            delta,
            h: delta + q / self.machine_k2,
        }
    }

    /// Run the schedule from rest (P = 0, δ₂ = 0 at t = 0), sampling each segment at
    /// `per_segment` equal steps (plus the start); exact at every sample.
    pub fn simulate(
        &self,
        schedule: &[Segment],
        per_segment: usize,
    ) -> Result<Vec<Sample>, TheoryError> {
        self.check()?;
        if per_segment == 0 {
            return Err(TheoryError::OutOfDomain {
                what: "samples per segment",
                value: 0.0,
                allowed: "at least 1".into(),
            });
        }
        let (tau, stiff) = (self.tau(), self.relaxed_stiffness());
        let (mut t0, mut p0, mut d2) = (0.0, 0.0, 0.0);
        let mut out = vec![self.sample(0.0, 0.0, 0.0)];
        for seg in schedule {
            positive("segment duration", seg.duration)?;
            if !seg.end_load.is_finite() {
                return Err(TheoryError::NotFinite {
                    what: "segment end load",
                    value: seg.end_load,
                });
            }
            let rate = (seg.end_load - p0) / seg.duration;
            let c = d2 - (p0 - rate * tau) / stiff;
            for i in 1..=per_segment {
                let dt = seg.duration * i as f64 / per_segment as f64;
                let p = p0 + rate * dt;
                let delta2 = (p - rate * tau) / stiff + c * (-dt / tau).exp();
                out.push(self.sample(t0 + dt, p, delta2));
            }
            t0 += seg.duration;
            p0 = seg.end_load;
            d2 = (p0 - rate * tau) / stiff + c * (-seg.duration / tau).exp();
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rheo() -> Rheology {
        Rheology {
            machine_k1: 200.0,
            machine_k2: 5e4,
            specimen_k1: 30.0,
            specimen_k2: 600.0,
            viscosity: 900.0,
        }
    }

    #[test]
    fn machine_equilibrium_holds_at_every_sample() {
        let r = rheo();
        let sched = Segment::load_hold_unload(1e4, 5.0, 10.0, 5.0);
        for s in r.simulate(&sched, 20).unwrap() {
            // P = k₁h + Q and Q = χ(P/k₁ − δ), to round-off of 1e4 nN
            assert!((r.machine_k1 * s.h + s.q - s.p).abs() < 1e-9 * 1e4);
            assert!((r.chi() * (s.p / r.machine_k1 - s.delta) - s.q).abs() < 1e-9 * 1e4);
        }
    }
}
