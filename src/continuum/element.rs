//! The axisymmetric 3-node triangle (CST) in total-Lagrangian finite deformation, and its
//! small-strain counterpart (seed chapter 4).
//!
//! Reference nodes Xₐ = (Rₐ, Zₐ), displacements uₐ, constant shape gradients bₐ = ∇₀Nₐ. The
//! deformation gradient is block-diagonal:
//!
//! F = [[I + Σₐ uₐ ⊗ bₐ, 0], [0, r/R]],
//!
//! with the hoop stretch r/R taken at the centroid (one-point rule; so a rigid rotation about
//! the centroid leaves r/R = 1 and gives no stress). Energy Πₑ = w ψ(C), C = FᵀF, with the
//! volume weight w = 2π R_c A ([`volume_weight`], the only place the 2πr factor appears for
//! the solid). Force fₑ = w Bᵀ S, with δE = B δu (Voigt, engineering shear), and the exact
//! tangent Kₑ = w (Bᵀ 𝔺 B + G), G the geometric (initial-stress) part
//! G_(ak)(bl) = δ_kl bₐ·S·b_b + δ_kr δ_lr S_θθ/(3R_c)².
//!
//! Small kinematics (`Kinematics::Small`): the same energy with the linearised strain
//! ε = sym ∇u, ε_θθ = u_r/R, fed to the material as E = ε (C = I + 2ε), B evaluated at F = I and no
//! geometric term — for linear elasticity exactly Hooke's small-strain theory.

use super::material::{Deformation, Material, MaterialError, Response, Voigt};
use serde::{Deserialize, Serialize};

/// Which kinematics the elements use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kinematics {
    /// total-Lagrangian finite deformation
    #[default]
    Finite,
    /// linearised (small-strain) kinematics
    Small,
}

/// The reference geometry of one triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    /// node indices, counter-clockwise in (R, Z)
    pub nodes: [usize; 3],
    /// shape-function gradients ∇₀Nₐ, 1/nm
    pub grad: [[f64; 2]; 3],
    /// reference area, nm²
    pub area: f64,
    /// reference centroid radius R_c, nm (> 0)
    pub r_c: f64,
}

/// Why an element cannot be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ElementError {
    /// the reference triangle is degenerate or clockwise
    #[error("element {0}: degenerate or clockwise reference triangle")]
    BadGeometry(usize),
    /// the deformed triangle is inverted (J ≤ 0)
    #[error("element {element}: inverted, J = {jac:e}")]
    Inverted {
        /// element index
        element: usize,
        /// det F
        jac: f64,
    },
    /// the material failed
    #[error("element {element}: {source}")]
    Material {
        /// element index
        element: usize,
        /// cause
        source: MaterialError,
    },
}

/// Energy, force and tangent of one element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementOutput {
    /// Πₑ, aJ
    pub energy: f64,
    /// ∂Πₑ/∂u, nN, dofs ordered (u_r, u_z) per node
    pub force: [f64; 6],
    /// ∂²Πₑ/∂u², nN/nm (zero when not asked for)
    pub stiffness: [[f64; 6]; 6],
}

/// The reference geometry of triangle `nodes` at positions `x`.
pub fn geometry(
    index: usize,
    nodes: [usize; 3],
    x: [[f64; 2]; 3],
) -> Result<Geometry, ElementError> {
    let two_a =
        (x[1][0] - x[0][0]) * (x[2][1] - x[0][1]) - (x[2][0] - x[0][0]) * (x[1][1] - x[0][1]);
    let r_c = (x[0][0] + x[1][0] + x[2][0]) / 3.0;
    if !(two_a > 0.0 && r_c > 0.0) {
        return Err(ElementError::BadGeometry(index));
    }
    let mut grad = [[0.0; 2]; 3];
    for a in 0..3 {
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        grad[a] = [(x[b][1] - x[c][1]) / two_a, (x[c][0] - x[b][0]) / two_a];
    }
    Ok(Geometry {
        nodes,
        grad,
        area: 0.5 * two_a,
        r_c,
    })
}

/// The volume of the ring swept by the triangle, w = 2π R_c A (nm³): the one place where the
/// axisymmetric 2πr weight of the solid enters.
pub fn volume_weight(g: &Geometry) -> f64 {
    2.0 * std::f64::consts::PI * g.r_c * g.area
}

/// Kinematic state of an element: F (in-plane 2×2 and hoop) and the deformation its material
/// sees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strain {
    /// in-plane deformation gradient (identity under small kinematics)
    pub f: [[f64; 2]; 2],
    /// hoop stretch r/R (1 under small kinematics)
    pub f_hoop: f64,
    /// E = ½(H + Hᵀ + HᵀH) from the displacement gradient H (finite), or ε (small), with
    /// C = I + 2E
    pub d: Deformation,
}

/// The strain measure of element `g` under displacements `u`.
pub fn strain(g: &Geometry, u: &[f64; 6], kin: Kinematics) -> Strain {
    let mut h = [[0.0; 2]; 2]; // displacement gradient ∇₀u
    let mut ur = 0.0;
    for a in 0..3 {
        for i in 0..2 {
            for j in 0..2 {
                h[i][j] += u[2 * a + i] * g.grad[a][j];
            }
        }
        ur += u[2 * a] / 3.0;
    }
    let hoop = ur / g.r_c;
    match kin {
        Kinematics::Finite => {
            let f = [[1.0 + h[0][0], h[0][1]], [h[1][0], 1.0 + h[1][1]]];
            // E from H itself: C − I formed from C would lose E's low digits
            let e = [
                h[0][0] + 0.5 * (h[0][0] * h[0][0] + h[1][0] * h[1][0]),
                h[1][1] + 0.5 * (h[0][1] * h[0][1] + h[1][1] * h[1][1]),
                hoop + 0.5 * hoop * hoop,
                0.5 * (h[0][1] + h[1][0] + h[0][0] * h[0][1] + h[1][0] * h[1][1]),
            ];
            Strain {
                f,
                f_hoop: 1.0 + hoop,
                d: Deformation::from_green(e),
            }
        }
        Kinematics::Small => Strain {
            f: [[1.0, 0.0], [0.0, 1.0]],
            f_hoop: 1.0,
            d: Deformation::from_green([h[0][0], h[1][1], hoop, 0.5 * (h[0][1] + h[1][0])]),
        },
    }
}

/// det F of the element (finite kinematics) — or of I + ∇u (small), for the inversion check.
fn jacobian(g: &Geometry, u: &[f64; 6]) -> f64 {
    let s = strain(g, u, Kinematics::Finite);
    (s.f[0][0] * s.f[1][1] - s.f[0][1] * s.f[1][0]) * s.f_hoop
}

/// What every element of a step shares: kinematics, material and time step.
#[derive(Clone, Copy)]
pub struct StepContext<'a> {
    /// finite or small kinematics
    pub kinematics: Kinematics,
    /// the constitutive model
    pub material: &'a dyn Material,
    /// time step of the increment, s
    pub dt: f64,
}

/// Energy, force and (if `tangent`) stiffness of element `index` with history `history`.
pub fn evaluate(
    index: usize,
    g: &Geometry,
    u: &[f64; 6],
    ctx: &StepContext,
    history: &[f64],
    tangent: bool,
) -> Result<ElementOutput, ElementError> {
    let (kin, material, dt) = (ctx.kinematics, ctx.material, ctx.dt);
    let jac = jacobian(g, u);
    if !(jac > 0.0) {
        return Err(ElementError::Inverted {
            element: index,
            jac,
        });
    }
    let s = strain(g, u, kin);
    let Response {
        energy,
        stress,
        tangent: d,
    } = material
        .response(&s.d, history, dt)
        .map_err(|source| ElementError::Material {
            element: index,
            source,
        })?;
    let w = volume_weight(g);
    let b = b_matrix(g, &s);
    let mut force = [0.0; 6];
    for (p, fp) in force.iter_mut().enumerate() {
        *fp = w * (0..4).map(|i| b[i][p] * stress[i]).sum::<f64>();
    }
    let mut stiffness = [[0.0; 6]; 6];
    if tangent {
        let mut db = [[0.0; 6]; 4]; // 𝔺 B
        for i in 0..4 {
            for p in 0..6 {
                db[i][p] = (0..4).map(|j| d[i][j] * b[j][p]).sum();
            }
        }
        for p in 0..6 {
            for q in 0..6 {
                stiffness[p][q] = w * (0..4).map(|i| b[i][p] * db[i][q]).sum::<f64>();
            }
        }
        if kin == Kinematics::Finite {
            let hoop = stress[2] / (9.0 * g.r_c * g.r_c);
            for a in 0..3 {
                for c in 0..3 {
                    let (ga, gc) = (g.grad[a], g.grad[c]);
                    let sab = ga[0] * (stress[0] * gc[0] + stress[3] * gc[1])
                        + ga[1] * (stress[3] * gc[0] + stress[1] * gc[1]);
                    for k in 0..2 {
                        stiffness[2 * a + k][2 * c + k] += w * sab;
                    }
                    stiffness[2 * a][2 * c] += w * hoop;
                }
            }
        }
    }
    Ok(ElementOutput {
        energy: w * energy,
        force,
        stiffness,
    })
}

/// B with δE = B δu (Voigt rows RR, ZZ, θθ, 2RZ; columns (u_r, u_z) per node).
fn b_matrix(g: &Geometry, s: &Strain) -> [[f64; 6]; 4] {
    let f = s.f;
    let mut b = [[0.0; 6]; 4];
    for a in 0..3 {
        let ba = g.grad[a];
        for k in 0..2 {
            let p = 2 * a + k;
            b[0][p] = f[k][0] * ba[0];
            b[1][p] = f[k][1] * ba[1];
            b[3][p] = f[k][0] * ba[1] + f[k][1] * ba[0];
        }
        b[2][2 * a] = s.f_hoop / (3.0 * g.r_c);
    }
    b
}

/// Cauchy stress σ = F S Fᵀ / J (finite) or S (small), Voigt, GPa.
pub fn cauchy(s: &Strain, pk2: &Voigt, kin: Kinematics) -> Voigt {
    if kin == Kinematics::Small {
        return *pk2;
    }
    let f = s.f;
    let j = (f[0][0] * f[1][1] - f[0][1] * f[1][0]) * s.f_hoop;
    let sm = [[pk2[0], pk2[3]], [pk2[3], pk2[1]]];
    let mut fs = [[0.0; 2]; 2];
    for i in 0..2 {
        for k in 0..2 {
            fs[i][k] = f[i][0] * sm[0][k] + f[i][1] * sm[1][k];
        }
    }
    let mut sig = [[0.0; 2]; 2];
    for i in 0..2 {
        for k in 0..2 {
            sig[i][k] = (fs[i][0] * f[k][0] + fs[i][1] * f[k][1]) / j;
        }
    }
    [
        sig[0][0],
        sig[1][1],
        pk2[2] * s.f_hoop * s.f_hoop / j,
        sig[0][1],
    ]
}

#[cfg(test)]
mod tests {
    use super::super::material::hyperfoam::{Hyperfoam, HyperfoamTerm};
    use super::super::material::linear::LinearElastic;
    use super::*;

    const FD_TOL: f64 = 1e-6; // central differences with step 1e-7·size: relative error ~1e-8
    const ROT_TOL: f64 = 1e-12; // a rigid rotation gives C = I up to round-off

    fn ctx(kinematics: Kinematics, material: &dyn Material) -> StepContext<'_> {
        StepContext {
            kinematics,
            material,
            dt: 0.0,
        }
    }

    fn tri() -> Geometry {
        geometry(0, [0, 1, 2], [[0.5, -1.0], [2.0, -0.7], [1.1, 0.3]]).unwrap()
    }

    fn foam() -> Hyperfoam {
        Hyperfoam {
            terms: vec![HyperfoamTerm {
                mu: 0.35,
                alpha: 9.1,
                beta: 0.15,
            }],
        }
    }

    #[test]
    fn force_and_stiffness_match_finite_differences_in_both_kinematics() {
        let g = tri();
        let u = [0.05, -0.1, -0.08, 0.02, 0.1, -0.15];
        let m = foam();
        for kin in [Kinematics::Finite, Kinematics::Small] {
            let out = evaluate(0, &g, &u, &ctx(kin, &m), &[], true).unwrap();
            let h = 1e-7;
            let fmax = out.force.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let kmax = out
                .stiffness
                .iter()
                .flatten()
                .fold(0.0f64, |a, v| a.max(v.abs()));
            for q in 0..6 {
                let (mut up, mut um) = (u, u);
                up[q] += h;
                um[q] -= h;
                let op = evaluate(0, &g, &up, &ctx(kin, &m), &[], true).unwrap();
                let om = evaluate(0, &g, &um, &ctx(kin, &m), &[], true).unwrap();
                let f_fd = (op.energy - om.energy) / (2.0 * h);
                assert!(
                    (f_fd - out.force[q]).abs() < FD_TOL * fmax,
                    "{kin:?} force {q}"
                );
                for p in 0..6 {
                    let k_fd = (op.force[p] - om.force[p]) / (2.0 * h);
                    assert!(
                        (k_fd - out.stiffness[p][q]).abs() < FD_TOL * kmax,
                        "{kin:?} K[{p}][{q}]: {k_fd} vs {}",
                        out.stiffness[p][q]
                    );
                }
            }
        }
    }

    #[test]
    fn rigid_rotation_about_the_centroid_gives_no_stress_only_in_finite_kinematics() {
        let x = [[0.5, -1.0], [2.0, -0.7], [1.1, 0.3]];
        let g = geometry(0, [0, 1, 2], x).unwrap();
        let zc = (x[0][1] + x[1][1] + x[2][1]) / 3.0;
        let rotation = |angle: f64| {
            let (s, c) = angle.sin_cos();
            let mut u = [0.0; 6];
            for a in 0..3 {
                let (dr, dz) = (x[a][0] - g.r_c, x[a][1] - zc);
                u[2 * a] = c * dr - s * dz - dr;
                u[2 * a + 1] = s * dr + c * dz - dz + 0.7; // plus an axial translation
            }
            u
        };
        let m = LinearElastic {
            youngs: 1.0,
            poisson: 0.3,
        };
        let u = rotation(1.0); // 57°
        let fin = evaluate(0, &g, &u, &ctx(Kinematics::Finite, &m), &[], false).unwrap();
        assert!(
            fin.force.iter().all(|f| f.abs() < ROT_TOL),
            "{:?}",
            fin.force
        );
        assert!(fin.energy.abs() < ROT_TOL);
        // 17°: under small kinematics 57° would strain the element by cos 57° − 1 = −0.46,
        // past the linear model's range (an error, see material::linear)
        let u = rotation(0.3);
        let small = evaluate(0, &g, &u, &ctx(Kinematics::Small, &m), &[], false).unwrap();
        assert!(small.energy > 1e-3, "small strain is not objective");
    }

    #[test]
    fn inverted_and_degenerate_elements_are_errors() {
        assert!(geometry(3, [0, 1, 2], [[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]]).is_err());
        let g = tri();
        let u = [0.0, 0.0, -3.0, 0.0, 0.0, 0.0];
        let m = foam();
        assert!(matches!(
            evaluate(0, &g, &u, &ctx(Kinematics::Finite, &m), &[], false),
            Err(ElementError::Inverted { .. })
        ));
    }
}
