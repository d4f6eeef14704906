#!/usr/bin/env bash
# Which tube parameters set the turf's stiffness and plateau: one-at-a-time sweeps of the tube
# density, length, length spread, van der Waals line energy, tilt and waviness about the
# quickstart's statistics, each point an ensemble of axial platen compressions to 30 %
# (docs/discrete-compression.md "Which tube parameters set the stiffness and the plateau").
#
#   bash benches/sweeps/turf_parameters.sh                 # every point, 9 tubes x 4 realisations
#   TUBES=25 REALISATIONS=4 bash benches/sweeps/turf_parameters.sh base spread_0.01
#
# Each point keeps the number of tubes (TUBES, a square number) and sets the periodic box from the
# density; the segment length is a tenth of the tube length. Runs go to runs/sweeps/<label>
# (a finished point is not run again); the table (stdout, and runs/sweeps/table.md) is read from
# each run's summary.json and discrete_ensemble_mean_top.csv by table.py.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="${OUT:-$root/runs/sweeps}"
tubes="${TUBES:-9}"
realisations="${REALISATIONS:-4}"
mkdir -p "$out"
(cd "$root" && cargo build --release --locked -q)
turf="$root/target/release/turf"

# label | density (1/cm^2) | length (um) | length spread | gamma_line (nN) | mean tilt | tilt |
# waviness (nm) | wave coherence
points="
base               1e10 2   0.05 1   0   0.1  50  0
length_1um         1e10 1   0.05 1   0   0.1  50  0
length_0.5um       1e10 0.5 0.05 1   0   0.1  50  0
spread_0.1         1e10 2   0.1  1   0   0.1  50  0
spread_0.02        1e10 2   0.02 1   0   0.1  50  0
spread_0.01        1e10 2   0.01 1   0   0.1  50  0
gamma_0.1nN        1e10 2   0.05 0.1 0   0.1  50  0
gamma_0.3nN        1e10 2   0.05 0.3 0   0.1  50  0
gamma_3nN          1e10 2   0.05 3   0   0.1  50  0
gamma_10nN         1e10 2   0.05 10  0   0.1  50  0
tilt_0.03          1e10 2   0.05 1   0   0.03 50  0
waviness_10nm      1e10 2   0.05 1   0   0.1  10  0
straight           1e10 2   0.05 1   0   0.03 10  0
straight_spread_0.01 1e10 2 0.01 1   0   0.03 10  0
collective         1e10 2   0.05 1   0.1 0.02 50  0.8
short_uniform      1e10 0.5 0.01 1   0   0.1  50  0
short_collective   1e10 0.5 0.01 1   0.1 0.02 50  0.8
short_collective_2e10 2e10 0.5 0.01 1 0.1 0.02 50 0.8
short_collective_3e10 3e10 0.5 0.01 1 0.1 0.02 50 0.8
"
want=" $* "
labels=()
while read -r label n len spread gamma mtilt tilt wav coh; do
    [ -z "$label" ] && continue
    if [ $# -gt 0 ] && [[ "$want" != *" $label "* ]]; then continue; fi
    labels+=("$label")
    dir="$out/t${tubes}_$label"
    if [ -f "$dir/summary.json" ] && grep -q '"complete": true' "$dir/summary.json"; then continue; fi
    box=$(python3 -c "print(f'{(${tubes}/(${n}*1e-14))**0.5:.4g} nm')")
    seg=$(python3 -c "print(f'{${len}*100:.4g} nm')")
    echo "== $label: n = $n /cm^2, box $box, L = $len um (segments $seg), gamma_L = $gamma nN, length spread $spread, tilt $mtilt + $tilt, waviness $wav nm (coherence $coh)" >&2
    "$turf" run "$root/scenes/turf_rve.toml" --set 'compression.mode="axial"' \
        --set "turf.realisations=$realisations" --set "turf.density=\"$n 1/cm^2\"" \
        --set "turf.box=[\"$box\",\"$box\"]" --set "turf.growth.length=\"$len um\"" \
        --set "turf.tube.segment=\"$seg\"" --set "turf.vdw.gamma_line=\"$gamma nN\"" \
        --set "turf.growth.tilt=$tilt" --set "turf.growth.waviness=\"$wav nm\"" \
        --set "turf.growth.length_spread=$spread" --set "turf.growth.mean_tilt=$mtilt" \
        --set "turf.growth.wave_coherence=$coh" \
        --out "$dir" --json > "$dir.log" 2>&1 || echo "   failed: see $dir.log" >&2
done <<< "$points"
(cd "$out" && python3 "$here/table.py" "${labels[@]/#/t${tubes}_}" | tee "$out/table.md")
