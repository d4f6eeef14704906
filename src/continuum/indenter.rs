//! Rigid axisymmetric indenters: the gap (signed distance) from a point of the specimen's
//! surface to the indenter, its gradient and Hessian.
//!
//! Coordinates (r, z): the specimen occupies z ≤ 0, the indenter comes from above, its tip at
//! z = −δ (δ > 0 penetration). The gap of a point x is g(x, δ) = G(x_r, x_z + δ), G the signed
//! distance to the indenter with its tip at the origin (positive outside); so ∂g/∂δ = ∂G/∂z.
//! For a body of revolution the nearest point lies in the meridian plane of x, so G is a 2D
//! distance.
//!
//! - Sphere of radius R: G = |p − c| − R, c = (0, R); ∇G = n = (p − c)/|p − c|,
//!   ∇²G = (I − n⊗n)/|p − c|.
//! - Blunt Berkovich (PHYSICS.md, seed §2.3): the sphere up to the tip depth h_t (junction
//!   radius r_t = √(2Rh_t − h_t²)), then the cone of half-angle θ = 70.3° (the Berkovich
//!   equivalent cone, same area–depth function) through the junction. With
//!   h_t = R(1 − sin θ) the cone is tangent to the sphere (R = 1.8 µm gives h_t ≈ 105 nm,
//!   the seed's "spherical up to 100 nm"); a smaller h_t leaves a convex kink whose nearest
//!   points are the junction circle itself.

use serde::{Deserialize, Serialize};

/// Why an indenter is unusable, or a depth beyond what it represents.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IndenterError {
    /// the radius is not positive and finite
    #[error("indenter radius must be positive, got {radius} nm")]
    Radius {
        /// the radius, nm
        radius: f64,
    },
    /// the cone half-angle is outside (0, 90) degrees
    #[error("cone half-angle must lie in (0, 90) degrees, got {half_angle_deg}")]
    HalfAngle {
        /// the half-angle, degrees
        half_angle_deg: f64,
    },
    /// the sphere–cone junction would not be convex
    #[error("tip_depth must lie in (0, R(1 − sin θ)] = (0, {h_max:.4}] nm for a convex tip, got {tip_depth} nm")]
    TipDepth {
        /// the tip depth asked for, nm
        tip_depth: f64,
        /// the largest convex tip depth R(1 − sin θ), nm
        h_max: f64,
    },
    /// the depth is not below the sphere's radius, the deepest the sphere represents
    #[error(
        "indenter depth {depth:.6e} nm is not below the sphere radius {radius} nm, the \
         deepest the sphere (no shank) represents; with a soft machine spring or load \
         control nothing holds the indenter before contact: use smaller increments or \
         approach first"
    )]
    TooDeep {
        /// the indenter depth, nm
        depth: f64,
        /// the sphere's radius, nm
        radius: f64,
    },
}

/// Half-angle of the cone equivalent to a Berkovich pyramid, degrees.
pub const BERKOVICH_CONE_HALF_ANGLE_DEG: f64 = 70.3;

/// A rigid indenter.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "kebab-case")]
pub enum Indenter {
    /// sphere of radius `radius` (nm)
    Sphere {
        /// radius R, nm
        radius: f64,
    },
    /// sphere up to `tip_depth`, then a cone of half-angle `half_angle_deg`
    BerkovichBlunt {
        /// tip radius R, nm
        radius: f64,
        /// depth of the spherical cap h_t, nm (≤ R(1 − sin θ))
        tip_depth: f64,
        /// cone half-angle θ, degrees (70.3 for Berkovich)
        half_angle_deg: f64,
    },
}

/// Gap, gradient and Hessian at a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gap {
    /// signed distance g, nm (positive open)
    pub gap: f64,
    /// ∇g = outward unit normal of the indenter at the nearest point
    pub normal: [f64; 2],
    /// ∇²g, 1/nm
    pub hessian: [[f64; 2]; 2],
}

/// The distance to a point `q` seen from `p`.
fn gap_to_point(p: [f64; 2], q: [f64; 2], offset: f64) -> Gap {
    let v = [p[0] - q[0], p[1] - q[1]];
    let d = v[0].hypot(v[1]);
    if d == 0.0 {
        return Gap {
            gap: -offset,
            normal: [0.0, -1.0],
            hessian: [[0.0; 2]; 2],
        };
    }
    let n = [v[0] / d, v[1] / d];
    let mut h = [[0.0; 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            h[i][j] = ((i == j) as u8 as f64 - n[i] * n[j]) / d;
        }
    }
    Gap {
        gap: d - offset,
        normal: n,
        hessian: h,
    }
}

impl Indenter {
    /// Tip radius R, nm.
    pub fn radius(&self) -> f64 {
        match *self {
            Indenter::Sphere { radius } | Indenter::BerkovichBlunt { radius, .. } => radius,
        }
    }

    /// The blunt Berkovich with the tip depth at which the cone is tangent to the sphere.
    pub fn berkovich_tangent(radius: f64) -> Self {
        let th = BERKOVICH_CONE_HALF_ANGLE_DEG.to_radians();
        Indenter::BerkovichBlunt {
            radius,
            tip_depth: radius * (1.0 - th.sin()),
            half_angle_deg: BERKOVICH_CONE_HALF_ANGLE_DEG,
        }
    }

    /// Check the dimensions (and convexity of the sphere–cone junction).
    pub fn validate(&self) -> Result<(), IndenterError> {
        let r = self.radius();
        if !(r > 0.0 && r.is_finite()) {
            return Err(IndenterError::Radius { radius: r });
        }
        if let Indenter::BerkovichBlunt {
            tip_depth,
            half_angle_deg,
            ..
        } = *self
        {
            if !(half_angle_deg > 0.0 && half_angle_deg < 90.0) {
                return Err(IndenterError::HalfAngle { half_angle_deg });
            }
            let h_max = r * (1.0 - half_angle_deg.to_radians().sin());
            if !(tip_depth > 0.0 && tip_depth <= h_max * (1.0 + 1e-9)) {
                return Err(IndenterError::TipDepth { tip_depth, h_max });
            }
        }
        Ok(())
    }

    /// Refuse a depth the indenter's shape does not represent: the sphere has no shank, so
    /// beyond δ = R its modelled surface no longer covers the contact (past δ ≈ 2R the specimen
    /// would lie above it, out of contact: a false equilibrium). A Newton iterate gets there
    /// when nothing holds the indenter before contact (a soft spring, K ≪ the contact
    /// stiffness, driven far in one increment); the driver then cuts the increment back.
    pub fn check_depth(&self, depth: f64) -> Result<(), IndenterError> {
        match *self {
            Indenter::Sphere { radius } if !(depth < radius) => {
                Err(IndenterError::TooDeep { depth, radius })
            }
            _ => Ok(()),
        }
    }

    /// Gap of the surface point `x` = (r, z) with the indenter at depth `depth` (nm).
    pub fn gap(&self, x: [f64; 2], depth: f64) -> Gap {
        let p = [x[0], x[1] + depth];
        match *self {
            Indenter::Sphere { radius } => gap_to_point(p, [0.0, radius], radius),
            Indenter::BerkovichBlunt {
                radius,
                tip_depth,
                half_angle_deg,
            } => {
                let c = [0.0, radius];
                let r_t = (2.0 * radius * tip_depth - tip_depth * tip_depth).sqrt();
                let phi_t = (r_t / radius).min(1.0).asin();
                let (v0, v1) = (p[0] - c[0], p[1] - c[1]);
                if v0.atan2(-v1) <= phi_t {
                    return gap_to_point(p, c, radius);
                }
                let (s, co) = half_angle_deg.to_radians().sin_cos();
                let q = [r_t, tip_depth];
                let w = [p[0] - q[0], p[1] - q[1]];
                if w[0] * s + w[1] * co >= 0.0 {
                    Gap {
                        gap: w[0] * co - w[1] * s,
                        normal: [co, -s],
                        hessian: [[0.0; 2]; 2],
                    }
                } else {
                    gap_to_point(p, q, 0.0)
                }
            }
        }
    }

    /// Expected contact radius at depth δ (nm): Hertz √(Rδ) on the sphere, Sneddon's
    /// (2/π)δ tan θ on the cone — used only to size the default mesh.
    pub fn contact_radius_estimate(&self, depth: f64) -> f64 {
        let d = depth.max(0.0);
        let sphere = (self.radius() * d).sqrt();
        match *self {
            Indenter::Sphere { .. } => sphere,
            Indenter::BerkovichBlunt { half_angle_deg, .. } => {
                sphere.max(2.0 / std::f64::consts::PI * d * half_angle_deg.to_radians().tan())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FD_TOL: f64 = 1e-6; // central differences, step 1e-6 nm, on lengths of order 1–100 nm

    fn check(ind: &Indenter, x: [f64; 2], depth: f64) {
        let g = ind.gap(x, depth);
        let h = 1e-6;
        for j in 0..2 {
            let (mut xp, mut xm) = (x, x);
            xp[j] += h;
            xm[j] -= h;
            let (gp, gm) = (ind.gap(xp, depth), ind.gap(xm, depth));
            assert!(
                ((gp.gap - gm.gap) / (2.0 * h) - g.normal[j]).abs() < FD_TOL,
                "{x:?}"
            );
            for i in 0..2 {
                let fd = (gp.normal[i] - gm.normal[i]) / (2.0 * h);
                assert!((fd - g.hessian[i][j]).abs() < FD_TOL, "{x:?} H[{i}][{j}]");
            }
        }
        // ∂g/∂δ = n_z
        let dd = (ind.gap(x, depth + h).gap - ind.gap(x, depth - h).gap) / (2.0 * h);
        assert!((dd - g.normal[1]).abs() < FD_TOL);
    }

    #[test]
    fn sphere_gap_is_the_distance_with_exact_derivatives() {
        let s = Indenter::Sphere { radius: 100.0 };
        assert!((s.gap([0.0, -2.0], 3.0).gap + 1.0).abs() < 1e-12); // tip at z = −3
        let g = s.gap([30.0, 0.0], 0.0).gap;
        assert!((g - ((30f64.powi(2) + 100f64.powi(2)).sqrt() - 100.0)).abs() < 1e-12);
        for x in [[10.0, -1.0], [50.0, 2.0], [0.0, -0.5]] {
            check(&s, x, 1.0);
        }
    }

    #[test]
    fn blunt_berkovich_is_the_sphere_then_the_cone_with_exact_derivatives() {
        let b = Indenter::berkovich_tangent(1800.0);
        b.validate().unwrap();
        if let Indenter::BerkovichBlunt { tip_depth, .. } = b {
            assert!((tip_depth - 105.3).abs() < 0.1, "{tip_depth}");
        }
        // on the cone far out: the surface z = h_t + (r − r_t) cot θ passes at gap 0
        let th = 70.3f64.to_radians();
        let (r_t, h_t) = (1800.0 * th.cos(), 1800.0 * (1.0 - th.sin()));
        let r = 2000.0;
        let z = h_t + (r - r_t) / th.tan();
        assert!(b.gap([r, z], 0.0).gap.abs() < 1e-9);
        // the sphere near the tip agrees with the plain sphere
        let s = Indenter::Sphere { radius: 1800.0 };
        assert_eq!(b.gap([100.0, -1.0], 5.0), s.gap([100.0, -1.0], 5.0));
        for x in [
            [100.0, -1.0],
            [700.0, -20.0],
            [1500.0, 0.0],
            [3000.0, -50.0],
        ] {
            check(&b, x, 30.0);
        }
        // a kinked (non-tangent) tip: the junction point region
        let k = Indenter::BerkovichBlunt {
            radius: 1800.0,
            tip_depth: 50.0,
            half_angle_deg: 70.3,
        };
        k.validate().unwrap();
        for x in [[430.0, 40.0], [600.0, 0.0], [100.0, -1.0]] {
            check(&k, x, 10.0);
        }
        assert!(Indenter::BerkovichBlunt {
            radius: 1800.0,
            tip_depth: 200.0,
            half_angle_deg: 70.3
        }
        .validate()
        .is_err());
    }
}
