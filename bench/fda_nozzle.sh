#!/usr/bin/env bash
# Issues 8 and 47: validation on the FDA benchmark nozzle (sudden-expansion orientation, Re_throat = 500,
# or RE=2000): the whole pipeline from `vesselmesh synth nozzle` to the comparison with the FDA's measurements
# (five laboratories' centerline velocity, wall pressure, velocity profiles and wall shear stress), figures
# included; the flow rate is the measurements' files'.
#   bench/fda_nozzle.sh [BUILD] [OUT] [POINTS_PER_CIRCLE] [HMAX_MM] [DT_S] [END_S]
# Defaults: build, BUILD/fda-nozzle, 30 points around the lumen (0.42 mm in the throat), sizes at
# most 0.7 mm, dt 5 ms to t = 0.5 s from the Stokes flow (the steady state, reached by time steps).
# STEADY=1 solves for the steady flow instead (Newton's method; DT_S and END_S unused): on the
# defaults' mesh (669k unknowns) 12 iterations to a residual of 1.6e-7 in 359 s and 2.0 GB on one
# process, where 300 time steps took 2140 s to t = 1.5 s. 4 boundary layers, TetGen inside.
# JET=SIZE refines the interior along the jet (within 3 mm of the axis from the expansion to z = 85 mm,
# `volume --refine`; SIZE in mm), where the distance sizing leaves the outlet pipe's core at HMAX_MM:
# the steady jet's decay past z = 30 mm is the mesh's (three levels of the defaults' sizing, ratio 1.31
# and 1.15 in h: 0.483, 0.542, 0.571 m/s at z = 40 mm against the labs' 0.625; JET=0.35 on the coarsest
# walls: 0.640; docs/validation/fda_nozzle.md).
# STATS_FROM=T (s) keeps the flow's time statistics from T to the end (statistics.vtu: the mean velocity and
# pressure, the RMS of the velocity's fluctuation; `vesselmesh sample OUT/flow --statistics --line ...` reads
# them): what the transitional jet at RE=2000 is compared by (bench_fda_nozzle then compares the time means, the
# jet's breakdown and the centreline's fluctuation with the LDV file's). PERTURBATION=I disturbs the inflow (each
# velocity component's RMS I times the local speed; the laboratories' inlet pipe had about 0.03-0.04).
# TAU_C=f and TAU_M_TIME=C_t set the stabilization's parameters (the case's [stabilization]: tau_C times f, tau_M's
# time term C_t / dt^2; defaults 1 and 4): what docs/validation/fda_nozzle.md measured of them at Re 2000.
# Re 2000 as docs/validation/fda_nozzle.md has it: RE=2000 STATS_FROM=0.1 PERTURBATION=0.04 bench/fda_nozzle.sh
# build OUT 30 0.7 0.00085 0.5 (663k unknowns, a largest CFL number of 55: at 128, steps of 2 ms, the jet breaks
# down falsely at 31 mm; about 35 minutes on one process): the breakdown at 74.0 mm, the labs' 57-76.
# The measurements: ../shared/data/reference/fda_nozzle/SE_exp_0500.zip (RE=2000: SE_exp_2000.zip) beside the
# checkout (or $FDA_ZIP); they are read from there, never copied into the project. Set NP=K to run the solver
# under `mpirun -np K`. About 30 minutes on 2 cores with the defaults (490k unknowns, 16 s a step).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build}
out=${2:-$build/fda-nozzle}
ppc=${3:-30}
hmax=${4:-0.7}
dt=${5:-0.005}
end=${6:-0.5}
re=${RE:-500}
zip=${FDA_ZIP:-$here/../../shared/data/reference/fda_nozzle/SE_exp_$(printf %04d "$re").zip}
if [[ ! -f "$zip" ]]; then
  echo "fda_nozzle.sh: no measurements at $zip (set FDA_ZIP to SE_exp_$(printf %04d "$re").zip of the FDA's" \
    "benchmark data)" >&2
  exit 2
fi
vm="$build/vesselmesh"
compare="$build/bench/bench_fda_nozzle"
mkdir -p "$out"
rm -rf "$out/experiment"
unzip -q -o "$zip" -d "$out"
flow=$(awk '$1 == "fluid-volumetric-flow-rate" { printf "%.6g", $2 * 1e6; exit }' "$out"/experiment/PIV_*.txt)
if [[ -z "$flow" ]]; then
  echo "fda_nozzle.sh: $zip: no fluid-volumetric-flow-rate in experiment/PIV_*.txt" >&2
  exit 2
fi
# shellcheck source=bench/nozzle_case.sh
source "$here/nozzle_case.sh"
refine=()
if [[ -n "${JET:-}" ]]; then refine=(--refine "0,0,-1:0,0,85:3:$JET"); fi
nozzle_mesh "$vm" "$out" "$ppc" "$hmax" "${refine[@]}"
if [[ -n "${STEADY:-}" ]]; then
  time_section=$'[time]\nsteady = true                # Newton\'s method, its inflow in stages\nsteady_iterations = 40'
else
  time_section="[time]
steady = false
dt = $dt
end = $end
save_every = $(python3 -c "print(max(1, round($end / $dt / 5)))")
initial = \"stokes\"           # the developed pipe flow from the start; the jet grows in time"
fi
inlet_keys=""
if [[ -n "${PERTURBATION:-}" ]]; then inlet_keys="perturbation = $PERTURBATION"; fi
write_nozzle_case "$out/case.toml" "$time_section" "$flow" "$inlet_keys"
if [[ -n "${STATS_FROM:-}" ]]; then printf '[output]\nstatistics_from = %s\n' "$STATS_FROM" >>"$out/case.toml"; fi
if [[ -n "${TAU_C:-}${TAU_M_TIME:-}" ]]; then
  printf '[stabilization]\ntau_c_factor = %s\ntau_m_time = %s\n' "${TAU_C:-1.0}" "${TAU_M_TIME:-4.0}" >>"$out/case.toml"
fi
run=("$vm" simulate "$out/case.toml" -o "$out/flow")
if [[ -n "${NP:-}" ]]; then run=(mpirun --allow-run-as-root -np "$NP" "${run[@]}"); fi
if [[ -x /usr/bin/time ]]; then run=(/usr/bin/time -f "simulate: %e s wall, %M KB peak" "${run[@]}"); fi
"${run[@]}"
python3 - "$out/flow/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"simulate: {s['dofs']} unknowns, {s['steps']} steps, {s['seconds_per_step']:.2f} s a step, "
      f"{s['seconds_per_step_per_million_dofs']:.2f} s a step per million unknowns, {s['ranks']} rank(s)")
PY
"$compare" "$out/flow" "$out/experiment" "$out"
