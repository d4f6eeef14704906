#!/usr/bin/env python3
"""The parameter sweep's table (benches/sweeps/turf_parameters.sh): one row per run directory.

Reads each run's summary.json (the resolved scene in internal units, nm / nN / GPa, and the
ensemble's values) and discrete_ensemble_mean_top.csv (the mean loading curve against the strain
from the tubes' mean top, eps_bar). Stresses are printed in MPa; a value with its 95 % interval
of the ensemble mean as [low, high].
"""
import csv
import json
import math
import sys


def mpa(values, key):
    """Mean [low, high] of an ensemble value in GPa, printed in MPa, with the number of
    realisations it is over when that is fewer than finished (the fitted law's constants are
    reduced over the realisations whose fit softens)."""
    m = values.get(f"ensemble_{key}_mean_GPa")
    lo = values.get(f"ensemble_{key}_ci95_low_GPa")
    hi = values.get(f"ensemble_{key}_ci95_high_GPa")
    n = values.get(f"ensemble_{key}_n", 0)
    if m is None:
        return "—"
    text = f"{1e3 * m:.3g}" if lo is None else f"{1e3 * m:.3g} [{1e3 * lo:.3g}, {1e3 * hi:.3g}]"
    return text if n >= values["realisations_finished"] else f"{text} ({n:.0f})"


def at_mean_top(path, targets):
    """Mean stress (MPa) of the loading curve at each eps_bar in targets, '—' outside its range."""
    rows = [r for r in csv.DictReader(open(path)) if float(r["loading"]) == 1.0]
    pts = [(float(r["strain_from_mean_top"]), 1e3 * float(r["stress_mean_GPa"])) for r in rows]
    out = []
    for t in targets:
        value = "—"
        for (e0, s0), (e1, s1) in zip(pts, pts[1:]):
            if e0 <= t <= e1 and e1 > e0:
                value = f"{s0 + (s1 - s0) * (t - e0) / (e1 - e0):.3g}"
                break
        out.append(value)
    return out


def row(run):
    summary = json.load(open(f"{run}/summary.json"))
    turf = summary["scene"]["turf"]
    stage = next(s for s in summary["stages"] if s["stage"] == "discrete")
    v = stage["values"]
    n = turf["density"]  # 1/nm^2
    length = turf["growth"]["length"]
    ei = summary["derived"]["tube_bending_stiffness"]  # nN nm^2
    euler = n * math.pi**2 * ei / (4 * length**2)  # GPa: free-tip columns, n P
    tubes = summary["derived"]["tube_count"]
    peak = v["ensemble_peak_stress_mean_GPa"]
    bar = at_mean_top(f"{run}/discrete_ensemble_mean_top.csv", [0.0, 0.05, 0.10, 0.15])
    return [
        run,
        f"{n * 1e14:.3g}",
        f"{length / 1e3:.3g}",
        f"{turf['growth']['length_spread']:.3g}",
        f"{turf['vdw']['gamma_line']:.3g}",
        f"{turf['growth']['mean_tilt']:.3g} + {turf['growth']['tilt']:.3g}",
        f"{turf['growth']['waviness']:.3g} ({turf['growth']['wave_coherence']:.3g})",
        f"{1e3 * euler:.3g}",
        mpa(v, "tangent_e0"),
        mpa(v, "tangent_e_inf"),
        mpa(v, "peak_stress"),
        f"{peak / euler:.2g}",
        " / ".join(bar),
        f"{v['relaxed_contacts'] / tubes:.2g}" if "relaxed_contacts" in v else "—",
        f"{v['realisations_finished']:.0f}/{v['realisations']:.0f}",
        f"{stage['wall_time_s']:.0f}",
    ]


head = [
    "run", "n (1/cm²)", "L (µm)", "length spread", "γ_L (nN)", "tilt: patch + tube",
    "waviness, nm (coherence)", "n·P (MPa)",
    "E⁰ (MPa)", "E^∞ (MPa)", "peak (MPa)", "peak / n·P", "σ at ε̄ = 0 / 0.05 / 0.10 / 0.15 (MPa)",
    "relaxed contacts per tube", "finished", "wall (s)",
]
print("| " + " | ".join(head) + " |")
print("|" + "---|" * len(head))
for run in sys.argv[1:]:
    try:
        print("| " + " | ".join(row(run)) + " |")
    except (OSError, KeyError, StopIteration, ValueError) as err:
        print(f"| {run} | not read: {err} |")
