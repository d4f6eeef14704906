//! Presets: the validation problems the ladder, the tests and the examples share, built as
//! plain FE parameters. [`tabor_sphere`] is the adhesive sphere of the half-space solver's
//! scaled units (seed ch. 3–4: pull-off against Tabor's μ), used to check the FE against the
//! half-space and Maugis–Dugdale.

use crate::continuum::adhesion::AdhesionParams;
use crate::continuum::damping::ContactDamping;
use crate::continuum::element::Kinematics;
use crate::continuum::indenter::Indenter;
use crate::continuum::material::hyperfoam::{Hyperfoam, HyperfoamTerm};
use crate::continuum::material::linear::LinearElastic;
use crate::continuum::material::Elastic;
use crate::continuum::{IndentParams, Segment};
use crate::laws::{LennardJones, LjKind};

/// Damping of [`tabor_sphere`]: c₀ in GPa·s/nm at the drive rate of 1 nm/s (its dissipation is
/// reported by every run; the tests hold it below 1 % of the strain energy).
pub const TABOR_SPHERE_DAMPING: f64 = 1e-6;

/// The validation problem in the half-space's terms: a rigid sphere of radius R = `r_over_z0`·z₀
/// (z₀ = 1 nm) on a block with E\* = 1 GPa (ν = 0), γ set by Tabor's μ
/// (γ = μ^(3/2) E\* √(z₀³/R)); approach from 6z₀ clear to δ = 1 nm and retract to 6z₀ clear at
/// 1 nm/s, with contact damping out to a gap of 6z₀.
///
/// The solid is linear at small strain and, at finite kinematics, the compressible neo-Hookean
/// with the same small-strain moduli: the one-term hyperfoam α = 2, β = 0, μ = E/2
/// (U = μ/2 (tr C − 3 − 2 ln J); E₀ = 2μ, ν₀ = 0, so E\* = E₀/(1 − ν₀²) = 1 GPa). Not
/// `Elastic::Linear` at finite kinematics, which is St Venant–Kirchhoff: its compressive stress
/// peaks at a principal stretch of 1/√3, and the surface under a snapping contact at
/// R/z₀ = 200, μ = 3 is compressed beyond it (docs/validation-continuum.md, Fig 6.4).
pub fn tabor_sphere(mu: f64, r_over_z0: f64, kind: LjKind, kinematics: Kinematics) -> IndentParams {
    let (z0, e_star) = (1.0, 1.0);
    let r = r_over_z0 * z0;
    let gamma = mu.powf(1.5) * e_star * (z0 * z0 * z0 / r).sqrt();
    let mut p = IndentParams::hertz_example();
    p.indenter = Indenter::Sphere { radius: r };
    p.material.elastic = match kinematics {
        Kinematics::Small => Elastic::Linear(LinearElastic {
            youngs: e_star,
            poisson: 0.0,
        }),
        Kinematics::Finite => Elastic::Hyperfoam(Hyperfoam {
            terms: vec![HyperfoamTerm {
                mu: 0.5 * e_star,
                alpha: 2.0,
                beta: 0.0,
            }],
        }),
    };
    p.kinematics = kinematics;
    p.start = -6.0 * z0;
    p.schedule = vec![
        Segment::Approach { to: z0, rate: 1.0 },
        Segment::Unload {
            to: -6.0 * z0,
            rate: 1.0,
        },
    ];
    p.adhesion = Some(AdhesionParams {
        law: LennardJones::new(kind, gamma, z0).into(),
        damping: Some(ContactDamping {
            c0: TABOR_SPHERE_DAMPING,
            gap: 6.0 * z0,
            eta: 0.5,
        }),
        area: Default::default(),
    });
    p.solver.increments = 140;
    // validated on a 50a block (docs/validation-continuum.md); on the 200a default, the
    // approach from 6z₀ at μ = 0.1 meets an absolute round-off floor of the residual (~5e-8 nN)
    // above Newton's relative stagnation test, so the first increments fail
    p.mesh.size_factor = 50.0;
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tabor_sphere_has_the_same_small_strain_moduli_at_both_kinematics() {
        for kin in [Kinematics::Small, Kinematics::Finite] {
            let p = tabor_sphere(2.0, 200.0, LjKind::Lj93, kin);
            let (e, nu) = p.material.elastic.initial_moduli();
            assert!(
                (e - 1.0).abs() < 1e-12 && nu.abs() < 1e-12,
                "{kin:?}: {e} {nu}"
            );
        }
        let finite = tabor_sphere(2.0, 200.0, LjKind::Lj93, Kinematics::Finite);
        assert!(matches!(finite.material.elastic, Elastic::Hyperfoam(_)));
    }
}
