//! The shift each body (tube) of the discrete model needs for its own block of the Hessian to be
//! positive definite — a block-diagonal modification of Newton's matrix.
//!
//! The shifted Newton step solves (H + μI) p = −g with one μ for the whole turf: while one tube
//! snaps, every other tube's soft bending modes (stiffness K/L³ ≈ 10⁻³ nN/nm against shifts of
//! 10–10⁴ nN/nm) move by only |g|/μ per iteration, a gradient descent. With a shift per body,
//! (H + D) p = −g with D = diag(μ_b) over body b's coordinates, the tubes whose own block is
//! positive definite take their full Newton step while the snapping ones are held back
//! (Nocedal & Wright, Numerical Optimization §3.4, modified Newton with a diagonal
//! modification, taken here by blocks).
//!
//! Each body's block — its coordinates' entries within [`BAND`] of the diagonal, a rod's
//! stretching and bending couple nodes up to two apart — is tested by a banded Cholesky
//! factorisation with a growing shift: the smallest power-of-ten shift that factors, refined by
//! three geometric bisections, then doubled ([`MARGIN`]) because the contacts couple the
//! blocks. The whole H + D is still factored by the Newton solver, which adds a common shift
//! on top when it fails; every step stays a descent direction.

use rayon::prelude::*;
use std::ops::Range;

/// Half-bandwidth (coordinates) of a body's block kept for the test: a bending vertex couples
/// nodes i − 1 and i + 1, 3·2 + 2 coordinates apart.
pub const BAND: usize = 8;

/// Factor applied to each body's smallest positive-definite shift (the contacts between bodies
/// can take the whole matrix below its diagonal blocks).
pub const MARGIN: f64 = 2.0;

/// Growth of the shift while a block fails to factor.
const GROWTH: f64 = 10.0;

/// Shifts tried per body before giving up on it (the common shift then takes over).
const MAX_ATTEMPTS: usize = 40;

/// The bodies' coordinate ranges and their shifts across Newton iterations.
pub struct BodyShifts {
    bodies: Vec<Range<usize>>,
    /// body of each coordinate (usize::MAX: none)
    body_of: Vec<usize>,
    /// whether each coordinate is free
    free: Vec<bool>,
    /// each body's band, row-major: entry (i, i − d) at i·(BAND + 1) + d, i local
    bands: Vec<Vec<f64>>,
    /// the last shift each body needed (before the margin), 0 if none
    memory: Vec<f64>,
    /// the current shift of each body (with the margin)
    shifts: Vec<f64>,
}

impl BodyShifts {
    /// For `bodies` (coordinate ranges, disjoint) of a model with `n` coordinates, `free`
    /// telling which are free.
    pub fn new(bodies: Vec<Range<usize>>, free: Vec<bool>) -> Self {
        let mut body_of = vec![usize::MAX; free.len()];
        for (b, r) in bodies.iter().enumerate() {
            body_of[r.clone()].iter_mut().for_each(|v| *v = b);
        }
        let bands = bodies
            .iter()
            .map(|r| vec![0.0; r.len() * (BAND + 1)])
            .collect();
        let n = bodies.len();
        BodyShifts {
            bodies,
            body_of,
            free,
            bands,
            memory: vec![0.0; n],
            shifts: vec![0.0; n],
        }
    }

    /// Whether there are bodies at all.
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }

    /// Whether any body is shifted now.
    pub fn any(&self) -> bool {
        self.shifts.iter().any(|&s| s > 0.0)
    }

    /// Number of bodies shifted now.
    pub fn count(&self) -> usize {
        self.shifts.iter().filter(|&&s| s > 0.0).count()
    }

    /// Each body's shift from the Hessian `trip` (full numbering, both triangles); `floor` is
    /// the smallest nonzero shift tried.
    pub fn update(&mut self, trip: &[(usize, usize, f64)], floor: f64) {
        for band in &mut self.bands {
            band.iter_mut().for_each(|v| *v = 0.0);
        }
        for &(r, c, v) in trip {
            let b = self.body_of[r];
            if b == usize::MAX || r < c || r - c > BAND || self.body_of[c] != b {
                continue;
            }
            if self.free[r] && self.free[c] {
                let i = r - self.bodies[b].start;
                self.bands[b][i * (BAND + 1) + (r - c)] += v;
            }
        }
        let free = &self.free;
        let bodies = &self.bodies;
        self.bands
            .par_iter_mut()
            .zip(&mut self.memory)
            .zip(&mut self.shifts)
            .enumerate()
            .for_each(|(b, ((band, memory), shift))| {
                let fixed: Vec<bool> = bodies[b].clone().map(|k| !free[k]).collect();
                // a fixed coordinate's row is the identity: it takes no part in the test
                for (i, &f) in fixed.iter().enumerate() {
                    if f {
                        band[i * (BAND + 1)] = 1.0;
                    }
                }
                let needed = smallest_shift(band, &fixed, floor, *memory);
                *memory = needed;
                *shift = MARGIN * needed;
            });
    }

    /// Add each body's shift to `diag` (indexed by free coordinate, `index` mapping a
    /// coordinate to its free number, usize::MAX when fixed).
    pub fn add_to(&self, index: &[usize], diag: &mut [f64]) {
        for (r, &s) in self.bodies.iter().zip(&self.shifts) {
            if s > 0.0 {
                for k in r.clone() {
                    if index[k] != usize::MAX {
                        diag[index[k]] += s;
                    }
                }
            }
        }
    }
}

/// The smallest shift (0, or `floor`·10^k refined by three geometric bisections) at which the
/// band `a` (fixed rows not shifted) factors; `memory`, the last one needed, starts the climb.
fn smallest_shift(a: &[f64], fixed: &[bool], floor: f64, memory: f64) -> f64 {
    let mut work = vec![0.0; a.len()];
    let mut factors = |shift: f64| {
        work.copy_from_slice(a);
        for (i, &f) in fixed.iter().enumerate() {
            if !f {
                work[i * (BAND + 1)] += shift;
            }
        }
        banded_cholesky(&mut work)
    };
    if factors(0.0) {
        return 0.0;
    }
    let mut hi = floor.max(memory / GROWTH);
    let mut lo = 0.0;
    let mut attempts = 0;
    while !factors(hi) {
        attempts += 1;
        if attempts >= MAX_ATTEMPTS {
            return hi;
        }
        lo = hi;
        hi *= GROWTH;
    }
    let mut lo = if lo > 0.0 { lo } else { hi / GROWTH };
    for _ in 0..3 {
        let mid = (lo * hi).sqrt();
        if factors(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// In-place Cholesky factorisation of a symmetric band (row-major, entry (i, i − d) at
/// i·(BAND + 1) + d); whether every pivot was positive.
fn banded_cholesky(a: &mut [f64]) -> bool {
    let n = a.len() / (BAND + 1);
    let w = BAND + 1;
    for i in 0..n {
        let j0 = i.saturating_sub(BAND);
        for j in j0..=i {
            // L(i, j) = (A(i, j) − Σ_k L(i, k) L(j, k)) / L(j, j), k from max(i, j) − BAND
            let mut s = a[i * w + (i - j)];
            for k in j0.max(j.saturating_sub(BAND))..j {
                s -= a[i * w + (i - k)] * a[j * w + (j - k)];
            }
            if j == i {
                if s.is_nan() || s <= 0.0 {
                    return false;
                }
                a[i * w] = s.sqrt();
            } else {
                a[i * w + (i - j)] = s / a[j * w];
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dense band of the 1D Laplacian-like matrix tridiag(−1, 2 + s, −1) of size n.
    fn band(n: usize, s: f64) -> Vec<f64> {
        let mut a = vec![0.0; n * (BAND + 1)];
        for i in 0..n {
            a[i * (BAND + 1)] = 2.0 + s;
            if i > 0 {
                a[i * (BAND + 1) + 1] = -1.0;
            }
        }
        a
    }

    #[test]
    fn banded_cholesky_reproduces_the_matrix() {
        // a random SPD band: L Lᵀ of the factor equals the input
        let n = 20;
        let mut a = vec![0.0; n * (BAND + 1)];
        for i in 0..n {
            for d in 1..=BAND.min(i) {
                a[i * (BAND + 1) + d] = ((i * 7 + d * 3) % 5) as f64 * 0.1 - 0.2;
            }
            a[i * (BAND + 1)] = 4.0;
        }
        let mut l = a.clone();
        assert!(banded_cholesky(&mut l));
        for i in 0..n {
            for d in 0..=BAND.min(i) {
                let j = i - d;
                let s: f64 = (i.saturating_sub(BAND)..=j)
                    .filter(|&k| j - k <= BAND)
                    .map(|k| l[i * (BAND + 1) + (i - k)] * l[j * (BAND + 1) + (j - k)])
                    .sum();
                assert!((s - a[i * (BAND + 1) + d]).abs() < 1e-12, "({i}, {j})");
            }
        }
    }

    #[test]
    fn the_shift_found_brackets_the_lowest_eigenvalue() {
        // tridiag(−1, 2 + s, −1): eigenvalues s + 2 − 2 cos(kπ/(n+1)); with s = −1 the lowest
        // is −1 + 2 − 2 cos(π/(n+1)) ≈ −0.98
        let n = 30;
        let lowest = 1.0 - 2.0 * (std::f64::consts::PI / (n as f64 + 1.0)).cos();
        let a = band(n, -1.0);
        let fixed = vec![false; n];
        let mu = smallest_shift(&a, &fixed, 1e-6, 0.0);
        // factors at μ, not below −λ_min, and within the bisection's resolution 10^(1/8)
        assert!(
            mu > -lowest && mu < -lowest * 10f64.powf(0.125),
            "{mu} vs {lowest}"
        );
        assert_eq!(smallest_shift(&band(n, 0.5), &fixed, 1e-6, 0.0), 0.0);
    }

    #[test]
    fn bodies_get_their_own_shift() {
        // three bodies of 3 coordinates: the first indefinite (diagonal −1), the second not,
        // the third indefinite only at a fixed coordinate (left out of the test)
        let mut trip = Vec::new();
        for k in 0..3 {
            trip.push((k, k, -1.0));
            trip.push((3 + k, 3 + k, 2.0));
            trip.push((6 + k, 6 + k, if k == 1 { -5.0 } else { 2.0 }));
            // a coupling to the next coordinate, within the band
            if k < 2 {
                trip.push((7 + k, 6 + k, 0.5));
                trip.push((6 + k, 7 + k, 0.5));
            }
        }
        let mut free = vec![true; 9];
        free[7] = false;
        let mut s = BodyShifts::new(vec![0..3, 3..6, 6..9], free.clone());
        s.update(&trip, 1e-3);
        assert_eq!(s.count(), 1);
        let mut index = vec![usize::MAX; 9];
        let mut n = 0;
        for k in (0..9).filter(|&k| free[k]) {
            index[k] = n;
            n += 1;
        }
        let mut diag = vec![0.0; n];
        s.add_to(&index, &mut diag);
        // −λ_min = 1, refined to within 10^(1/8)
        assert!(diag[..3].iter().all(|&d| d > MARGIN && d < MARGIN * 1.34));
        assert!(diag[3..].iter().all(|&d| d == 0.0));
    }
}
