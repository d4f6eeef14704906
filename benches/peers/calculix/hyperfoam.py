"""Peer: CalculiX (ccx) on turf's hyperfoam sphere indentation (benches/peers/hyperfoam_sphere.toml).

A sphere of radius R = 1 um pressed δ = 100 nm (δ/R = 0.1) into a block of the seed's Table 5.1
hyperfoam (μ = 350 MPa, α = 18.8, β = 0, i.e. ν = 0), finite deformation (NLGEOM), frictionless,
no adhesion, no relaxation. Mesh, stiff meshed sphere (E = 1e4 GPa) and surface-to-surface
penalty contact as in hertz.py (which writes the deck); only the block material, the depth and
the step differ. CalculiX 2.20 fails on *HYPERFOAM, N=1 (singular matrix), so the one-term card is
written as N=2 with a zero second term, the same energy (as turf's material.inp does).

CalculiX 2.20's *HYPERFOAM stress is wrong at near-isotropic small strain: uniaxial strain of
5e-6 gives 0.40 of the closed form T = (2μ/α)(λ^(α−1) − 1/λ), 1e-5 gives +0.4 %, 1e-4 −1.4e-4,
1e-3 exact (`--check` prints this). The far field of an indentation sits at such strains, and the
jumps there keep Newton from converging. So the block is hyperfoam only
within `--far` contact radii of the first contact point and beyond that the foam's small-strain
limit, linear elastic E = 2μ, ν = 0 (St Venant–Kirchhoff under NLGEOM); moving that boundary
from 4a to 8a lowers the load at 100 nm by 0.10 %, and a C/r² fit puts 8a (the default) 0.03 %
above the all-foam limit (docs/peers.md). Foam out to 20a does not converge.

Prints one JSON line: elements, wall time of ccx, and the load (nN, 180·RF: CalculiX reports
axisymmetric reactions for a 2° segment) at every converged increment, with the depth. With
`--check`: one JSON line per strain of the one-element uniaxial-strain test.

Usage: python hyperfoam.py [--per-radius 10] [--ratio 1.2] [--block 200] [--far 8]
                           [--first 0.2] [--increment 0.05] [--workdir DIR] [--check]
"""

import json
import re
from pathlib import Path

from hertz import R, mesh_parser, run_ccx, run_record, total_reactions, write_input

DEPTH, MU, ALPHA = 100.0, 0.35, 18.8  # nm, GPa (CalculiX's μ_i is turf's), –


def foam_block():
    """The hyperfoam block: N = 2, μ₂ = 0; data line μ₁, α₁, μ₂, α₂, ν₁, ν₂ (ν = 0: β = 0)."""
    return f"*MATERIAL, NAME=BLOCK\n*HYPERFOAM, N=2\n{MU}, {ALPHA}, 0.0, {ALPHA}, 0.0, 0.0\n"


def far_block():
    """The foam's small-strain limit: initial shear modulus μ and ν = 0, so E = 2μ."""
    return f"*MATERIAL, NAME=FAR\n*ELASTIC\n{2.0 * MU}, 0.0\n"


def uniaxial_check(work, strains=(1e-3, 1e-4, 1e-5, 5e-6, 1e-6)):
    """One C3D8 unit cube in uniaxial strain (sides held): the top's nominal stress against
    T = (2μ/α)(λ^(α−1) − 1/λ), the exact uniaxial answer of the ν = 0 foam."""
    nodes = "\n".join(f"{k + 1}, {k & 1 ^ (k >> 1) & 1}, {(k >> 1) & 1}, {k >> 2}" for k in range(8))
    for e in strains:
        deck = (
            f"*NODE, NSET=NALL\n{nodes}\n*ELEMENT, TYPE=C3D8, ELSET=EALL\n1, 1, 2, 3, 4, 5, 6, 7, 8\n"
            "*NSET, NSET=TOP\n5, 6, 7, 8\n*NSET, NSET=BOT\n1, 2, 3, 4\n"
            f"{foam_block()}*SOLID SECTION, ELSET=EALL, MATERIAL=BLOCK\n"
            "*BOUNDARY\nNALL, 1, 2, 0.0\nBOT, 3, 3, 0.0\n*STEP, NLGEOM\n*STATIC, DIRECT\n1.0, 1.0\n"
            f"*BOUNDARY\nTOP, 3, 3, {-e}\n*NODE PRINT, NSET=TOP, TOTALS=ONLY\nRF\n*END STEP\n"
        )
        (work / "uniaxial.inp").write_text(deck)
        run_ccx(work, "uniaxial")
        text = (work / "uniaxial.dat").read_text()
        rz = float(re.findall(r"total force.*?\n\s*\n?\s*\S+\s+\S+\s+(\S+)", text, re.S)[-1])
        lam = 1.0 - e
        exact = 2.0 * MU / ALPHA * (lam ** (ALPHA - 1.0) - 1.0 / lam)
        print(json.dumps({"peer": "calculix", "check": "hyperfoam_uniaxial_strain", "strain": -e,
                          "nominal_stress_GPa": rz, "closed_form_GPa": exact, "ratio": rz / exact}))


def main():
    ap = mesh_parser(__doc__, 10.0, 1.2, "/tmp/turf_peer_ccx_foam")
    ap.add_argument("--increment", type=float, default=0.05, help="largest increment after the first, fraction of the depth")
    ap.add_argument("--first", type=float, default=0.2, help="depth of the first increment, fraction of the depth")
    ap.add_argument("--far", type=float, default=8.0, help="hyperfoam within this many contact radii, E = 2μ beyond")
    ap.add_argument("--check", action="store_true", help="only the one-element uniaxial check of *HYPERFOAM")
    a = ap.parse_args()
    work = Path(a.workdir)
    work.mkdir(parents=True, exist_ok=True)
    if a.check:
        uniaxial_check(work)
        return
    # automatic incrementation (cut back on failure) of at most `increment` of the depth, after a
    # first increment straight to `first` of the depth: at smaller depths the foam's outer
    # elements are still strained below 1e-4 and the defect of --check stalls Newton (a/20 mesh)
    inc, first = a.increment, a.first
    period = 1.0 - first + inc
    step = f"*STEP, NLGEOM, INC=1000\n*STATIC\n{inc}, {period}, 1e-5, {inc}\n"
    elements, nodes, n_spec = write_input(
        work / "foam.inp", a.per_radius, a.ratio, a.block, a.penalty,
        depth=DEPTH, material=foam_block(), step=step, far=(a.far, far_block()),
        ramp=[(0.0, 0.0), (inc, first), (period, 1.0)],
    )
    wall = run_ccx(work, "foam")
    # depth = DEPTH × the ramp at each printed step time
    curve = [
        (DEPTH * (t * first / inc if t <= inc else first + (t - inc) * (1.0 - first) / (period - inc)), -180.0 * ry)
        for t, ry in total_reactions(work / "foam.dat")
    ]
    print(json.dumps({
        **run_record(a, elements, n_spec, nodes, wall),
        "problem": "hyperfoam_sphere",
        "radius_nm": R,
        "far_over_a": a.far,
        "depth_nm": [d for d, _ in curve],
        "load_nN": [p for _, p in curve],
    }))


if __name__ == "__main__":
    main()
