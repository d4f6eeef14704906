"""Peer: CalculiX (ccx) on turf's Hertz problem (scenes/hertz.toml).

A sphere of radius R = 1 um pressed δ = 4 nm into an elastic block (E = 1 GPa, ν = 0.3),
axisymmetric, small strain, frictionless. CalculiX has no analytical rigid surface, so the
indenter is meshed as a stiff body (E = 1e4 GPa: E* differs from the rigid-indenter value by
1e-4 relative) whose flat top is displaced by δ. Contact: surface-to-surface penalty
(`*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR`, slope K ≫ p₀/(0.01 δ)). The block is
`--block` contact radii wide and deep (turf's default: 200a) with a rigid, fixed bottom and a free
side; the mesh is uniform (a/`--per-radius`) to r, depth 2a, then grows geometrically by `--ratio`,
like turf's graded mesh. Elements: CAX4 (bilinear axisymmetric quads; ccx expands them into
wedges), units nm, nN, GPa.

CalculiX reports the reaction of axisymmetric models for a 2° segment (its expansion), so the
total load is 180·RF — checked against Hertz to the 1 % level, which a wrong factor (2π) could
not meet.

Prints one JSON line: elements, nodes, wall time of ccx, load and its error against Hertz
(P = (4/3)E*√R δ^{3/2}).

Usage: python hertz.py [--per-radius 20] [--ratio 1.15] [--block 200] [--workdir DIR]
"""

import argparse
import json
import math
import os
import re
import shutil
import subprocess
import time
from pathlib import Path

R, DEPTH, YOUNGS, POISSON = 1000.0, 4.0, 1.0, 0.3
E_STAR = YOUNGS / (1.0 - POISSON**2)
P_HERTZ = 4.0 / 3.0 * E_STAR * math.sqrt(R) * DEPTH**1.5


def graded(fine_end, h0, ratio, end):
    """Nodes 0..end: uniform h0 to fine_end, then growing by `ratio`."""
    xs = [0.0]
    h = h0
    while xs[-1] < end - 1e-9:
        if xs[-1] >= fine_end - 1e-9:
            h *= ratio
        xs.append(min(end, xs[-1] + h))
        if end - xs[-1] < 0.5 * h:
            xs[-1] = end
    return xs


def linear_block():
    """The Hertz block's material lines."""
    return f"*MATERIAL, NAME=BLOCK\n*ELASTIC\n{YOUNGS}, {POISSON}\n"


def write_input(path, per_radius, ratio, block, penalty, depth=DEPTH, material=None, step="*STEP, INC=200\n*STATIC\n0.1, 1.0, 1e-5, 0.2\n", far=None, ramp=None):
    """The deck: the block (`material`: *MATERIAL, NAME=BLOCK lines; default linear_block()) and
    the stiff sphere pressed `depth` nm; mesh sizes from the contact radius a = √(R·depth).
    `far` = (radius over a, *MATERIAL, NAME=FAR lines): block elements whose centre lies farther
    than that from the first contact point get the FAR material instead (hyperfoam.py).
    `ramp`: (step time, fraction of the depth) points of the imposed displacement (default:
    proportional to the step time)."""
    A = math.sqrt(R * depth)
    h0 = A / per_radius
    rs = graded(2.0 * A, h0, ratio, block * A)
    ds = graded(2.0 * A, h0, ratio, block * A)
    ys = [-d for d in reversed(ds)]  # bottom to top, top at 0
    nodes, elems = [], []
    nid = {}

    def node(key, x, y):
        nid[key] = len(nodes) + 1
        nodes.append((x, y))
        return nid[key]

    for j, y in enumerate(ys):
        for i, x in enumerate(rs):
            node(("s", i, j), x, y)
    nr, ny = len(rs), len(ys)
    top_faces = []
    for j in range(ny - 1):
        for i in range(nr - 1):
            elems.append(("S", [nid[("s", i, j)], nid[("s", i + 1, j)], nid[("s", i + 1, j + 1)], nid[("s", i, j + 1)]]))
            if j == ny - 2 and rs[i] < 3.0 * A:
                top_faces.append((len(elems), 3))
    n_specimen = len(elems)
    far_ids = set()
    if far is not None:
        for k, (_, c) in enumerate(elems, 1):
            x = sum(nodes[n - 1][0] for n in c) / 4.0
            y = sum(nodes[n - 1][1] for n in c) / 4.0
            if math.hypot(x, y) > far[0] * A:
                far_ids.add(k)
    # indenter: radial stations as the specimen's up to 3a, vertical layers from the sphere up
    ri = [x for x in rs if x <= 3.0 * A + 1e-9]
    surf = [R - math.sqrt(R * R - x * x) for x in ri]
    top = surf[-1] + 2.0 * A
    layers = 12
    for i, x in enumerate(ri):
        for k in range(layers + 1):
            s = (k / layers) ** 1.5
            node(("i", i, k), x, surf[i] + s * (top - surf[i]))
    bottom_faces = []
    for i in range(len(ri) - 1):
        for k in range(layers):
            elems.append(("I", [nid[("i", i, k)], nid[("i", i + 1, k)], nid[("i", i + 1, k + 1)], nid[("i", i, k + 1)]]))
            if k == 0:
                bottom_faces.append((len(elems), 1))
    with open(path, "w") as f:
        f.write("*HEADING\nturf peer: Hertz, stiff sphere on elastic block (nm, nN, GPa)\n*NODE\n")
        for k, (x, y) in enumerate(nodes, 1):
            f.write(f"{k}, {x:.10g}, {y:.10g}\n")
        for elset, outer in (("SPECIMEN", False), ("FAR", True)):
            ids = [k for k in range(1, n_specimen + 1) if (k in far_ids) == outer]
            if ids:
                f.write(f"*ELEMENT, TYPE=CAX4, ELSET={elset}\n")
            for k in ids:
                c = elems[k - 1][1]
                f.write(f"{k}, {c[0]}, {c[1]}, {c[2]}, {c[3]}\n")
        f.write("*ELEMENT, TYPE=CAX4, ELSET=INDENTER\n")
        for k, (_, c) in enumerate(elems[n_specimen:], n_specimen + 1):
            f.write(f"{k}, {c[0]}, {c[1]}, {c[2]}, {c[3]}\n")

        def nset(name, ids):
            f.write(f"*NSET, NSET={name}\n")
            for c in range(0, len(ids), 12):
                f.write(", ".join(str(x) for x in ids[c:c + 12]) + "\n")

        nset("AXIS", [nid[("s", 0, j)] for j in range(ny)] + [nid[("i", 0, k)] for k in range(layers + 1)])
        nset("BOTTOM", [nid[("s", i, 0)] for i in range(nr)])
        nset("ITOP", [nid[("i", i, layers)] for i in range(len(ri))])
        f.write("*SURFACE, NAME=SLAVE, TYPE=ELEMENT\n")
        for e, face in top_faces:
            f.write(f"{e}, S{face}\n")
        f.write("*SURFACE, NAME=MASTER, TYPE=ELEMENT\n")
        for e, face in bottom_faces:
            f.write(f"{e}, S{face}\n")
        f.write(material or linear_block())
        if far_ids:
            f.write(far[1] + "*SOLID SECTION, ELSET=FAR, MATERIAL=FAR\n")
        f.write(f"*MATERIAL, NAME=STIFF\n*ELASTIC\n{YOUNGS * 1e4}, {POISSON}\n")
        f.write("*SOLID SECTION, ELSET=SPECIMEN, MATERIAL=BLOCK\n*SOLID SECTION, ELSET=INDENTER, MATERIAL=STIFF\n")
        f.write("*SURFACE INTERACTION, NAME=SI\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n")
        f.write(f"{penalty}, 1e-9, {A}\n")
        f.write("*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE\nSLAVE, MASTER\n")
        f.write("*BOUNDARY\nAXIS, 1, 1\nBOTTOM, 1, 2\n")
        if ramp is not None:
            f.write("*AMPLITUDE, NAME=RAMP\n" + ", ".join(f"{t:g}, {v:g}" for t, v in ramp) + "\n")
        f.write(step)
        f.write(f"*BOUNDARY{', AMPLITUDE=RAMP' if ramp else ''}\nITOP, 2, 2, {-depth}\n")
        f.write("*NODE PRINT, NSET=ITOP, TOTALS=ONLY\nRF\n*END STEP\n")
    return len(elems), len(nodes), n_specimen


def total_reactions(dat):
    """(step time, y component) of every 'total force' block of the .dat file."""
    text = Path(dat).read_text()
    blocks = re.findall(r"total force.*?time\s+([-+0-9.Ee]+)\s*\n\s*\n?\s*([-+0-9.Ee]+)\s+([-+0-9.Ee]+)\s+([-+0-9.Ee]+)", text, re.S)
    if not blocks:
        raise RuntimeError(f"no total force in {dat}")
    return [(float(b[0]), float(b[2])) for b in blocks]


def run_ccx(work, name):
    """Run ccx on WORK/NAME.inp; returns the wall time (s)."""
    ccx = shutil.which("ccx")
    if ccx is None:
        raise SystemExit("ccx not found: apt-get install calculix-ccx")
    env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "2"))
    t0 = time.perf_counter()
    run = subprocess.run([ccx, "-i", name], cwd=work, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if run.returncode != 0 or "ERROR" in run.stdout:
        tail = "\n".join(run.stdout.splitlines()[-20:])
        raise SystemExit(f"ccx failed:\n{tail}")
    return wall


def mesh_parser(doc, per_radius, ratio, workdir):
    """The command line shared by the CalculiX peers: mesh, block, penalty and work directory."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--per-radius", type=float, default=per_radius)
    ap.add_argument("--ratio", type=float, default=ratio)
    ap.add_argument("--block", type=float, default=200.0)
    ap.add_argument("--penalty", type=float, default=100.0, help="GPa/nm")
    ap.add_argument("--workdir", default=workdir)
    return ap


def run_record(a, elements, n_spec, nodes, wall):
    """The fields every CalculiX peer reports: mesh, block and cost."""
    return {
        "peer": "calculix",
        "elements": elements,
        "specimen_elements": n_spec,
        "nodes": nodes,
        "per_radius": a.per_radius,
        "ratio": a.ratio,
        "block_over_a": a.block,
        "wall_time_s": wall,
    }


def main():
    a = mesh_parser(__doc__, 20.0, 1.15, "/tmp/turf_peer_ccx").parse_args()
    work = Path(a.workdir)
    work.mkdir(parents=True, exist_ok=True)
    elements, nodes, n_spec = write_input(work / "hertz.inp", a.per_radius, a.ratio, a.block, a.penalty)
    wall = run_ccx(work, "hertz")
    # reaction on the indenter's top (opposes the imposed downward motion): load = -RF_y
    load = -180.0 * total_reactions(work / "hertz.dat")[-1][1]
    print(json.dumps({
        **run_record(a, elements, n_spec, nodes, wall),
        "load_nN": load,
        "hertz_nN": P_HERTZ,
        "error_relative": (load - P_HERTZ) / P_HERTZ,
    }))


if __name__ == "__main__":
    main()
