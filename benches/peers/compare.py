"""Print the turf-vs-peer table (markdown) from the JSON results written by run.sh."""

import json
import math
import sys
from pathlib import Path


def lines(path):
    return [json.loads(l) for l in Path(path).read_text().splitlines() if l.strip()]


def load_at(depths, loads, d):
    """The load at depth d between the recorded increments, as the local power law through the
    two neighbours (P ∝ δ^n with n from 1.5 to ~1.3 here; linear interpolation would be 0.2 %
    off across a 3.75 nm step of this convex curve), linear from the origin."""
    pts = sorted(zip(depths, loads))
    for (d0, p0), (d1, p1) in zip(pts, pts[1:]):
        if d0 <= d <= d1:
            if d == d1 or d1 <= d0:
                return p1
            if d0 <= 0.0 or p0 <= 0.0:
                return p0 + (p1 - p0) * (d - d0) / (d1 - d0)
            return p0 * (d / d0) ** (math.log(p1 / p0) / math.log(d1 / d0))
    raise ValueError(f"depth {d} nm outside the recorded curve ({pts[0][0]}..{pts[-1][0]} nm)")


def turf_curve(out, name):
    """(depths, loads, wall time, elements) of a turf run's continuum stage."""
    run = json.loads((out / f"{name}.json").read_text())
    cont = next(s for s in run["stages"] if s["stage"] == "continuum")
    rows = (out / name / "continuum" / "load_depth.csv").read_text().splitlines()
    head = rows[0].split(",")
    cols = [[float(v) for v in r.split(",")] for r in rows[1:] if r.strip()]
    i_d, i_p = head.index("depth_nm"), head.index("load_nN")
    return [c[i_d] for c in cols], [c[i_p] for c in cols], cont["wall_time_s"], cont["values"]["elements"]


FOAM_DEPTHS = (25.0, 50.0, 100.0)


def cantilever_rows(out):
    """The single rod: turf's static Newton vs PyElastica brought to rest."""
    rows = []
    turf = json.loads((out / "turf_cantilever.json").read_text())
    values = turf["stages"][0]["values"]
    dy = -values["rod0_tip_dy_nm"] / values["rod0_length_nm"]
    t_turf = values["wall_time_solve_s"]
    peers = lines(out / "pyelastica_cantilever.jsonl")
    ref = -peers[0]["reference_dy_over_L"]
    rows.append(("cantilever PL²/EI = 1, 50 elements", "turf (Newton)", f"{abs(dy - ref) / ref:.1e}", f"{t_turf:.4f}", "1"))
    for p in peers:
        rows.append((
            "", f"PyElastica (dt {p['dt']:g}, {p['steps']} steps)",
            f"{p['error_dy_relative']:.1e}", f"{p['wall_time_s']:.1f}",
            f"{p['wall_time_s'] / t_turf:.0f}",
        ))
    return rows


def halfspace_rows(out):
    """Half-space pull-off: turf's axisymmetric solver vs Adhesion/ContactMechanics."""
    rows = []
    hs = json.loads((out / "turf_halfspace_mu1.json").read_text())
    ref = hs["pull_off_normalized"]
    t_hs = hs["cost"]["wall_time_s"]
    rows.append(("half-space pull-off, LJ 10-4, μ = 1", "turf (axisymmetric, 3 grids)", f"±{hs['error_estimate']:.1e} (est.)", f"{t_hs:.3f}", "1"))
    for p in lines(out / "contactmechanics_pulloff.jsonl"):
        rows.append((
            "", f"Adhesion/ContactMechanics {p['grid'][0]}² (h = {p['spacing_over_z0']:.1f} z₀)",
            f"{(p['pull_off_normalised'] - ref) / abs(ref):+.1e} vs turf", f"{p['wall_time_s']:.1f}",
            f"{p['wall_time_s'] / t_hs:.0f}",
        ))
    return rows


def hertz_rows(out):
    """Hertz by FE: turf CST vs CalculiX CAX4."""
    rows = []
    hz = json.loads((out / "turf_hertz.json").read_text())
    cont = next(s for s in hz["stages"] if s["stage"] == "continuum")
    p_hertz = 4.0 / 3.0 * (1.0 / (1.0 - 0.3**2)) * 1000.0**0.5 * 4.0**1.5
    t_fe = cont["wall_time_s"]
    rows.append((
        "Hertz, R = 1 µm, δ = 4 nm, E = 1 GPa, ν = 0.3", f"turf FE ({cont['values']['elements']:.0f} CST, load + unload)",
        f"{cont['values']['max_load_nN'] / p_hertz - 1:+.2%}", f"{t_fe:.1f}", "1",
    ))
    for p in lines(out / "calculix_hertz.jsonl"):
        rows.append((
            "", f"CalculiX ({p['elements']} CAX4, a/{p['per_radius']:g}, loading only)",
            f"{p['error_relative']:+.2%}", f"{p['wall_time_s']:.1f}", f"{p['wall_time_s'] / t_fe:.0f}",
        ))
    return rows


def hyperfoam_rows(out):
    """Hyperfoam sphere: loads at FOAM_DEPTHS, differences against turf's finest mesh (a/40)."""
    rows = []
    fine = turf_curve(out, "turf_hyperfoam_sphere_a40")
    ref = [load_at(fine[0], fine[1], d) for d in FOAM_DEPTHS]
    t_foam = turf_curve(out, "turf_hyperfoam_sphere")[2]
    runs = [(f"turf FE ({c[3]:.0f} CST{', a/40' if n.endswith('a40') else ''})", c[0], c[1], c[2])
            for n in ("turf_hyperfoam_sphere", "turf_hyperfoam_sphere_a40") for c in [turf_curve(out, n)]]
    runs += [(f"CalculiX ({p['elements']} CAX4, a/{p['per_radius']:g})", p["depth_nm"], p["load_nN"], p["wall_time_s"])
             for p in lines(out / "calculix_hyperfoam_sphere.jsonl")]
    first = "hyperfoam sphere, R = 1 µm, load at " + " / ".join(f"{d:g}" for d in FOAM_DEPTHS) + " nm"
    for k, (code, ds, ps, wall) in enumerate(runs):
        loads = [load_at(ds, ps, d) for d in FOAM_DEPTHS]
        worst = max(abs(p / r - 1.0) for p, r in zip(loads, ref))
        rows.append((
            first if k == 0 else "", code, " / ".join(f"{p:.0f}" for p in loads) + f" nN (max {worst:.2%} vs turf a/40)",
            f"{wall:.1f}", f"{wall / t_foam:.0f}",
        ))
    return rows


def mesont_rows(out):
    """turf_100x100 scaled to MESONT's (10,10) tube: turf (Newton) vs LAMMPS MESONT (minimize).
    The error column carries the stress at the last strain both reached and the iterations."""
    rows = []
    run = json.loads((out / "turf_mesont_scaled.json").read_text())
    st = run["stages"][0]
    v = st["values"]
    nodes = v["segments"] + v["tubes"]
    its_turf = v["relaxation_iterations"] + v["compression_iterations"]
    wall_turf = v["wall_time_relaxation_s"] + v["wall_time_compression_s"]
    csv = (out / "mesont" / "turf_scaled" / "stress_strain.csv").read_text().splitlines()
    head = csv[0].split(",")
    last = csv[-1].split(",")
    eps_turf, sig_turf = float(last[head.index("strain")]), float(last[head.index("stress_GPa")])
    first = f"turf_100x100 scaled to (10,10), {nodes:.0f} nodes, straight"
    rows.append((
        first, f"turf Newton: relax + compression to {eps_turf:.2f} ({its_turf:.0f} iterations, "
        f"{1e6 * wall_turf / max(its_turf, 1) / nodes:.1f} µs per node-iteration)",
        f"σ = {sig_turf * 1e3:.4g} MPa at ε = {eps_turf:.2f}", f"{wall_turf:.1f}", "1",
    ))
    for p in lines(out / "lammps_mesont.jsonl"):
        # LAMMPS up to turf's last strain: relaxation + those steps, and the largest force left
        upto = [s for s in p.get("steps", []) if s["strain"] <= eps_turf + 1e-9]
        its = p["relaxation"]["iterations"] + sum(s.get("iterations", 0) for s in upto)
        wall = p["relaxation"]["wall_s"] + sum(s["wall_s"] for s in upto)
        cost = {c["state"]: c["us_per_node_evaluation"] for c in p["cost"]}
        fmax = max([p["relaxation"].get("force_max_final_nN", 0.0)] + [s.get("force_max_final_nN", 0.0) for s in upto])
        failed = [s["strain"] for s in p.get("steps", []) if "alpha is zero" in s.get("stop", "")]
        answer = (f"σ = {upto[-1]['stress_GPa'] * 1e3:.4g} MPa at ε = {upto[-1]['strain']:.2f}" if upto else "—") + (
            f"; largest force left {fmax:.2g} nN (tolerance {p['ftol_max_component_nN']:g})")
        if failed:
            answer += f"; line search failed from ε = {min(failed):.2f}"
        rows.append((
            "", f"LAMMPS MESONT {p['min_style']} to ε = {eps_turf:.2f} ({its} iterations; "
            + ", ".join(f"{k} {c:.2f}" for k, c in cost.items()) + " µs per node-evaluation)",
            answer, f"{wall:.1f}", f"{wall / wall_turf:.2f}",
        ))
    return rows


SECTIONS = {"cantilever": cantilever_rows, "halfspace": halfspace_rows, "hertz": hertz_rows, "hyperfoam": hyperfoam_rows,
            "mesont": mesont_rows}


def main(out, names):
    """The table of the sections `names` (all by default) from the results in `out`."""
    rows = [r for n in names for r in SECTIONS[n](Path(out))]
    print("| problem | code | error | wall time, s | time / turf |")
    print("|---|---|---|---|---|")
    for r in rows:
        print("| " + " | ".join(r) + " |")


if __name__ == "__main__":
    # python compare.py [RESULTS_DIR [SECTION ...]], SECTION one of SECTIONS (default: all)
    bad = [n for n in sys.argv[2:] if n not in SECTIONS]
    if bad:
        sys.exit(f"compare.py: unknown section {bad[0]!r}; allowed: {', '.join(SECTIONS)}")
    main(sys.argv[1] if len(sys.argv) > 1 else "results", sys.argv[2:] or list(SECTIONS))
