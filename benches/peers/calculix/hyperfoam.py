"""Peer: CalculiX (ccx) on turf's hyperfoam sphere indentation (benches/peers/hyperfoam_sphere.toml).

A sphere of radius R = 1 um pressed δ = 100 nm (δ/R = 0.1) into a block of the seed's Table 5.1
hyperfoam (μ = 350 MPa, α = 18.8, β = 0, i.e. ν = 0), finite deformation (NLGEOM), frictionless,
no adhesion, no relaxation. Mesh, stiff meshed sphere (E = 1e4 GPa) and surface-to-surface
penalty contact as in hertz.py (which writes the deck); only the block material, the depth and
the step differ. CalculiX 2.20 fails on *HYPERFOAM, N=1 (singular matrix), so the one-term card is
written as N=2 with a zero second term, the same energy (as turf's material.inp does).

Prints one JSON line: elements, wall time of ccx, and the load (nN, 180·RF: CalculiX reports
axisymmetric reactions for a 2° segment) at every converged increment, with the depth.

Usage: python hyperfoam.py [--per-radius 10] [--ratio 1.2] [--block 200] [--workdir DIR]
"""

import json
from pathlib import Path

from hertz import R, mesh_parser, run_ccx, run_record, total_reactions, write_input

DEPTH, MU, ALPHA = 100.0, 0.35, 18.8  # nm, GPa (CalculiX's μ_i is turf's), –


def foam_block():
    """The hyperfoam block: N = 2, μ₂ = 0; data line μ₁, α₁, μ₂, α₂, ν₁, ν₂ (ν = 0: β = 0)."""
    return f"*MATERIAL, NAME=BLOCK\n*HYPERFOAM, N=2\n{MU}, {ALPHA}, 0.0, {ALPHA}, 0.0, 0.0\n"


def main():
    ap = mesh_parser(__doc__, 10.0, 1.2, "/tmp/turf_peer_ccx_foam")
    ap.add_argument("--increment", type=float, default=0.02, help="first and largest increment, fraction of the depth")
    a = ap.parse_args()
    work = Path(a.workdir)
    work.mkdir(parents=True, exist_ok=True)
    # automatic incrementation (cut back on failure), at most `increment` of the depth per step
    step = f"*STEP, NLGEOM, INC=1000\n*STATIC\n{a.increment}, 1.0, 1e-6, {a.increment}\n"
    elements, nodes, n_spec = write_input(
        work / "foam.inp", a.per_radius, a.ratio, a.block, a.penalty,
        depth=DEPTH, material=foam_block(), step=step,
    )
    wall = run_ccx(work, "foam")
    curve = [(t * DEPTH, -180.0 * ry) for t, ry in total_reactions(work / "foam.dat")]
    print(json.dumps({
        **run_record(a, elements, n_spec, nodes, wall),
        "problem": "hyperfoam_sphere",
        "radius_nm": R,
        "depth_nm": [d for d, _ in curve],
        "load_nN": [p for _, p in curve],
    }))


if __name__ == "__main__":
    main()
