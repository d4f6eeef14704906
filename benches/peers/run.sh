#!/usr/bin/env bash
# Run turf and its peers on the same problems and print the comparison (docs/peers.md).
#
#   bash benches/peers/run.sh            # all peers, default sizes (tens of minutes on 2 cores)
#   QUICK=1 bash benches/peers/run.sh    # coarse peer settings, a few minutes
#
# Installs the Python peers from PyPI into benches/peers/.venv (pinned in requirements.txt) and
# CalculiX from Debian when missing; builds turf in release. Results go to
# benches/peers/results/*.json, the table to stdout.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
venv="$here/.venv"
out="$here/results"
mkdir -p "$out"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/pip" install -q -r "$here/requirements.txt"   # a no-op when the pins are installed
py="$venv/bin/python"
(cd "$root" && cargo build --release --locked -q)
turf="$root/target/release/turf"

# 1. single rod: the Bisshopp–Drucker cantilever, turf (Newton, static) vs PyElastica (damped
#    explicit dynamics brought to rest)
"$turf" run "$root/scenes/rods_cantilever.toml" --out "$out/turf_cantilever" --json > "$out/turf_cantilever.json"
if [ -n "${QUICK:-}" ]; then rests="1e-8"; else rests="1e-8 1e-9 1e-10"; fi
: > "$out/pyelastica_cantilever.jsonl"
for r in $rests; do
    "$py" "$here/pyelastica/cantilever.py" --elements 50 --damping 10 --rest "$r" --max-time 40 \
        >> "$out/pyelastica_cantilever.jsonl"
done

# 2. half-space pull-off, LJ 10-4 (Adhesion's "LJ93" energy), mu = 1: turf's axisymmetric
#    integral solver vs the 3D FFT boundary-element half-space
"$turf" theory halfspace --mu 1 --law lj104 --json > "$out/turf_halfspace_mu1.json"
if [ -n "${QUICK:-}" ]; then grids="32"; else grids="32 64 128"; fi
: > "$out/contactmechanics_pulloff.jsonl"
for n in $grids; do
    "$py" "$here/contactmechanics/pulloff.py" --mu 1 --nx "$n" --step 0.1 \
        >> "$out/contactmechanics_pulloff.jsonl"
done

# 3. Hertz by FE: turf's axisymmetric CST (scenes/hertz.toml, load and unload) vs CalculiX CAX4
#    with a penalty contact pair (loading only)
"$turf" run "$root/scenes/hertz.toml" --out "$out/turf_hertz" --json > "$out/turf_hertz.json"
command -v ccx > /dev/null || { apt-get update -qq && apt-get install -y -qq calculix-ccx; }
if [ -n "${QUICK:-}" ]; then meshes="10:1.3"; else meshes="10:1.3 20:1.15 40:1.1"; fi
: > "$out/calculix_hertz.jsonl"
for m in $meshes; do
    "$py" "$here/calculix/hertz.py" --per-radius "${m%%:*}" --ratio "${m##*:}" >> "$out/calculix_hertz.jsonl"
done

# 4. hyperfoam sphere at finite deformation, no adhesion: turf's scene at a/20 and a/40 vs
#    CalculiX CAX4 *HYPERFOAM (foam within 5a, its small-strain limit beyond; docs/peers.md),
#    after the one-element check of CalculiX's *HYPERFOAM against the closed form
"$turf" run "$here/hyperfoam_sphere.toml" --out "$out/turf_hyperfoam_sphere" --json > "$out/turf_hyperfoam_sphere.json"
"$turf" run "$here/hyperfoam_sphere.toml" --set mesh.smallest="7.91 nm" \
    --out "$out/turf_hyperfoam_sphere_a40" --json > "$out/turf_hyperfoam_sphere_a40.json"
"$py" "$here/calculix/hyperfoam.py" --check > "$out/calculix_hyperfoam_check.jsonl"
if [ -n "${QUICK:-}" ]; then foams="10"; else foams="10 20"; fi
: > "$out/calculix_hyperfoam_sphere.jsonl"
for n in $foams; do
    "$py" "$here/calculix/hyperfoam.py" --per-radius "$n" >> "$out/calculix_hyperfoam_sphere.jsonl"
done

# 5. LAMMPS MESONT (pair/bond/angle mesocnt) on turf_100x100 scaled to the (10,10) tube
#    (docs/peers.md "LAMMPS MESONT"): turf writes the scaled turf's nodes, LAMMPS measures its cost
#    per force evaluation and compresses it by minimisation; turf compresses the same scaled turf.
#    turf's side runs one 3 % step unless MESONT_FULL=1 (the full 30 % in 10 steps; turf's
#    Newton took about an hour on the original 100 x 100 turf, docs/benchmarks.md); QUICK=1 also
#    stops LAMMPS at 3 % in one step.
mesont="$out/mesont"
"$py" "$here/mesont/scale.py" --out "$mesont" > "$out/mesont_scale.json"
"$turf" run "$mesont/scaled_geometry.toml" --out "$mesont/turf_geometry" --json > "$mesont/turf_geometry.json"
if [ -n "${QUICK:-}" ]; then lmp_run="--to 0.03 --steps 1 --maxiter-relax 3000 --maxiter 500"
else lmp_run="--to 0.3 --steps 10 --maxiter-relax 10000 --maxiter 3000"; fi
OMP_NUM_THREADS=1 "$py" "$here/mesont/compress.py" $lmp_run --line forcezero \
    --vtk "$mesont/turf_geometry/vtk/discrete_step_000.vtu" --scene "$mesont/scaled_geometry.toml" \
    --work "$mesont/lammps" > "$out/lammps_mesont.jsonl"
if [ -n "${MESONT_FULL:-}" ]; then turf_strain=(); else
    turf_strain=(--set compression.to=0.03 --set compression.steps=1); fi
RAYON_NUM_THREADS=1 "$turf" run "$mesont/scaled.toml" "${turf_strain[@]}" --set output.vtk=false \
    --out "$mesont/turf_scaled" --json > "$out/turf_mesont_scaled.json"

"$py" "$here/compare.py" "$out"
