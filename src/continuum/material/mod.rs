//! Constitutive models of the solid behind one trait, [`Material`]: energy density ψ(C), second
//! Piola–Kirchhoff stress S = 2∂ψ/∂C and material tangent 𝔺 = 4∂²ψ/∂C∂C, with per-point
//! history for rate-dependent models.
//!
//! A material point sees its [`Deformation`]: the Green–Lagrange strain E = (C − I)/2 as the
//! element computes it from the displacement gradient, and C = I + 2E. The energies are
//! evaluated from E (ψ's terms as expm1/ln_1p of E's invariants), so that ψ keeps its relative
//! precision at small strain: formed from C, Σcₐ^p − 3 carries a round-off of ~ε_mach·μ per
//! unit volume whatever the strain, and Π summed over a large, mostly slightly strained block
//! (R/z₀ = 10⁴: a 27 µm one) then has a noise of 10⁻³ aJ — above the energy changes of a
//! Newton step at a 0.05 nN residual, so a snap's descent could not tell its steps apart.
//!
//! In axisymmetry C is block-diagonal: a 2×2 in-plane block (R, Z) and the hoop entry C_θθ.
//! Symmetric tensors are stored in the Voigt order [RR, ZZ, θθ, RZ] **without** a factor 2 on
//! the shear entry (stress-like); strain increments are paired with engineering shear, so that
//! dψ = S·dE with dE = [dE_RR, dE_ZZ, dE_θθ, 2dE_RZ] and dS = 𝔺·dE. A 4th-order tensor 𝕋 maps
//! to the 4×4 matrix D_IJ = 𝕋_ijkl with I ↔ (ij), J ↔ (kl).
//!
//! [`ellipticity`] tells whether a state can localise (the acoustic tensor).
//!
//! Models: [`linear`] (St Venant–Kirchhoff; Hooke under small kinematics), [`hyperfoam`]
//! (Storåkers/Abaqus `*HYPERFOAM`, seed eq. 5.3 corrected in PHYSICS.md), [`transverse_foam`]
//! (the hyperfoam with fibre and longitudinal-shear terms along the Z axis: the turf's
//! anisotropy), and
//! [`viscoelastic`] (Prony series on the whole stress, seed eq. 5.8, Simo 1987 recurrence).
//! Every model checks J = √det C > 0 and returns an error otherwise.

pub mod ellipticity;
pub mod hyperfoam;
pub mod linear;
pub mod transverse_foam;
pub mod viscoelastic;

use serde::{Deserialize, Serialize};

/// A symmetric axisymmetric tensor in Voigt order [RR, ZZ, θθ, RZ] (no factor 2 on RZ).
pub type Voigt = [f64; 4];
/// A 4×4 material tangent in the same Voigt order (engineering shear on the strain side).
pub type Tangent = [[f64; 4]; 4];

/// Index pairs (i, j) of the 3×3 tensor behind each Voigt slot (0 = R, 1 = Z, 2 = θ).
pub const VOIGT_PAIRS: [(usize, usize); 4] = [(0, 0), (1, 1), (2, 2), (0, 1)];

/// The identity tensor in Voigt form.
pub const IDENTITY: Voigt = [1.0, 1.0, 1.0, 0.0];

/// Energy, stress and tangent at one material point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Response {
    /// energy density per reference volume, GPa (= aJ/nm³); for rate-dependent models the
    /// incremental potential of the step
    pub energy: f64,
    /// second Piola–Kirchhoff stress S, GPa
    pub stress: Voigt,
    /// tangent 𝔺 = 2∂S/∂C, GPa
    pub tangent: Tangent,
}

/// Why a material point cannot be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MaterialError {
    /// det C ≤ 0: the point is inverted or crushed to nothing
    #[error("material point inverted or degenerate: det C = {det_c:e} (J must be > 0)")]
    NonPositiveJ {
        /// the determinant of C
        det_c: f64,
    },
    /// the stress or tangent overflowed
    #[error("non-finite stress or tangent at C = {c:?}")]
    NonFinite {
        /// the right Cauchy–Green tensor, Voigt
        c: Voigt,
    },
    /// the parameters are outside the model's range
    #[error("invalid material parameters: {0}")]
    Invalid(String),
    /// the deformation is outside the range where the model is physical
    #[error("material point outside the model's range: {0}")]
    OutOfRange(String),
    /// the history handed to the point (from the last step, or projected from another mesh) is
    /// not finite
    #[error("history not finite in {bad} of its {len} values (carried from the last step or another mesh)")]
    NonFiniteHistory {
        /// non-finite values
        bad: usize,
        /// values per point
        len: usize,
    },
}

/// A material point's evaluation: its response, or why it cannot be evaluated.
pub type Evaluated = Result<Response, MaterialError>;

/// A constitutive model evaluated at one material point.
pub trait Material: Send + Sync {
    /// Number of history values stored per material point (0 for elastic models).
    fn history_len(&self) -> usize {
        0
    }

    /// ψ, S and 𝔺 at the deformation `d`, given the history at the start of a step of length
    /// `dt` (s).
    fn response(&self, d: &Deformation, history: &[f64], dt: f64) -> Evaluated;

    /// Advance the history to the end of a converged step that ended at `d`.
    fn update_history(
        &self,
        _d: &Deformation,
        _history: &mut [f64],
        _dt: f64,
    ) -> Result<(), MaterialError> {
        Ok(())
    }
}

/// The elastic models selectable from a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "lowercase")]
pub enum Elastic {
    /// St Venant–Kirchhoff (Hooke at small strain)
    Linear(linear::LinearElastic),
    /// N-term hyperfoam
    Hyperfoam(hyperfoam::Hyperfoam),
    /// transversely isotropic hyperfoam, axis Z
    Transverse(transverse_foam::TransverseFoam),
}

impl Elastic {
    /// Initial Young's modulus E and Poisson ratio ν (for Hertz estimates and penalty scales).
    pub fn initial_moduli(&self) -> (f64, f64) {
        match self {
            Elastic::Linear(m) => (m.youngs, m.poisson),
            Elastic::Hyperfoam(m) => m.initial_moduli(),
            Elastic::Transverse(m) => m.initial_moduli(),
        }
    }

    /// Check the parameters.
    pub fn validate(&self) -> Result<(), MaterialError> {
        match self {
            Elastic::Linear(m) => m.validate(),
            Elastic::Hyperfoam(m) => m.validate(),
            Elastic::Transverse(m) => m.validate(),
        }
    }
}

impl Material for Elastic {
    fn response(&self, d: &Deformation, history: &[f64], dt: f64) -> Evaluated {
        match self {
            Elastic::Linear(m) => m.response(d, history, dt),
            Elastic::Hyperfoam(m) => m.response(d, history, dt),
            Elastic::Transverse(m) => m.response(d, history, dt),
        }
    }
}

/// The deformation of a material point: the Green–Lagrange strain E and C = I + 2E, Voigt.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Deformation {
    e: Voigt,
    c: Voigt,
}

impl Deformation {
    /// From the Green–Lagrange strain E (under small kinematics the strain ε).
    pub fn from_green(e: Voigt) -> Self {
        let c = [
            1.0 + 2.0 * e[0],
            1.0 + 2.0 * e[1],
            1.0 + 2.0 * e[2],
            2.0 * e[3],
        ];
        Deformation { e, c }
    }

    /// From the right Cauchy–Green tensor C (E = (C − I)/2, to the precision C holds).
    pub fn from_c(c: Voigt) -> Self {
        let e = [
            0.5 * (c[0] - 1.0),
            0.5 * (c[1] - 1.0),
            0.5 * (c[2] - 1.0),
            0.5 * c[3],
        ];
        Deformation { e, c }
    }

    /// E, Voigt.
    pub fn green(&self) -> &Voigt {
        &self.e
    }

    /// C, Voigt.
    pub fn c(&self) -> &Voigt {
        &self.c
    }

    /// ln J = ½ ln det C, checked det C > 0; from det C − 1 expanded in E, so that it keeps
    /// its relative precision at small strain.
    pub fn ln_jacobian(&self) -> Result<f64, MaterialError> {
        let e = &self.e;
        // det(I + 2E) − 1 of the in-plane block, then with the hoop factor 1 + 2E_θθ
        let block = 2.0 * (e[0] + e[1]) + 4.0 * (e[0] * e[1] - e[3] * e[3]);
        let det_c_minus_1 = block + 2.0 * e[2] * (1.0 + block);
        let det_c = 1.0 + det_c_minus_1;
        if det_c > 0.0 && det_c.is_finite() {
            Ok(0.5 * det_c_minus_1.ln_1p())
        } else {
            Err(MaterialError::NonPositiveJ { det_c })
        }
    }
}

/// The inverse of a Voigt tensor (block-diagonal 2×2 + hoop).
pub fn inverse(c: &Voigt) -> Voigt {
    let d = c[0] * c[1] - c[3] * c[3];
    [c[1] / d, c[0] / d, 1.0 / c[2], -c[3] / d]
}

/// Full 3×3 matrix of a Voigt tensor.
pub fn full(a: &Voigt) -> [[f64; 3]; 3] {
    [[a[0], a[3], 0.0], [a[3], a[1], 0.0], [0.0, 0.0, a[2]]]
}

/// Double contraction A:B of two symmetric tensors (shear counted twice).
pub fn contract(a: &Voigt, b: &Voigt) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + 2.0 * a[3] * b[3]
}

/// Outer product a ⊗ b as a tangent.
pub fn outer(a: &Voigt, b: &Voigt) -> Tangent {
    let mut d = [[0.0; 4]; 4];
    for i in 0..4 {
        for j in 0..4 {
            d[i][j] = a[i] * b[j];
        }
    }
    d
}

/// The symmetrised product 𝕀_ijkl = ½(X_ik Y_jl + X_il Y_jk) as a tangent.
pub fn sym_product(x: &Voigt, y: &Voigt) -> Tangent {
    let (x, y) = (full(x), full(y));
    let mut d = [[0.0; 4]; 4];
    for (a, &(i, j)) in VOIGT_PAIRS.iter().enumerate() {
        for (b, &(k, l)) in VOIGT_PAIRS.iter().enumerate() {
            d[a][b] = 0.5 * (x[i][k] * y[j][l] + x[i][l] * y[j][k]);
        }
    }
    d
}

/// `acc += s·d`.
pub fn add_scaled(acc: &mut Tangent, s: f64, d: &Tangent) {
    for i in 0..4 {
        for j in 0..4 {
            acc[i][j] += s * d[i][j];
        }
    }
}

/// Error unless every stress and tangent entry is finite.
pub fn finite(r: Response, d: &Deformation) -> Evaluated {
    let ok = r.energy.is_finite()
        && r.stress.iter().all(|v| v.is_finite())
        && r.tangent.iter().flatten().all(|v| v.is_finite());
    if ok {
        Ok(r)
    } else {
        Err(MaterialError::NonFinite { c: d.c })
    }
}

/// Finite-difference checks shared by the models' tests.
#[cfg(test)]
pub(crate) mod fd {
    use super::*;

    /// Relative step for central differences in C.
    pub const STEP: f64 = 1e-6;

    /// Largest relative mismatch between S and 2∂ψ/∂C, and between 𝔺 and 2∂S/∂C, by
    /// central differences (relative to the largest entry of each).
    pub fn mismatch(m: &dyn Material, c: &Voigt, history: &[f64], dt: f64) -> (f64, f64) {
        let e = *Deformation::from_c(*c).green();
        let r = m
            .response(&Deformation::from_green(e), history, dt)
            .unwrap();
        // stresses are compared at the scale of the tangent too: S vanishes at C = I
        let dmax = r
            .tangent
            .iter()
            .flatten()
            .fold(1e-300f64, |a, v| a.max(v.abs()));
        let smax = r.stress.iter().fold(dmax, |a, v| a.max(v.abs()));
        let (mut es, mut ed) = (0.0f64, 0.0f64);
        for j in 0..4 {
            // perturb E_j by h (engineering shear: dE_RZ = h/2 for slot 3)
            let h = STEP;
            let (mut ep, mut em) = (e, e);
            let de = if j == 3 { 0.5 * h } else { h };
            ep[j] += de;
            em[j] -= de;
            let rp = m
                .response(&Deformation::from_green(ep), history, dt)
                .unwrap();
            let rm = m
                .response(&Deformation::from_green(em), history, dt)
                .unwrap();
            let s_fd = (rp.energy - rm.energy) / (2.0 * h);
            es = es.max((s_fd - r.stress[j]).abs() / smax);
            for i in 0..4 {
                let d_fd = (rp.stress[i] - rm.stress[i]) / (2.0 * h);
                ed = ed.max((d_fd - r.tangent[i][j]).abs() / dmax);
            }
        }
        (es, ed)
    }

    /// Relative mismatch between ψ at the small strain `e` and the quadratic form ½ ê·𝔺₀·ê of
    /// the tangent at rest (ê = E with engineering shear): O(|E|) (the cubic term) when ψ
    /// keeps its relative precision.
    pub fn quadratic_mismatch(m: &dyn Material, e: Voigt) -> f64 {
        let d0 = m
            .response(&Deformation::from_green([0.0; 4]), &[], 0.0)
            .unwrap()
            .tangent;
        let hat = [e[0], e[1], e[2], 2.0 * e[3]];
        let quadratic: f64 = (0..4)
            .map(|i| {
                (0..4)
                    .map(|j| 0.5 * hat[i] * d0[i][j] * hat[j])
                    .sum::<f64>()
            })
            .sum();
        let psi = m
            .response(&Deformation::from_green(e), &[], 0.0)
            .unwrap()
            .energy;
        (psi - quadratic).abs() / quadratic.abs()
    }

    /// A general small strain of size `size` (every component, shear included).
    pub fn small_strain(size: f64) -> Voigt {
        [0.7 * size, -1.1 * size, 0.4 * size, 0.5 * size]
    }
}
