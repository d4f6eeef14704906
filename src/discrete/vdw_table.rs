//! The tube–tube van der Waals energy with its inner line integral tabulated (the
//! MESONT idea of tabulating the tube–segment interaction, applied to the double line
//! integral of [`super::vdw`], seed §2.4).
//!
//! The energy of a material point p of one axis with a straight segment b (current ends b₀, b₁,
//! current length L, reference length L₀) is the line integral over b's material arclength,
//!
//!   J(p; b) = (L₀/L) ∫₀ᴸ u(√(d² + (σ − s)²)) dσ = (L₀/L) [G(d, L − s) + G(d, s)],
//!
//! with s = (p − b₀)·ê the axial coordinate of p along b, d its distance from b's axis line and
//!
//!   G(d, x) = ∫₀ˣ u(√(d² + σ²)) dσ   (odd in x),
//!
//! a function of two numbers only. G is tabulated once per potential on a (d, x) grid
//! with G_x = u(ρ) and G_dx = u′(ρ) d/ρ exact and G, G_d by 8-point Gauss–Legendre per cell,
//! and interpolated by bicubic Hermite polynomials. The segment-pair energy is Σᵢ Wᵢ J(pᵢ; b)
//! over the material Gauss points of a (the same points and weights as the quadrature kernel):
//! one table look-up per point of a replaces the sum over its partner points on b. The energy
//! is C¹; gradient and Hessian are the exact derivatives of the interpolant (the Hessian is
//! continuous inside a cell and jumps by the interpolation error across cell lines), checked
//! against finite differences. The point quadrature of [`super::vdw::energy_segment_segment`]
//! stays the reference this kernel is checked against.
//!
//! The table's rows are fine (`D_STEP`) from a gap of −0.5 nm to the cutoff and coarse (0.02 nm)
//! down to a gap of −2 nm, where the law's guard already makes the overlap cost far more than any
//! contact gains. A point of a closer than that floor to b's axis *line* takes the point
//! quadrature's inner sum over b's Gauss points instead ([`InnerSum`], the reference kernel's,
//! on panels graded from [`FLOOR_PANEL`] at b's ends): inside b's span that is a deep overlap
//! only a failed solve reaches, but beyond b's ends it is an ordinary contact — b's tip against
//! a's side, or two tubes end to end — where the distance to the axis line says nothing about
//! the distance to the segment, and no table in (d, x) from the axis' foot holds the integral
//! (continued below its floor, the table gave a tip pressed 1.18 nm into a side at 40° in a
//! relaxed 400-tube turf −0.95 aJ where the quadrature gives +1.3 × 10⁵ aJ). Where a point
//! crosses the floor beyond an end the two meet to the table's accuracy (2e-8 of the energy),
//! so the energy stays continuous for the line search (test
//! `a_tip_against_a_side_matches_the_point_quadrature`).
//!
//! **Memory.** For the seed's tubes the table is ≈ 19 MB (1,576 rows × 382 columns × 4
//! values), beyond a core's L2 cache, and a look-up's arithmetic waits on its loads (two thirds
//! of the look-up's time in a profile of a compressed turf). While a point of a is evaluated,
//! the kernel hints the processor to fetch the cells of the point [`PREFETCH_AHEAD`] places on
//! ([`InnerTable::prefetch`]), so that the misses of consecutive points overlap; the values are
//! the same to the bit.

use rayon::prelude::*;

use super::vdw::{
    energy_segment_segment, quadrature_points, scatter_point, within, InnerSum, LinePairPotential,
    QuadPoint, QuadSegment, SegmentPairEnergy, RHO_DEGENERATE,
};
use crate::numerics::quadrature::gauss_legendre_unit;

/// Row spacing of the table in the axis distance d, nm: the repulsive wall of u varies over
/// ≈ z₀/9 ≈ 0.04 nm. Measured against direct integration (default potential): the largest
/// error of G is 2e-7 at this spacing for gaps 0.23–3.3 nm (1.7e-6 at 0.004 nm), against a
/// depth G(·, ∞) = −γ_L/2 = −0.5 nN, and 5.5e-7 (1.6e-7 of the value) at 0.21 nm, next to the
/// law's guard at 0.5 z₀ where u‴ jumps.
pub const D_STEP: f64 = 0.002;
/// Column spacing of the table in the axial coordinate x, nm: G_x = u is exact at the nodes,
/// and spacings of 0.025–0.1 nm give the same largest error (the rows set it).
pub const X_STEP: f64 = 0.05;
/// Gap (nm) of the table's lowest row; closer points take the point quadrature.
const GAP_FLOOR: f64 = -2.0;
/// Gap (nm) where the fine rows start.
const GAP_FINE: f64 = -0.5;
/// Row spacing between the floor and the fine rows, nm.
const COARSE_STEP: f64 = 0.02;
/// Length (nm) of the panels at b's ends in b's inner rule for the points of a below the
/// table's floor; the panels grow by [`FLOOR_GROWTH`] towards b's middle. Beyond b's tip the
/// distance to b's points grows about as fast as the arclength, so the integrand crosses the
/// repulsive wall (≈ z₀/9 ≈ 0.04 nm) within a few hundredths of a nanometre of the tip and
/// decays away from it: 0.125 nm growing by 1.3 (four Gauss points each) keeps a tip against a
/// side within 7e-6 of the energy and 1e-4 of the largest force of a rule of 0.03 nm panels,
/// where b's own panels (≈ 4 nm on a 200 nm segment) were 4 % off at the equilibrium gap (test
/// `a_tip_against_a_side_matches_the_point_quadrature`). The few nanometres of b within the
/// cutoff of such a point are about ten panels.
const FLOOR_PANEL: f64 = 0.125;
/// Growth of the panels from b's ends towards its middle, for the points below the floor.
const FLOOR_GROWTH: f64 = 1.3;
/// How many quadrature points ahead of the one evaluated the kernel asks for table entries
/// ([`InnerTable::prefetch`]): far enough for the misses to overlap, near enough for the lines
/// to stay in the L1 cache until used (up to eight lines a point).
const PREFETCH_AHEAD: usize = 4;
/// Gauss–Legendre points per table cell for the integrals G and G_d along x.
const CELL_ORDER: usize = 8;

/// G(d, x) of one potential and one radius sum, on a bicubic Hermite grid.
#[derive(Debug, Clone)]
pub struct InnerTable {
    /// sum of the outer radii, nm
    r_sum: f64,
    /// axis distance of the cutoff, nm
    rc: f64,
    /// axis distance of the first row, nm
    d_min: f64,
    /// axis distance of the first fine row, nm
    d_fine: f64,
    /// coarse row spacing (rows 0 ..= `nc`), nm
    hc: f64,
    /// number of coarse cells
    nc: usize,
    /// fine row spacing (rows `nc` .. `nd`), nm
    hd: f64,
    /// number of rows (the last at d = rc, where G ≡ 0)
    nd: usize,
    /// column spacing, nm
    hx: f64,
    /// number of columns (the first at x = 0, the last at the reach √(r_c² − d²) of the first row)
    nx: usize,
    /// for each row, the first column (nm) from which G no longer changes along the row and
    /// the next (at most the last column's, beyond which G(d, x) no longer changes for any
    /// tabulated d)
    flat_from: Vec<f64>,
    /// (G, G_d, G_x, G_dx) at row i, column j: index i·nx + j
    data: Vec<[f64; 4]>,
}

/// G and its derivatives at one (d, x): [G, G_d, G_x, G_dd, G_dx, G_xx].
type Derivs = [f64; 6];

/// Weights of the cubic Hermite data (f₀, f₀′, f₁, f₁′) of a cell of width `h` at local
/// coordinate u ∈ [0, 1]: for the value, the first and the second derivative.
fn hermite(u: f64, h: f64) -> [[f64; 4]; 3] {
    let (u2, u3) = (u * u, u * u * u);
    [
        [
            2.0 * u3 - 3.0 * u2 + 1.0,
            h * (u3 - 2.0 * u2 + u),
            -2.0 * u3 + 3.0 * u2,
            h * (u3 - u2),
        ],
        [
            (6.0 * u2 - 6.0 * u) / h,
            3.0 * u2 - 4.0 * u + 1.0,
            (6.0 * u - 6.0 * u2) / h,
            3.0 * u2 - 2.0 * u,
        ],
        [
            (12.0 * u - 6.0) / (h * h),
            (6.0 * u - 4.0) / h,
            (6.0 - 12.0 * u) / (h * h),
            (6.0 * u - 2.0) / h,
        ],
    ]
}

impl InnerTable {
    /// Tabulate G for `pot` between axes whose outer radii sum to `r_sum` (nm), at row and
    /// column spacings `hd`, `hx` (nm; [`D_STEP`], [`X_STEP`] by default).
    pub fn new(pot: &LinePairPotential, r_sum: f64, hd: f64, hx: f64) -> Self {
        let rc = pot.cutoff(r_sum);
        let d_min = (r_sum + GAP_FLOOR).max(0.5 * r_sum);
        let d_fine = (r_sum + GAP_FINE).max(0.75 * r_sum);
        let nc = ((d_fine - d_min) / COARSE_STEP).ceil() as usize;
        let hc = (d_fine - d_min) / nc as f64;
        let n_fine = ((rc - d_fine) / hd).ceil() as usize + 1;
        let hd = (rc - d_fine) / (n_fine - 1) as f64;
        let nd = nc + n_fine;
        let row_d = |k: usize| {
            if k < nc {
                d_min + k as f64 * hc
            } else {
                d_fine + (k - nc) as f64 * hd
            }
        };
        let x_end = (rc * rc - d_min * d_min).sqrt();
        let nx = (x_end / hx).ceil() as usize + 1;
        let hx = x_end / (nx - 1) as f64;
        let rule = gauss_legendre_unit(CELL_ORDER);
        let row = |i: usize| -> Vec<[f64; 4]> {
            let d = row_d(i);
            // (u, u′ d/ρ) at axial coordinate x
            let integrand = |x: f64| {
                let rho = (d * d + x * x).sqrt();
                let (u, du, _) = pot.eval(rho, r_sum);
                (u, du * d / rho)
            };
            let (mut g, mut gd) = (0.0, 0.0);
            (0..nx)
                .map(|j| {
                    let x = j as f64 * hx;
                    if j > 0 {
                        for &(t, w) in &rule {
                            let (u, ud) = integrand(x - hx + t * hx);
                            g += w * hx * u;
                            gd += w * hx * ud;
                        }
                    }
                    let (u, ud) = integrand(x);
                    [g, gd, u, ud]
                })
                .collect()
        };
        let data = (0..nd).into_par_iter().flat_map_iter(row).collect();
        // one column past the row's reach, so that a reach rounded down cannot leave a cell
        // whose integrand is not exactly zero
        let flat_from = (0..nd)
            .map(|i| {
                let d = row_d(i);
                let reach = (rc * rc - d * d).max(0.0).sqrt();
                let column = ((reach / hx).ceil() as usize + 1).min(nx - 1);
                (column as f64 * hx).min(x_end)
            })
            .collect();
        InnerTable {
            r_sum,
            rc,
            d_min,
            d_fine,
            hc,
            nc,
            hd,
            nd,
            hx,
            nx,
            flat_from,
            data,
        }
    }

    /// The radius sum the table was built for, nm.
    pub fn r_sum(&self) -> f64 {
        self.r_sum
    }

    /// The axis distance of the table's first row, nm.
    pub fn floor(&self) -> f64 {
        self.d_min
    }

    /// Number of grid nodes (rows × columns).
    pub fn nodes(&self) -> usize {
        self.nd * self.nx
    }

    /// [G, G_d, G_x, G_dd, G_dx, G_xx] at axis distance `d` (at or above the floor
    /// [`floor`](Self::floor)) and axial coordinate `x` (nm); the last three are left 0 unless
    /// `second`.
    pub fn eval(&self, d: f64, x: f64, second: bool) -> Derivs {
        if d >= self.rc {
            return [0.0; 6];
        }
        self.eval_in(&self.row(d), x, second)
    }

    /// [`eval`](Self::eval) at axial coordinate `x` in the row cell `row` of an axis distance
    /// below the cutoff: where G is flat in x ([`Self::flat`]) the last column alone, Hermite
    /// in d, at a quarter of the look-ups; else the tensor-product Hermite cell.
    pub fn eval_in(&self, row: &RowCell, x: f64, second: bool) -> Derivs {
        let (ax, sign) = if x < 0.0 { (-x, -1.0) } else { (x, 1.0) };
        let mut out = if self.flat(row, x) {
            self.eval_flat(row, second)
        } else {
            self.eval_cell(row, ax, second)
        };
        // odd in x: G, G_d, G_dd and G_xx change sign with x, G_x and G_dx do not
        for k in [0, 1, 3, 5] {
            out[k] *= sign;
        }
        out
    }

    /// Whether G no longer depends on x at |`x`| in the cell `row`: beyond the reach
    /// √(r_c² − d²) of the cutoff from the cell's closer row (the farther row reaches less),
    /// where every column holds the same G and G_d and a zero G_x and G_dx.
    pub fn flat(&self, row: &RowCell, x: f64) -> bool {
        x.abs() >= self.flat_from[row.i]
    }

    /// G and its derivatives at |x| where G is flat in x: the last column, Hermite in d.
    fn eval_flat(&self, row: &RowCell, second: bool) -> Derivs {
        let mut out = [0.0; 6];
        let last = self.nx - 1;
        let orders: &[(usize, usize)] = if second {
            &[(0, 0), (1, 1), (2, 3)]
        } else {
            &[(0, 0), (1, 1)]
        };
        for &(kd, o) in orders {
            for a in 0..2 {
                let [g, gd, _, _] = self.data[(row.i + a) * self.nx + last];
                out[o] += row.w[kd][2 * a] * g + row.w[kd][2 * a + 1] * gd;
            }
        }
        out
    }

    /// G and its derivatives at `ax` ≥ 0 by the tensor-product Hermite cell: along x on the
    /// two rows (for G and for G_d), then along d.
    fn eval_cell(&self, row: &RowCell, ax: f64, second: bool) -> Derivs {
        let mut out = [0.0; 6];
        let j = ((ax / self.hx) as usize).min(self.nx - 2);
        let xw = hermite(ax / self.hx - j as f64, self.hx);
        let kx_max = if second { 3 } else { 2 };
        let mut along_x = [[[0.0; 3]; 2]; 2]; // [row a][G or G_d][x-derivative order]
        for (a, r) in along_x.iter_mut().enumerate() {
            for b in 0..2 {
                let [g, gd, gx, gdx] = self.data[(row.i + a) * self.nx + j + b];
                for k in 0..kx_max {
                    let (xv, xd) = (xw[k][2 * b], xw[k][2 * b + 1]);
                    r[0][k] += xv * g + xd * gx;
                    r[1][k] += xv * gd + xd * gdx;
                }
            }
        }
        let orders: &[(usize, usize)] = if second {
            &[(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)]
        } else {
            &[(0, 0), (1, 0), (0, 1)]
        };
        for (o, &(kd, kx)) in out.iter_mut().zip(orders) {
            for (a, r) in along_x.iter().enumerate() {
                *o += row.w[kd][2 * a] * r[0][kx] + row.w[kd][2 * a + 1] * r[1][kx];
            }
        }
        out
    }

    /// The row cell and the Hermite weights in d (value, first and second derivative) at
    /// axis distance `d`, at or above the table's floor (the kernel takes the points below it
    /// by the point quadrature).
    pub fn row(&self, d: f64) -> RowCell {
        debug_assert!(d >= self.d_min, "axis distance {d} below the table's floor");
        let (i, u, h) = self.row_position(d);
        RowCell {
            i,
            w: hermite(u, h),
        }
    }

    /// The first row of the cell holding axis distance `d`, the local coordinate in it (0 to
    /// 1) and the cell's height (coarse or fine rows).
    fn row_position(&self, d: f64) -> (usize, f64, f64) {
        if d < self.d_fine {
            let i = (((d - self.d_min) / self.hc) as usize).min(self.nc - 1);
            (i, (d - self.d_min) / self.hc - i as f64, self.hc)
        } else {
            let k = (((d - self.d_fine) / self.hd) as usize).min(self.nd - self.nc - 2);
            (self.nc + k, (d - self.d_fine) / self.hd - k as f64, self.hd)
        }
    }

    /// Ask the processor to bring into its cache the entries a look-up at (`d`, `x`) will read
    /// (`d` at or above the floor): the two rows of its cell at the two columns of its cell, or
    /// at the last column where G is flat. A hint only: no value changes (module doc, "Memory").
    pub fn prefetch(&self, d: f64, x: f64) {
        let i = self.row_position(d).0;
        let j = if x.abs() >= self.flat_from[i] {
            self.nx - 2
        } else {
            ((x.abs() / self.hx) as usize).min(self.nx - 2)
        };
        for a in 0..2 {
            // entries j and j + 1 of the row: 64 contiguous bytes, at most two cache lines
            let k = (i + a) * self.nx + j;
            prefetch_line(&self.data[k][0]);
            prefetch_line(&self.data[k + 1][3]);
        }
    }
}

/// A hint to load the cache line holding `v` (x86-64: `prefetcht0`; elsewhere nothing).
#[inline(always)]
fn prefetch_line(v: &f64) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch never faults and reads nothing into the program's state; the pointer
    // comes from a live reference.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
            (v as *const f64).cast::<i8>(),
        );
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = v;
}

/// The part of a look-up at one axis distance that the two look-ups of a point (at x = s and
/// x = L − s) share: the table's row cell and its Hermite weights in d.
pub struct RowCell {
    /// the cell's first (closer) row
    i: usize,
    /// Hermite weights in d: for the value, the first and the second derivative
    w: [[f64; 4]; 3],
}

type M3 = [[f64; 3]; 3];

/// a bᵀ
fn outer(a: [f64; 3], b: [f64; 3]) -> M3 {
    std::array::from_fn(|i| std::array::from_fn(|j| a[i] * b[j]))
}

/// m += c·x
fn add(m: &mut M3, c: f64, x: &M3) {
    for (mi, xi) in m.iter_mut().zip(x) {
        for (v, w) in mi.iter_mut().zip(xi) {
            *v += c * w;
        }
    }
}

/// The 3 × 3 blocks of a point's Hessian in (r, e) = (p − b₀, b₁ − b₀): rr, re (rows r,
/// columns e), ee.
#[derive(Default, Clone, Copy)]
struct Blocks {
    rr: M3,
    re: M3,
    ee: M3,
}

impl Blocks {
    /// self += c (u vᵀ) for 6-vectors u = (u_r, u_e), v = (v_r, v_e)
    fn add_outer(&mut self, c: f64, u: &[[f64; 3]; 2], v: &[[f64; 3]; 2]) {
        add(&mut self.rr, c, &outer(u[0], v[0]));
        add(&mut self.re, c, &outer(u[0], v[1]));
        add(&mut self.ee, c, &outer(u[1], v[1]));
    }
}

/// Per-pair sums over the points of a (weights W·L₀_b folded in): the (r, e) gradient and its
/// t-moment, and the Hessian blocks' t-moments (t the point's parameter along a).
#[derive(Default)]
struct PointSums {
    energy: f64,
    g_r: [f64; 3],
    g_r_t: [f64; 3],
    g_e: [f64; 3],
    rr: [M3; 3],
    re: [M3; 2],
    ee: M3,
}

/// A point p of segment a seen from segment b's axis: d, s, L and the directions the
/// derivatives need, with the gradients of q = (d, s, L) in (r, e) = (p − b₀, b₁ − b₀).
struct AxisPoint {
    d: f64,
    s: f64,
    len: f64,
    /// unit vector from b's axis line to p
    n: [f64; 3],
    /// b's unit axis ê
    eh: [f64; 3],
    /// the part of r normal to the axis, d n
    rp: [f64; 3],
    /// ∇d, ∇s, ∇L as (r part, e part)
    grads: [[[f64; 3]; 2]; 3],
}

impl AxisPoint {
    fn new(d: f64, s: f64, len: f64, eh: [f64; 3], rp: [f64; 3]) -> Self {
        let n = rp.map(|v| v / d);
        AxisPoint {
            d,
            s,
            len,
            n,
            eh,
            rp,
            grads: [
                [n, n.map(|v| -s * v / len)],
                [eh, rp.map(|v| v / len)],
                [[0.0; 3], eh],
            ],
        }
    }
}

/// J/L₀ = F(d, s, L) = A/L with A = G(d, L − s) + G(d, s), from the look-ups `far` at
/// x = L − s and `near` at x = s: F and its first derivatives in q = (d, s, L).
fn first_derivatives(far: &Derivs, near: &Derivs, len: f64) -> [f64; 4] {
    let aa = far[0] + near[0];
    let (a_d, a_s, a_l) = (far[1] + near[1], near[2] - far[2], far[2]);
    [aa / len, a_d / len, a_s / len, a_l / len - aa / (len * len)]
}

/// The Hessian of F in (r, e) at `p`: Σ_pq F_pq ∇q_p ∇q_qᵀ + F_d ∇²d + F_s ∇²s + F_L ∇²L.
fn point_hessian(p: &AxisPoint, far: &Derivs, near: &Derivs, f: &[f64; 4]) -> Blocks {
    let (d, s, len) = (p.d, p.s, p.len);
    let l2 = len * len;
    let aa = far[0] + near[0];
    let (a_d, a_s, a_l) = (far[1] + near[1], near[2] - far[2], far[2]);
    let (a_dd, a_ds, a_dl) = (far[3] + near[3], near[4] - far[4], far[4]);
    let (a_ss, a_sl, a_ll) = (far[5] + near[5], -far[5], far[5]);
    let f_dl = a_dl / len - a_d / l2;
    let f_sl = a_sl / len - a_s / l2;
    let f_ll = a_ll / len - 2.0 * a_l / l2 + 2.0 * aa / (l2 * len);
    let fqq = [
        [a_dd / len, a_ds / len, f_dl],
        [a_ds / len, a_ss / len, f_sl],
        [f_dl, f_sl, f_ll],
    ];
    // Σ_pq F_pq ∇q_p ∇q_qᵀ = Σ_p ∇q_p v_pᵀ with v_p = Σ_q F_pq ∇q_q
    let mut h = Blocks::default();
    let g = &p.grads;
    for (gp, fp) in g.iter().zip(&fqq) {
        let v: [[f64; 3]; 2] = std::array::from_fn(|half| {
            std::array::from_fn(|k| {
                fp[0] * g[0][half][k] + fp[1] * g[1][half][k] + fp[2] * g[2][half][k]
            })
        });
        h.add_outer(1.0, gp, &v);
    }
    let [_, f_d, f_s, f_l] = *f;
    let (eh, n) = (p.eh, p.n);
    // F_d ∇²d: m = ê × n spans the plane normal to both
    let m = [
        eh[1] * n[2] - eh[2] * n[1],
        eh[2] * n[0] - eh[0] * n[2],
        eh[0] * n[1] - eh[1] * n[0],
    ];
    let (mm, nn) = (outer(m, m), outer(n, n));
    let (en, ne) = (outer(eh, n), outer(n, eh));
    add(&mut h.rr, f_d / d, &mm);
    add(&mut h.re, -f_d / len, &en);
    add(&mut h.re, -f_d * s / (len * d), &mm);
    add(&mut h.ee, -f_d * d / l2, &nn);
    add(&mut h.ee, f_d * s / l2, &en);
    add(&mut h.ee, f_d * s / l2, &ne);
    add(&mut h.ee, f_d * s * s / (l2 * d), &mm);
    // F_s ∇²s and F_L ∇²L, with P = I − ê êᵀ
    let proj: M3 = std::array::from_fn(|i| {
        std::array::from_fn(|j| f64::from(u8::from(i == j)) - eh[i] * eh[j])
    });
    add(&mut h.re, f_s / len, &proj);
    add(&mut h.ee, -f_s / l2, &outer(eh, p.rp));
    add(&mut h.ee, -f_s / l2, &outer(p.rp, eh));
    add(&mut h.ee, -f_s * s / l2 + f_l / len, &proj);
    h
}

/// Energy, gradient and (optionally) Hessian of segments `a` and `b` with the inner integral
/// over `b` from `table` and the outer sum over `a`'s material Gauss points (`rule`), in the
/// local dof order of [`SegmentPairEnergy`]. `point_pairs` counts the points of a within the
/// cutoff of b; `min_gap` is the smallest gap between those points and b's axis segment.
pub fn energy_segment_segment_tabulated(
    pot: &LinePairPotential,
    table: &InnerTable,
    rule: &[(f64, f64)],
    a: &QuadSegment,
    b: &QuadSegment,
    want_hessian: bool,
) -> SegmentPairEnergy {
    let (r_sum, rc) = (table.r_sum, table.rc);
    let mut out = SegmentPairEnergy::none(want_hessian);
    if !within(a, b, rc) {
        return out;
    }
    let e = b.ends[1] - b.ends[0];
    let len = e.length();
    if len < RHO_DEGENERATE {
        // a collapsed segment has no axis: the point quadrature handles it
        return energy_segment_segment(pot, rule, a, b, r_sum, want_hessian);
    }
    let eh = e / len;
    let da = a.ends[1] - a.ends[0];
    // while a point is evaluated, the table entries of the point PREFETCH_AHEAD places on are
    // asked for (module doc, "Memory")
    let hint = |qa: QuadPoint| {
        let r = a.ends[0] + da * qa.t - b.ends[0];
        let s = r.dot(eh);
        let d2 = (r - eh * s).length_squared();
        if d2 < rc * rc && d2 >= table.d_min * table.d_min {
            let d = d2.sqrt();
            table.prefetch(d, s);
            table.prefetch(d, len - s);
        }
    };
    let mut ahead = quadrature_points(rule, a);
    ahead.by_ref().take(PREFETCH_AHEAD).for_each(hint);
    let mut sums = PointSums::default();
    // the points below the table's floor, by the point quadrature over b
    let mut direct: Option<(InnerSum, SegmentPairEnergy)> = None;
    for qa in quadrature_points(rule, a) {
        if let Some(q) = ahead.next() {
            hint(q);
        }
        let p = a.ends[0] + da * qa.t;
        let r = p - b.ends[0];
        let s = r.dot(eh);
        let rp = r - eh * s;
        let d2 = rp.length_squared();
        if d2 >= rc * rc {
            continue;
        }
        let reach = (rc * rc - d2).sqrt();
        if s <= -reach || s >= len + reach {
            continue;
        }
        if d2 < table.d_min * table.d_min {
            let (inner, part) = direct.get_or_insert_with(|| {
                (
                    InnerSum::new(pot, rule, b, r_sum).graded(FLOOR_PANEL, FLOOR_GROWTH),
                    SegmentPairEnergy::none(want_hessian),
                )
            });
            if let Some(partners) = inner.partners(p, want_hessian, part) {
                scatter_point(part, &partners, qa);
            }
            continue;
        }
        let d = d2.sqrt();
        let off = s - s.clamp(0.0, len);
        out.point_pairs += 1;
        out.min_gap = out.min_gap.min((d2 + off * off).sqrt() - r_sum);
        let row = table.row(d);
        let far = table.eval_in(&row, len - s, want_hessian);
        let near = if (0.0..=len).contains(&s) && table.flat(&row, s) && table.flat(&row, len - s) {
            far
        } else {
            table.eval_in(&row, s, want_hessian)
        };
        let f = first_derivatives(&far, &near, len);
        let p = AxisPoint::new(d, s, len, [eh.x, eh.y, eh.z], [rp.x, rp.y, rp.z]);
        let w = qa.weight * b.length0;
        sums.energy += w * f[0];
        let [gd, gs, gl] = &p.grads;
        let g_r: [f64; 3] = std::array::from_fn(|k| w * (f[1] * gd[0][k] + f[2] * gs[0][k]));
        let g_e: [f64; 3] =
            std::array::from_fn(|k| w * (f[1] * gd[1][k] + f[2] * gs[1][k] + f[3] * gl[1][k]));
        for k in 0..3 {
            sums.g_r[k] += g_r[k];
            sums.g_r_t[k] += qa.t * g_r[k];
            sums.g_e[k] += g_e[k];
        }
        if want_hessian {
            sums.add_hessian(w, qa.t, &point_hessian(&p, &far, &near, &f));
        }
    }
    scatter(&mut out, &sums);
    if let Some((_, part)) = direct {
        out.add(&part);
    }
    out
}

impl PointSums {
    /// Add a point's Hessian blocks, weight `w`, at parameter `t` along a, to the t-moments.
    fn add_hessian(&mut self, w: f64, t: f64, h: &Blocks) {
        let tk = [1.0, t, t * t];
        for (mk, t) in self.rr.iter_mut().zip(tk) {
            add(mk, w * t, &h.rr);
        }
        for (mk, t) in self.re.iter_mut().zip(tk) {
            add(mk, w * t, &h.re);
        }
        add(&mut self.ee, w, &h.ee);
    }
}

/// Map the (r, e) sums to the nodes (a₀, a₁, b₀, b₁): r = (α + β t)·nodes, e = γ·nodes with
/// α = (1, 0, −1, 0), β = (−1, 1, 0, 0), γ = (0, 0, −1, 1).
fn scatter(out: &mut SegmentPairEnergy, s: &PointSums) {
    const ALPHA: [f64; 4] = [1.0, 0.0, -1.0, 0.0];
    const BETA: [f64; 4] = [-1.0, 1.0, 0.0, 0.0];
    const GAMMA: [f64; 4] = [0.0, 0.0, -1.0, 1.0];
    out.energy = s.energy;
    for node in 0..4 {
        for k in 0..3 {
            out.grad[3 * node + k] =
                ALPHA[node] * s.g_r[k] + BETA[node] * s.g_r_t[k] + GAMMA[node] * s.g_e[k];
        }
    }
    let Some(h) = out.hessian.as_mut() else {
        return;
    };
    for ni in 0..4 {
        for nj in 0..4 {
            let (ai, bi, ci) = (ALPHA[ni], BETA[ni], GAMMA[ni]);
            let (aj, bj, cj) = (ALPHA[nj], BETA[nj], GAMMA[nj]);
            let c_rr = [ai * aj, ai * bj + bi * aj, bi * bj];
            let c_re = [ai * cj, bi * cj];
            let c_er = [ci * aj, ci * bj];
            for k in 0..3 {
                for l in 0..3 {
                    let mut v = ci * cj * s.ee[k][l];
                    for (c, m) in c_rr.iter().zip(&s.rr) {
                        v += c * m[k][l];
                    }
                    for ((c, c2), m) in c_re.iter().zip(&c_er).zip(&s.re) {
                        v += c * m[k][l] + c2 * m[l][k];
                    }
                    h[(3 * ni + k) * 12 + 3 * nj + l] = v;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrete::vdw::tests::{flat, pair, unflat};
    use crate::discrete::vdw::VdwParams;
    use parry3d_f64::math::Vector;

    const R_SUM: f64 = 40.0;

    fn setup() -> (LinePairPotential, InnerTable, Vec<(f64, f64)>) {
        let pot = LinePairPotential::calibrate(&VdwParams::default()).unwrap();
        let table = InnerTable::new(&pot, R_SUM, D_STEP, X_STEP);
        (pot, table, gauss_legendre_unit(4))
    }

    /// G(d, x) and G_d(d, x) by fine composite Gauss–Legendre (the reference).
    fn direct(pot: &LinePairPotential, d: f64, x: f64) -> (f64, f64) {
        let (panels, rule) = (4000, gauss_legendre_unit(8));
        let h = x / panels as f64;
        let (mut g, mut gd) = (0.0, 0.0);
        for p in 0..panels {
            for &(t, w) in &rule {
                let s = (p as f64 + t) * h;
                let rho = (d * d + s * s).sqrt();
                let (u, du, _) = pot.eval(rho, R_SUM);
                g += w * h * u;
                gd += w * h * du * d / rho;
            }
        }
        (g, gd)
    }

    /// The table against direct integration over the gaps a contact visits (0.2–3.3 nm) and
    /// along the axis, inside and beyond the cutoff's reach. G must be within 1e-6 of the
    /// larger of its own size and the depth |G(·, ∞)| = γ_L/2 — 70× below the default point
    /// quadrature's own discretisation error (7e-5 relative, docs/discrete-compression.md), so
    /// the tabulated kernel is the more accurate one; G_d within 1e-4 of the force at a gap
    /// of 0.25 nm (the cubic interpolant is least accurate on the 9th-power wall, and next to
    /// the law's guard at 0.5 z₀ where u‴ jumps).
    #[test]
    fn table_matches_the_direct_integral() {
        let (pot, table, _) = setup();
        let depth = direct(&pot, R_SUM + 0.34, 30.0).0.abs();
        let force_scale = direct(&pot, R_SUM + 0.25, 30.0).1.abs();
        for &gap in &[0.213, 0.3, 0.34, 0.517, 0.9, 1.37, 2.2, 3.3] {
            for &x in &[0.0123, 0.7, 2.31, 5.0, 9.87, 14.4, 25.0] {
                let d = R_SUM + gap;
                let (g, gd) = direct(&pot, d, x);
                let t = table.eval(d, x, false);
                assert!(
                    (t[0] - g).abs() < 1e-6 * depth.max(g.abs()),
                    "G at gap {gap}, x {x}: {} vs {g}, depth {depth}",
                    t[0]
                );
                assert!(
                    (t[1] - gd).abs() < 1e-4 * force_scale,
                    "G_d at gap {gap}, x {x}"
                );
                let m = table.eval(d, -x, false);
                assert_eq!((m[0], m[1], m[2]), (-t[0], -t[1], t[2]), "odd in x");
            }
        }
    }

    /// Where G is flat in x (past the reach of the cutoff from the cell's closer row) the
    /// one-column look-up gives the Hermite cell's numbers: the cell's columns hold the same G
    /// and G_d and a zero G_x and G_dx, so the two differ only by the round-off of Hermite
    /// weights that sum to 1 (value) or 0 (derivatives) — at most a few ulps of G and G_d
    /// times 1/h_x per x-derivative. Checked in coarse and fine rows and below the floor, from
    /// the first flat column to past the table's end; and flatness starts well before x_end
    /// at contact gaps (the speed-up), but not before the reach.
    #[test]
    fn where_g_is_flat_in_x_the_one_column_look_up_is_the_hermite_cell() {
        let (_, table, _) = setup();
        let x_end = (table.nx - 1) as f64 * table.hx;
        let mut checked = 0;
        for &gap in &[-1.9, -1.3, -0.2, 0.213, 0.34, 0.9, 1.9, 2.4] {
            let d = R_SUM + gap;
            let row = table.row(d);
            let from = table.flat_from[row.i];
            let reach = (table.rc * table.rc - d * d).max(0.0).sqrt();
            assert!(
                from >= reach.min(x_end),
                "gap {gap}: flat from {from} < reach {reach}"
            );
            for k in 0..40 {
                let x = from + k as f64 * 0.37 * table.hx;
                if x >= x_end {
                    break;
                }
                let (flat, cell) = (table.eval_flat(&row, true), table.eval_cell(&row, x, true));
                // the row data's size, and each derivative's division by the spacings
                let h = if row.i < table.nc { table.hc } else { table.hd };
                let [g0, gd0, ..] = table.data[(row.i + 1) * table.nx - 1];
                let size = g0.abs() + h * gd0.abs();
                for (o, (f, c)) in flat.iter().zip(&cell).enumerate() {
                    let (kd, kx) = [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)][o];
                    let tol = 1e-14 * size / (h.powi(kd) * table.hx.powi(kx));
                    assert!(
                        (f - c).abs() <= tol,
                        "gap {gap}, x {x}, derivative {o}: {f} vs {c}"
                    );
                }
                assert!(table.flat(&row, x) && table.flat(&row, -x));
                checked += 1;
            }
            assert!(!table.flat(&row, 0.99 * from));
        }
        assert!(checked > 100, "{checked}");
        // at a contact gap the look-up is flat from ≈ the reach, well before the table's end
        let row = table.row(R_SUM + 0.34);
        assert!(
            table.flat_from[row.i] < 0.8 * x_end,
            "{} vs {x_end}",
            table.flat_from[row.i]
        );
    }

    /// The prefetch hint stays inside the table wherever a caller may ask: from below the floor
    /// to beyond the cutoff, at x of either sign up to past the last column.
    #[test]
    fn the_prefetch_hint_stays_inside_the_table() {
        let (_, table, _) = setup();
        let x_end = (table.nx - 1) as f64 * table.hx;
        for gap in [
            -3.0,
            -2.0,
            -1.99,
            -0.5,
            -0.49,
            0.0,
            0.34,
            2.49,
            2.5,
            3.0,
            f64::NAN,
        ] {
            for x in [0.0, 1e-9, 0.5 * x_end, x_end, 2.0 * x_end, -x_end, f64::NAN] {
                table.prefetch(R_SUM + gap, x);
            }
        }
    }

    /// Two parallel straight axes at the calibrated distance: each point of the shorter one
    /// sees the longer as infinite, so the energy is −γ_L per unit length of the shorter.
    #[test]
    fn parallel_axes_at_the_equilibrium_distance_have_energy_minus_gamma_l_per_length() {
        let (pot, table, rule) = setup();
        let d0 = R_SUM + VdwParams::default().gap_eq;
        let seg = |y: f64, x0: f64, len: f64, panels| QuadSegment {
            ends: [Vector::new(x0, y, 0.0), Vector::new(x0 + len, y, 0.0)],
            panels,
            length0: len,
        };
        let (a, b) = (seg(0.0, 0.0, 100.0, 30), seg(d0, -60.0, 220.0, 60));
        let e = energy_segment_segment_tabulated(&pot, &table, &rule, &a, &b, false);
        let gamma_l = VdwParams::default().gamma_l;
        assert!(
            (e.energy / 100.0 + gamma_l).abs() < 1e-6 * gamma_l,
            "{}",
            e.energy
        );
        // at the minimum: no force across the axes
        assert!(e.grad[1].abs() < 1e-5 * gamma_l, "{}", e.grad[1]);
    }

    /// The tabulated kernel's `tab` against the point quadrature's `quad` of the same pair:
    /// the energy within `energy_tol` of its size, each gradient entry within `force_tol` of
    /// the largest.
    fn assert_agree(
        name: &str,
        tab: &SegmentPairEnergy,
        quad: &SegmentPairEnergy,
        energy_tol: f64,
        force_tol: f64,
    ) {
        let scale = quad.grad.iter().fold(0.0f64, |m, g| m.max(g.abs()));
        assert!(
            (tab.energy - quad.energy).abs() < energy_tol * quad.energy.abs(),
            "{name}: {} vs {}",
            tab.energy,
            quad.energy
        );
        for k in 0..12 {
            assert!(
                (tab.grad[k] - quad.grad[k]).abs() < force_tol * scale,
                "{name} grad {k}: {} vs {}",
                tab.grad[k],
                quad.grad[k]
            );
        }
    }

    /// The tabulated kernel against the point quadrature with a fine inner quadrature on b and
    /// the same outer points on a: the two evaluate the same sum, up to the inner rules' errors.
    #[test]
    fn kernel_matches_the_point_quadrature_with_a_fine_inner_rule() {
        let (pot, table, rule) = setup();
        let mut checked = 0;
        for seed in 0..20 {
            let (a, mut b) = pair(seed);
            let tab = energy_segment_segment_tabulated(&pot, &table, &rule, &a, &b, false);
            b.panels = 400;
            let quad = energy_segment_segment(&pot, &rule, &a, &b, R_SUM, false);
            if quad.point_pairs == 0 {
                assert_eq!(tab.point_pairs, 0, "seed {seed}");
                continue;
            }
            checked += 1;
            assert_agree(&format!("seed {seed}"), &tab, &quad, 1e-6, 1e-5);
        }
        assert!(checked > 10, "the test must cover interacting pairs");
    }

    /// A segment b of 200 nm (51 panels, as the engine gives a 200 nm segment of an
    /// r_o = 20 nm tube) whose tip (its end b₁) is at the origin, its body below a and at
    /// `angle` (radians) to it, and a segment a of 200 nm along x̂ whose axis passes over the tip
    /// at the axis distance r_sum + `gap`, its middle above the tip.
    fn tip_and_side(angle: f64, gap: f64) -> (QuadSegment, QuadSegment) {
        let len = 200.0;
        let ub = Vector::new(-angle.cos(), 0.0, -angle.sin());
        let b = QuadSegment {
            ends: [ub * len, Vector::ZERO],
            panels: 51,
            length0: len,
        };
        let c = Vector::new(0.0, 0.0, R_SUM + gap);
        let a = QuadSegment {
            ends: [c - Vector::X * 100.0, c + Vector::X * 100.0],
            panels: 51,
            length0: len,
        };
        (a, b)
    }

    /// b's tip against a's side, from a T (b perpendicular to a) to 20°, at the equilibrium
    /// gap, in the tail, and pressed 1.18 nm in (where a 400-tube relaxation left a tip when
    /// the table was continued below its floor); and two tubes end to end on
    /// one axis line. The points of a near the tip are closer than the table's floor to b's
    /// axis line, beyond its end. The kernel must give the point quadrature's energy and
    /// forces on 6400 equal panels of 0.03 nm (the reference; the kernel's panels at b's ends
    /// are 0.125 nm, [`FLOOR_PANEL`]): within 1e-5 of the energy (measured ≤ 6.6e-6), and of
    /// the largest force within 1e-4 at the equilibrium gap and in the tail (the table's own
    /// accuracy in G_d, `table_matches_the_direct_integral`; measured ≤ 8.6e-5) and 5e-4
    /// pressed 1.18 nm in (measured ≤ 2.5e-4; a state only a failed step reaches, where what
    /// counts is a large repulsion pointing out). b's own 51 panels were 4 % off at the
    /// equilibrium gap.
    #[test]
    fn a_tip_against_a_side_matches_the_point_quadrature() {
        let (pot, table, rule) = setup();
        let mut cases = Vec::new();
        for angle in [90.0f64, 60.0, 40.0, 20.0] {
            for gap in [0.34, 1.5, -1.18] {
                let force_tol = if gap < 0.0 { 5e-4 } else { 1e-4 };
                cases.push((
                    format!("{angle}°, gap {gap}"),
                    tip_and_side(angle.to_radians(), gap),
                    force_tol,
                ));
            }
        }
        // end to end: a on b's axis line (b along −ẑ below the tip), a gap beyond b's tip
        let (_, b) = tip_and_side(90f64.to_radians(), 0.0);
        for gap in [0.34, 1.0] {
            let a = QuadSegment {
                ends: [
                    Vector::new(0.0, 0.0, R_SUM + gap),
                    Vector::new(0.0, 0.0, R_SUM + gap + 200.0),
                ],
                panels: 51,
                length0: 200.0,
            };
            cases.push((format!("end to end, gap {gap}"), (a, b), 1e-4));
        }
        for (name, (a, b), force_tol) in &cases {
            let below = quadrature_points(&rule, a).any(|q| {
                let p = a.ends[0] + (a.ends[1] - a.ends[0]) * q.t - b.ends[0];
                let e = (b.ends[1] - b.ends[0]).normalize();
                (p - e * p.dot(e)).length() < table.floor() && p.dot(e) > 200.0
            });
            assert!(
                below,
                "{name}: some point of a must be below the floor, beyond the tip"
            );
            let tab = energy_segment_segment_tabulated(&pot, &table, &rule, a, b, false);
            let mut fine = *b;
            fine.panels = 6400;
            let quad = energy_segment_segment(&pot, &rule, a, &fine, R_SUM, false);
            assert_agree(name, &tab, &quad, 1e-5, *force_tol);
        }
        // a short piece of a crossing the floor beyond b's tip, in the tail (gap ≈ 0.85 nm):
        // the table above the floor and the point quadrature below it meet to the table's
        // accuracy (1e-6; 2e-8 measured)
        let (_, b) = tip_and_side(90f64.to_radians(), 0.0);
        let piece = |d: f64| QuadSegment {
            ends: [Vector::new(d, -5e-4, 15.0), Vector::new(d, 5e-4, 15.0)],
            panels: 1,
            length0: 1e-3,
        };
        let f = table.floor();
        let above =
            energy_segment_segment_tabulated(&pot, &table, &rule, &piece(f + 1e-9), &b, false);
        let below =
            energy_segment_segment_tabulated(&pot, &table, &rule, &piece(f - 1e-9), &b, false);
        assert!(above.energy < 0.0 && below.energy < 0.0);
        assert!(
            (above.energy - below.energy).abs() < 1e-6 * above.energy.abs(),
            "{} above the floor, {} below",
            above.energy,
            below.energy
        );
    }

    /// Gradient against central differences of the energy, Hessian against central differences
    /// of the gradient, on crossing pairs, pairs pressed into the coarse rows and through the
    /// table's floor (those points by the point quadrature), and a pair overlapping end to end
    /// (points beyond b's ends).
    #[test]
    fn gradient_and_hessian_match_finite_differences() {
        let (pot, table, rule) = setup();
        let mut cases: Vec<(QuadSegment, QuadSegment)> = (0..6).map(pair).collect();
        // pressed into the coarse rows, and below the floor
        for depth in [1.2, 2.8] {
            let (a, mut b) = pair(7);
            let sink = Vector::new(0.0, -depth, 0.0);
            b.ends = [b.ends[0] + sink, b.ends[1] + sink];
            cases.push((a, b));
        }
        let along = |x0: f64, y: f64| QuadSegment {
            ends: [
                Vector::new(x0, y, 0.1),
                Vector::new(x0 + 20.0, y + 0.3, -0.2),
            ],
            panels: 5,
            length0: 20.0,
        };
        cases.push((along(0.0, 0.0), along(12.0, 40.4)));
        // a long, nearly parallel contact: most points of a are beyond the reach of b's ends
        let long = |x0: f64, y: f64, tilt: f64| QuadSegment {
            ends: [
                Vector::new(x0, y, 0.0),
                Vector::new(x0 + 150.0, y + tilt, 0.3),
            ],
            panels: 40,
            length0: 150.0,
        };
        cases.push((long(10.0, 40.6, -0.4), long(-20.0, 0.0, 0.2)));
        const STEP: f64 = 1e-6;
        for (c, (a, b)) in cases.iter().enumerate() {
            let base = energy_segment_segment_tabulated(&pot, &table, &rule, a, b, true);
            assert!(base.point_pairs > 0, "case {c} must interact");
            let x = flat(a, b);
            let h = base.hessian.as_ref().unwrap();
            let gscale = base.grad.iter().fold(1e-3f64, |m, g| m.max(g.abs()));
            let hscale = h.iter().fold(1e-3f64, |m, v| m.max(v.abs()));
            for k in 0..12 {
                let (mut xp, mut xm) = (x, x);
                xp[k] += STEP;
                xm[k] -= STEP;
                let (ap, bp) = unflat(&xp, a, b);
                let (am, bm) = unflat(&xm, a, b);
                let ep = energy_segment_segment_tabulated(&pot, &table, &rule, &ap, &bp, false);
                let em = energy_segment_segment_tabulated(&pot, &table, &rule, &am, &bm, false);
                let fd = (ep.energy - em.energy) / (2.0 * STEP);
                assert!(
                    (fd - base.grad[k]).abs() < 1e-6 * gscale,
                    "case {c} grad {k}: {fd} vs {}",
                    base.grad[k]
                );
                for j in 0..12 {
                    let fdh = (ep.grad[j] - em.grad[j]) / (2.0 * STEP);
                    assert!(
                        (fdh - h[j * 12 + k]).abs() < 1e-5 * hscale,
                        "case {c} hess {j} {k}: {fdh} vs {}",
                        h[j * 12 + k]
                    );
                }
            }
            let sym = (0..144).all(|i| (h[i] - h[(i % 12) * 12 + i / 12]).abs() < 1e-9 * hscale);
            assert!(sym, "case {c}: Hessian symmetric");
        }
    }
}
