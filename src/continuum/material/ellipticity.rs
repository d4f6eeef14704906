//! Strong ellipticity of a material state in the (R, Z) plane. The acoustic tensor of the
//! first elasticity tensor A = ∂P/∂F,
//!
//! Q_ik(N) = A_iJkL N_J N_L,  A_iJkL = δ_ik S_JL + F_iI F_kK 𝔺_IJKL,
//!
//! is formed from a material's exact S and 𝔺 ([`super::Response`]) for in-plane unit normals
//! N = (sin θ, cos θ) and in-plane polarisations (i, k ∈ {R, Z}). While the smallest eigenvalue
//! of Q over all N is positive the state is strongly elliptic in the plane; where it reaches
//! zero the equilibrium equations admit a jump of the displacement gradient across a line of
//! normal N — a band localises (in a fibre material compressed along its fibres, a kink band:
//! Rosen's microbuckling), and a local continuum has no length to set the band's width, so the
//! FE's answer then depends on its mesh and Newton meets a tangent that is indefinite in the
//! band's mode.

use super::{Response, VOIGT_PAIRS};

/// The in-plane direction of least acoustic stiffness.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AcousticMinimum {
    /// smallest eigenvalue of Q over the normals sampled, GPa (≤ 0: not strongly elliptic)
    pub eigenvalue: f64,
    /// the normal's angle from the Z axis (the indentation axis), degrees in [0, 180)
    pub normal_deg: f64,
}

/// The Voigt slot of the in-plane index pair (i, j) (0 = R, 1 = Z).
fn slot(i: usize, j: usize) -> usize {
    VOIGT_PAIRS
        .iter()
        .position(|&(a, b)| (a, b) == (i, j) || (b, a) == (i, j))
        .unwrap_or(3)
}

/// The smallest eigenvalue of the acoustic tensor over `directions` normals evenly spaced in
/// angle, for the material `response` at the in-plane deformation gradient `f` (rows R, Z).
pub fn in_plane_minimum(
    response: &Response,
    f: [[f64; 2]; 2],
    directions: usize,
) -> AcousticMinimum {
    let (s, c) = (&response.stress, &response.tangent);
    let mut a = [[[[0.0; 2]; 2]; 2]; 2];
    for (i, ai) in a.iter_mut().enumerate() {
        for (jj, aij) in ai.iter_mut().enumerate() {
            for (k, aijk) in aij.iter_mut().enumerate() {
                for (l, v) in aijk.iter_mut().enumerate() {
                    let mut x = if i == k { s[slot(jj, l)] } else { 0.0 };
                    for (ii, fi) in f[i].iter().enumerate() {
                        for (kk, fk) in f[k].iter().enumerate() {
                            x += fi * fk * c[slot(ii, jj)][slot(kk, l)];
                        }
                    }
                    *v = x;
                }
            }
        }
    }
    let mut best = AcousticMinimum {
        eigenvalue: f64::INFINITY,
        normal_deg: 0.0,
    };
    for d in 0..directions.max(1) {
        let theta = std::f64::consts::PI * d as f64 / directions.max(1) as f64;
        let n = [theta.sin(), theta.cos()];
        let mut q = [[0.0; 2]; 2];
        for (i, qi) in q.iter_mut().enumerate() {
            for (k, v) in qi.iter_mut().enumerate() {
                for (jj, nj) in n.iter().enumerate() {
                    for (l, nl) in n.iter().enumerate() {
                        *v += a[i][jj][k][l] * nj * nl;
                    }
                }
            }
        }
        let mean = 0.5 * (q[0][0] + q[1][1]);
        let half = (0.5 * (q[0][0] - q[1][1])).hypot(0.5 * (q[0][1] + q[1][0]));
        if mean - half < best.eigenvalue {
            best = AcousticMinimum {
                eigenvalue: mean - half,
                normal_deg: theta.to_degrees(),
            };
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::continuum::material::linear::LinearElastic;
    use crate::continuum::material::{Deformation, Material};

    #[test]
    fn an_isotropic_solid_at_rest_has_the_shear_modulus_as_its_least_wave_stiffness() {
        // Q = μI + (λ + μ)N⊗N: eigenvalues μ and λ + 2μ for every N
        let m = LinearElastic {
            youngs: 0.7,
            poisson: 0.3,
        };
        let (lambda, mu) = m.lame();
        let r = m
            .response(&Deformation::from_c([1.0, 1.0, 1.0, 0.0]), &[], 0.0)
            .unwrap();
        let q = in_plane_minimum(&r, [[1.0, 0.0], [0.0, 1.0]], 90);
        assert!(
            (q.eigenvalue - mu).abs() < 1e-12 * (lambda + 2.0 * mu),
            "{q:?}"
        );
    }
}
