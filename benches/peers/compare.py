"""Print the turf-vs-peer table (markdown) from the JSON results written by run.sh."""

import json
import sys
from pathlib import Path


def lines(path):
    return [json.loads(l) for l in Path(path).read_text().splitlines() if l.strip()]


def main(out):
    out = Path(out)
    rows = []
    # cantilever
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
    # half-space pull-off
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
    # Hertz
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
    print("| problem | code | error | wall time, s | time / turf |")
    print("|---|---|---|---|---|")
    for r in rows:
        print("| " + " | ".join(r) + " |")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "results")
