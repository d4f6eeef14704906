"""Peer: the `Adhesion` + `ContactMechanics` packages (FFT boundary-element half-space, 3D grid)
on turf's half-space pull-off problem.

A rigid paraboloid of radius R on a linear elastic half-space of contact modulus E*, adhering
through the Lennard-Jones law that Adhesion calls LJ93 (energy per area
V(h) = eps[(2/15)(sigma/h)^9 - (sigma/h)^3]; its pressure is turf's `lj104` law,
p = (9 gamma / 2 z0)[(z0/h)^10 - (z0/h)^4]). With z0 = 1 and gamma = 1: sigma = (5/2)^(1/6),
eps = 1/1.054093. Tabor's mu = (R gamma^2 / (E*^2 z0^3))^(1/3); R = 1000 z0 and E* = sqrt(R/mu^3).

Displacement control: the rigid body approaches from a clearance, indents, and retracts; at each
offset the total energy is minimised over the surface displacements (scipy L-BFGS-B from the
previous state, as Adhesion's examples do), with Adhesion's linearised core below z0/2 so
that a line search overshooting into the wall cannot diverge. The pull-off is the most tensile force on the
retraction, reported normalised by pi*gamma*R (turf's convention). The free (non-periodic) FFT
half-space `FreeFFTElasticHalfSpace` is used, the grid square of side `--size` contact radii.

Prints one JSON line: grid, offsets, L-BFGS iterations, wall time, pull-off.

Usage: python pulloff.py [--mu 1] [--nx 128] [--size 4] [--step 0.05]
"""

import argparse
import json
import time

import numpy as np
import scipy.optimize as optim
from Adhesion.Interactions import LJ93
from Adhesion.System import SmoothContactSystem
from ContactMechanics import FreeFFTElasticHalfSpace
from SurfaceTopography import make_sphere

Z0, GAMMA = 1.0, 1.0
SIGMA = (5.0 / 2.0) ** (1.0 / 6.0)
EPS = GAMMA / ((2.0 / 15.0) * SIGMA**9 - SIGMA**3) * -1.0  # V(z0) = -gamma


def build(mu, nx, size, radius=1000.0):
    e_star = np.sqrt(radius * GAMMA**2 / (mu**3 * Z0**3))
    a0 = (9.0 * np.pi * GAMMA * radius**2 / (2.0 * e_star)) ** (1.0 / 3.0)  # JKR, zero load
    side = size * a0
    substrate = FreeFFTElasticHalfSpace((nx, nx), young=e_star, physical_sizes=(side, side))
    surface = make_sphere(radius, (nx, nx), (side, side), kind="paraboloid")
    # the singular core is replaced below gap z0/2 by a linear one (Adhesion's recommended
    # robust form): equilibrium gaps stay near z0, where the law is untouched
    system = SmoothContactSystem(substrate, LJ93(EPS, SIGMA).linearize_core(r_ti=0.5 * Z0), surface)
    return system, substrate, radius, e_star, side


def relax(system, substrate, offset, disp0):
    res = optim.minimize(
        system.objective(offset, gradient=True),
        disp0.reshape(-1),
        method="L-BFGS-B",
        jac=True,
        options=dict(gtol=1e-8 * abs(system.area_per_pt), ftol=0, maxcor=20, maxiter=20000),
    )
    disp = res.x.reshape(substrate.nb_subdomain_grid_pts)
    system.evaluate(disp, offset, forces=True)
    return disp, system.compute_normal_force(), res.nit, res.success


def run(mu, nx, size, step, start, depth):
    system, substrate, radius, e_star, side = build(mu, nx, size)
    disp = np.zeros(substrate.nb_subdomain_grid_pts)
    # offset > 0 indents; the approach starts at a clearance `start` (in z0)
    offsets = list(np.arange(-start, depth + 1e-12, step)) + list(np.arange(depth, -start - 1e-12, -step))
    forces, iterations, failures = [], 0, 0
    t0 = time.perf_counter()
    for k, off in enumerate(offsets):
        disp, force, nit, ok = relax(system, substrate, off, disp)
        iterations += nit
        failures += 0 if ok else 1
        forces.append(force)
    wall = time.perf_counter() - t0
    forces = np.array(forces)
    turn = len(offsets) // 2
    # Adhesion's normal force is the sum of -dV/dgap over the contact area: repulsion > 0,
    # attraction < 0, turf's convention; the pull-off is the most tensile retraction force
    pull_off = forces[turn:].min()
    return {
        "peer": "Adhesion/ContactMechanics",
        "mu": mu,
        "law": "lj104",
        "R_over_z0": radius,
        "grid": [nx, nx],
        "side_over_z0": side,
        "spacing_over_z0": side / nx,
        "offsets": len(offsets),
        "lbfgs_iterations": int(iterations),
        "lbfgs_failures": int(failures),
        "wall_time_s": wall,
        "pull_off_normalised": float(pull_off / (np.pi * GAMMA * radius)),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mu", type=float, default=1.0)
    ap.add_argument("--nx", type=int, default=128)
    ap.add_argument("--size", type=float, default=4.0, help="grid side in JKR zero-load contact radii")
    ap.add_argument("--step", type=float, default=0.05, help="offset step, z0")
    ap.add_argument("--start", type=float, default=3.0, help="initial clearance, z0")
    ap.add_argument("--depth", type=float, default=None, help="deepest offset, z0 (default: a0^2/R)")
    a = ap.parse_args()
    depth = a.depth
    if depth is None:
        _, _, radius, e_star, _ = build(a.mu, 8, a.size)
        a0 = (9.0 * np.pi * GAMMA * radius**2 / (2.0 * e_star)) ** (1.0 / 3.0)
        depth = max(1.0, a0**2 / radius)
    print(json.dumps(run(a.mu, a.nx, a.size, a.step, a.start, depth)))


if __name__ == "__main__":
    main()
