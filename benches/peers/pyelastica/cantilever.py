"""Peer: PyElastica (explicit, damped Cosserat rod) on turf's large-deflection cantilever.

The problem of scenes/rods_cantilever.toml in dimensionless form: a clamped-free rod of length
L = 1 and bending stiffness EI = 1 under a fixed-direction tip load P perpendicular to its axis,
PL^2/EI = 1 (Bisshopp & Drucker 1945). The reference tip position comes from shooting the
elastica ODE theta'' = (P/EI) cos(theta), theta(0) = 0, theta'(L) = 0 with scipy (rtol 1e-12).

PyElastica integrates the dynamics with position Verlet and a linear (analytical) damper and is
stopped when the tip moves less than `--rest` (relative to L) over one check interval. The
script prints one JSON line: elements, steps, simulated time, wall time, the tip position and its
error against the reference, and element updates per second (a cost measure comparable to
turf's segment evaluations).

Usage: python cantilever.py [--elements 50] [--dt 1e-5] [--damping 2.0] [--rest 1e-7]
"""

import argparse
import json
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import elastica as ea


def reference_tip(load):
    """Tip (x, y) of the inextensible elastica, L = EI = 1, tip load `load` along -y."""

    def rhs(_s, z):
        theta, kappa, x, y = z
        return [kappa, load * np.cos(theta), np.cos(theta), np.sin(theta)]

    def end_moment(k0):
        sol = solve_ivp(rhs, (0.0, 1.0), [0.0, k0, 0.0, 0.0], rtol=1e-12, atol=1e-14)
        return sol.y[1, -1], sol

    # the curvature at the clamp is -P * (horizontal lever arm) < 0 for a downward load
    k0 = brentq(lambda k: end_moment(k)[0], -load, 0.0, xtol=1e-15)
    _, sol = end_moment(k0)
    return sol.y[2, -1], sol.y[3, -1]


class Simulator(ea.BaseSystemCollection, ea.Constraints, ea.Forcing, ea.Damping):
    pass


def run(elements, dt, damping, rest, max_time):
    length, radius, density = 1.0, 0.01, 1000.0
    inertia = np.pi * radius**4 / 4.0
    youngs = 1.0 / inertia  # EI = 1
    load = 1.0  # PL^2/EI = 1
    sim = Simulator()
    rod = ea.CosseratRod.straight_rod(
        elements,
        np.zeros(3),
        np.array([1.0, 0.0, 0.0]),
        np.array([0.0, 0.0, 1.0]),
        length,
        radius,
        density,
        youngs_modulus=youngs,
        shear_modulus=youngs / 1.5,  # Poisson 0.5, PyElastica's default
    )
    sim.append(rod)
    sim.constrain(rod).using(
        ea.OneEndFixedBC, constrained_position_idx=(0,), constrained_director_idx=(0,)
    )
    sim.add_forcing_to(rod).using(
        ea.EndpointForces, np.zeros(3), np.array([0.0, -load, 0.0]), ramp_up_time=0.1
    )
    sim.dampen(rod).using(ea.AnalyticalLinearDamper, uniform_damping_constant=damping, time_step=dt)
    sim.finalize()
    stepper = ea.PositionVerlet()
    check = max(1, int(round(0.01 / dt)))  # check the tip every 0.01 time units
    t, steps = 0.0, 0
    last = rod.position_collection[:, -1].copy()
    start = time.perf_counter()
    while t < max_time:
        for _ in range(check):
            t = stepper.step(sim, t, dt)
        steps += check
        tip = rod.position_collection[:, -1].copy()
        if t > 0.2 and np.linalg.norm(tip - last) < rest * length:
            break
        last = tip
    wall = time.perf_counter() - start
    ref_x, ref_y = reference_tip(load)
    tip = rod.position_collection[:, -1]
    return {
        "peer": "pyelastica",
        "version": getattr(ea, "__version__", "1.0.0"),
        "elements": elements,
        "dt": dt,
        "steps": steps,
        "simulated_time": t,
        "wall_time_s": wall,
        "tip_dx_over_L": float(tip[0] - length),
        "tip_dy_over_L": float(tip[1]),
        "reference_dx_over_L": float(ref_x - length),
        "reference_dy_over_L": float(ref_y),
        "error_dy_relative": float(abs(tip[1] - ref_y) / abs(ref_y)),
        "error_dx_relative": float(abs(tip[0] - ref_x) / abs(ref_x - length)),
        "element_updates_per_s": elements * steps / wall,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--elements", type=int, default=50)
    ap.add_argument("--dt", type=float, default=1e-5)
    ap.add_argument("--damping", type=float, default=2.0)
    ap.add_argument("--rest", type=float, default=1e-7)
    ap.add_argument("--max-time", type=float, default=30.0)
    a = ap.parse_args()
    print(json.dumps(run(a.elements, a.dt, a.damping, a.rest, a.max_time)))


if __name__ == "__main__":
    main()
