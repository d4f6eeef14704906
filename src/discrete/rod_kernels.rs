//! Element kernels of the discrete elastica: one stretched edge, one bent vertex.
//!
//! Pure functions of the edge vectors, returning the energy with its exact gradient and Hessian
//! with respect to those edge vectors; the scatter to node coordinates lives in [`super::rod`].
//!
//! - Stretching of an edge e with rest length ℓ and axial stiffness EA (nN):
//!   W_s = EA/(2ℓ) (|e| − ℓ)², the continuum ½ EA ε² per unit length.
//! - Bending at the vertex between edges e (incoming) and f (outgoing), discrete elastic rods
//!   (Bergou, Wardetzky, Robinson, Audoly & Grinspun, SIGGRAPH 2008, eq. 1 and §4.2): the
//!   curvature binormal κb = 2 (e × f)/(|e||f| + e·f), of magnitude 2 tan(φ/2) for a turning
//!   angle φ, and W_b = K/(ℓ_e + ℓ_f) |κb − κb⁰|² with ℓ_e, ℓ_f the rest lengths and K = YI
//!   (nN·nm²). With ℓ̄ = (ℓ_e + ℓ_f)/2 the Voronoi length and κ ≈ φ/ℓ̄ this is K κ² ℓ̄/2: the
//!   elastica's ½ K κ² per unit length.
//!
//! Derivatives (y = (e, f) ∈ ℝ⁶, u = e × f, d = |e||f| + e·f, κb = 2u/d):
//! ∂u/∂e = −[f]×, ∂u/∂f = [e]×, ∂²u_k/∂e_a∂f_b = ε_kab;
//! ∂d/∂e = |f| ê + f, ∂d/∂f = |e| f̂ + e, ∂²d/∂e² = (|f|/|e|)(I − êêᵀ),
//! ∂²d/∂f² = (|e|/|f|)(I − f̂f̂ᵀ), ∂²d/∂e∂f = ê f̂ᵀ + I;
//! ∇κ_k = 2∇u_k/d − 2u_k ∇d/d², and
//! ∇²κ_k = 2∇²u_k/d − 2(∇u_k ∇dᵀ + ∇d ∇u_kᵀ)/d² − 2u_k ∇²d/d² + 4u_k ∇d ∇dᵀ/d³;
//! for W = c|κb − κb⁰|² (r = κb − κb⁰): ∇W = 2c Σ_k r_k ∇κ_k and
//! ∇²W = 2c Σ_k (∇κ_k ∇κ_kᵀ + r_k ∇²κ_k).
//!
//! The vertex is singular only for a full fold-back (e·f = −|e||f|, d = 0): the energy is then
//! infinite or NaN and the solvers report it as non-finite.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// 6×6 matrix over the two edge vectors (e, f) of a vertex.
pub type Mat6 = SMatrix<f64, 6, 6>;
/// 6-vector (e, f).
pub type Vec6 = SVector<f64, 6>;

/// Energy (aJ), gradient (nN) and Hessian (nN/nm) of one stretched edge with respect to its
/// edge vector e = x_{j+1} − x_j.
pub fn stretch_edge(e: &Vector3<f64>, rest: f64, axial: f64) -> (f64, Vector3<f64>, Matrix3<f64>) {
    let len = e.norm();
    let t = e / len;
    let k = axial / rest;
    let ext = len - rest;
    let energy = 0.5 * k * ext * ext;
    let grad = t * (k * ext);
    let ttt = t * t.transpose();
    let hess = ttt * k + (Matrix3::identity() - ttt) * (k * ext / len);
    (energy, grad, hess)
}

/// Energy (aJ) and gradient (nN) of one stretched edge, without the Hessian.
pub fn stretch_edge_gradient(e: &Vector3<f64>, rest: f64, axial: f64) -> (f64, Vector3<f64>) {
    let len = e.norm();
    let k = axial / rest;
    let ext = len - rest;
    (0.5 * k * ext * ext, e * (k * ext / len))
}

/// Energy (aJ) and gradient (nN) of one bent vertex, without the Hessian:
/// ∇W = 2c [(2/d)(f × r, r × e) − 2 (r·u)/d² ∇d], since Σ_k r_k ∇u_k = (f × r, r × e).
pub fn bend_vertex_gradient(
    e: &Vector3<f64>,
    f: &Vector3<f64>,
    natural: &Vector3<f64>,
    weight: f64,
) -> (f64, Vector3<f64>, Vector3<f64>) {
    let (le, lf) = (e.norm(), f.norm());
    let u = e.cross(f);
    let d = le * lf + e.dot(f);
    let r = u * (2.0 / d) - natural;
    let a = 4.0 * weight / d;
    let b = 4.0 * weight * r.dot(&u) / (d * d);
    let ge = f.cross(&r) * a - (e * (lf / le) + f) * b;
    let gf = r.cross(e) * a - (f * (le / lf) + e) * b;
    (weight * r.norm_squared(), ge, gf)
}

/// Curvature binormal κb = 2 (e × f)/(|e||f| + e·f) (dimensionless, |κb| = 2 tan(φ/2)).
pub fn curvature_binormal(e: &Vector3<f64>, f: &Vector3<f64>) -> Vector3<f64> {
    e.cross(f) * (2.0 / (e.norm() * f.norm() + e.dot(f)))
}

/// Energy (aJ), gradient (nN) and Hessian (nN/nm) of one bent vertex with respect to
/// y = (e, f): W = `weight` |κb(e, f) − `natural`|², weight = K/(ℓ_e + ℓ_f) (aJ).
pub fn bend_vertex(
    e: &Vector3<f64>,
    f: &Vector3<f64>,
    natural: &Vector3<f64>,
    weight: f64,
) -> (f64, Vec6, Mat6) {
    let (le, lf) = (e.norm(), f.norm());
    let (te, tf) = (e / le, f / lf);
    let u = e.cross(f);
    let d = le * lf + e.dot(f);
    let kb = u * (2.0 / d);
    let r = kb - natural;
    let energy = weight * r.norm_squared();

    // ∇d and ∇²d
    let mut gd = Vec6::zeros();
    gd.fixed_rows_mut::<3>(0).copy_from(&(te * lf + f));
    gd.fixed_rows_mut::<3>(3).copy_from(&(tf * le + e));
    let eye = Matrix3::identity();
    let mut hd = Mat6::zeros();
    hd.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&((eye - te * te.transpose()) * (lf / le)));
    hd.fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&((eye - tf * tf.transpose()) * (le / lf)));
    let cross = te * tf.transpose() + eye;
    hd.fixed_view_mut::<3, 3>(0, 3).copy_from(&cross);
    hd.fixed_view_mut::<3, 3>(3, 0)
        .copy_from(&cross.transpose());

    // ∇u_k: rows of [−[f]×, [e]×]
    let du_e = -f.cross_matrix();
    let du_f = e.cross_matrix();

    let mut grad = Vec6::zeros();
    let mut hess = Mat6::zeros();
    for k in 0..3 {
        let mut gu = Vec6::zeros();
        for a in 0..3 {
            gu[a] = du_e[(k, a)];
            gu[3 + a] = du_f[(k, a)];
        }
        let gk = gu * (2.0 / d) - gd * (2.0 * u[k] / (d * d));
        // ∇²u_k: ε_kab in the (e, f) block and its transpose
        let mut hu = Mat6::zeros();
        for a in 0..3 {
            for b in 0..3 {
                let eps = levi_civita(k, a, b);
                hu[(a, 3 + b)] = eps;
                hu[(3 + b, a)] = eps;
            }
        }
        let sym = gu * gd.transpose() + gd * gu.transpose();
        let hk = hu * (2.0 / d) - sym * (2.0 / (d * d)) - hd * (2.0 * u[k] / (d * d))
            + gd * gd.transpose() * (4.0 * u[k] / (d * d * d));
        grad += gk * (2.0 * weight * r[k]);
        hess += (gk * gk.transpose() + hk * r[k]) * (2.0 * weight);
    }
    (energy, grad, hess)
}

fn levi_civita(i: usize, j: usize, k: usize) -> f64 {
    match (i, j, k) {
        (0, 1, 2) | (1, 2, 0) | (2, 0, 1) => 1.0,
        (0, 2, 1) | (2, 1, 0) | (1, 0, 2) => -1.0,
        _ => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64;

    /// Central differences with step 1e-6 on O(1)-sized inputs: truncation ~1e-12, round-off
    /// ~1e-10 relative; 1e-6 leaves a wide margin while catching any wrong term.
    const FD_TOL: f64 = 1e-6;
    const H: f64 = 1e-6;

    fn random_vec(rng: &mut Pcg64) -> Vector3<f64> {
        Vector3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
    }

    fn rel_err(a: f64, b: f64, scale: f64) -> f64 {
        (a - b).abs() / scale.max(1e-12)
    }

    #[test]
    fn bending_gradient_and_hessian_match_finite_differences() {
        let mut rng = Pcg64::seed_from_u64(7);
        for _ in 0..20 {
            let e = random_vec(&mut rng) + Vector3::new(1.0, 0.0, 0.0);
            let f = random_vec(&mut rng) + Vector3::new(1.0, 0.0, 0.0);
            let nat = random_vec(&mut rng) * 0.3;
            let w = 1.7;
            let y = |v: &Vec6| {
                (
                    Vector3::new(v[0], v[1], v[2]),
                    Vector3::new(v[3], v[4], v[5]),
                )
            };
            let mut y0 = Vec6::zeros();
            y0.fixed_rows_mut::<3>(0).copy_from(&e);
            y0.fixed_rows_mut::<3>(3).copy_from(&f);
            let (_, g, hm) = bend_vertex(&e, &f, &nat, w);
            let gscale = g.amax();
            let hscale = hm.amax();
            for a in 0..6 {
                let mut yp = y0;
                let mut ym = y0;
                yp[a] += H;
                ym[a] -= H;
                let (ep, fp) = y(&yp);
                let (em, fm) = y(&ym);
                let (wp, gp, _) = bend_vertex(&ep, &fp, &nat, w);
                let (wm, gm, _) = bend_vertex(&em, &fm, &nat, w);
                assert!(rel_err((wp - wm) / (2.0 * H), g[a], gscale) < FD_TOL);
                for b in 0..6 {
                    let fd = (gp[b] - gm[b]) / (2.0 * H);
                    assert!(rel_err(fd, hm[(b, a)], hscale) < FD_TOL, "H[{b},{a}]");
                }
            }
            assert!((hm - hm.transpose()).amax() <= 1e-12 * hscale);
        }
    }

    #[test]
    fn lean_gradients_equal_the_full_kernels() {
        let mut rng = Pcg64::seed_from_u64(13);
        for _ in 0..20 {
            let e = random_vec(&mut rng) + Vector3::new(1.0, 0.0, 0.0);
            let f = random_vec(&mut rng) + Vector3::new(1.0, 0.0, 0.0);
            let nat = random_vec(&mut rng) * 0.3;
            let (w, g, _) = bend_vertex(&e, &f, &nat, 2.3);
            let (w2, ge, gf) = bend_vertex_gradient(&e, &f, &nat, 2.3);
            // same quantity by two formulas: round-off only
            assert!((w - w2).abs() <= 1e-14 * w.abs().max(1.0));
            for a in 0..3 {
                assert!((g[a] - ge[a]).abs() < 1e-12 * g.amax());
                assert!((g[3 + a] - gf[a]).abs() < 1e-12 * g.amax());
            }
            let (ws, gs, _) = stretch_edge(&e, 0.9, 3.0);
            let (ws2, gs2) = stretch_edge_gradient(&e, 0.9, 3.0);
            assert!((ws - ws2).abs() < 1e-14 && (gs - gs2).amax() < 1e-13);
        }
    }

    #[test]
    fn stretching_gradient_and_hessian_match_finite_differences() {
        let mut rng = Pcg64::seed_from_u64(11);
        for _ in 0..20 {
            let e = random_vec(&mut rng) + Vector3::new(1.5, 0.0, 0.0);
            let (rest, ea) = (1.3, 2.5);
            let (_, g, hm) = stretch_edge(&e, rest, ea);
            for a in 0..3 {
                let (mut ep, mut em) = (e, e);
                ep[a] += H;
                em[a] -= H;
                let (wp, gp, _) = stretch_edge(&ep, rest, ea);
                let (wm, gm, _) = stretch_edge(&em, rest, ea);
                assert!(rel_err((wp - wm) / (2.0 * H), g[a], g.amax()) < FD_TOL);
                for b in 0..3 {
                    let fd = (gp[b] - gm[b]) / (2.0 * H);
                    assert!(rel_err(fd, hm[(b, a)], hm.amax()) < FD_TOL);
                }
            }
        }
    }

    #[test]
    fn curvature_binormal_is_two_tan_half_angle_and_invariant() {
        let phi: f64 = 0.7;
        let e = Vector3::new(2.0, 0.0, 0.0);
        let f = Vector3::new(phi.cos(), phi.sin(), 0.0) * 0.5;
        let kb = curvature_binormal(&e, &f);
        assert!((kb.norm() - 2.0 * (phi / 2.0).tan()).abs() < 1e-14);
        assert!((kb - Vector3::new(0.0, 0.0, kb.norm())).norm() < 1e-14);
        // straight: zero energy, zero gradient
        let (w, g, _) = bend_vertex(&e, &e, &Vector3::zeros(), 1.0);
        assert!(w == 0.0 && g.amax() == 0.0);
    }
}
