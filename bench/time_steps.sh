#!/usr/bin/env bash
# What a time step's linear solve costs on the flows a study runs (issue 48's benchmark): the
# anastomosis study's curvature mesh under examples/anastomosis.toml's pulsatile flow (CFL up to
# about 40), the FDA nozzle at Re 500 on a coarse mesh from its Stokes flow (CFL about 50) and, with
# PIPE=1, the benchmark pipe (bench/flow_scaling.sh's, 285k unknowns) at dt 10 ms (CFL about 25),
# each case run once a variant in the same session with one binary, interleaved. One process.
#   bench/time_steps.sh [BUILD] [OUT] [ANASTOMOSIS_END_S=0.3] [FDA_STEPS=12] [ROUNDS=1] [VARIANT...]
# A VARIANT is NAME:KEPT:PETSC_OPTIONS ([solver] kept_solutions and petsc_options); the default pair
# compares the solves starting from the least-residual combination of the extrapolated flow and the
# last solutions (kept:4:, the default) with the extrapolation alone (kept0:0:). E.g. the velocity
# block by block-Jacobi ILU and the Schur factorization's upper part only:
#   bench/time_steps.sh build OUT 0.3 12 1 default:4: \
#     'ilu-upper:4:-fieldsplit_u_pc_type bjacobi -fieldsplit_u_sub_pc_type ilu -pc_fieldsplit_schur_fact_type upper'
# Printed per case and variant: unknowns, steps, linear iterations a step (mean and largest over the
# steps after the fifth: the first ones start the flow), solve and whole seconds a step over the
# same steps, the steps that built a preconditioner, the largest CFL number, the peak resident
# memory (MB), and each variant's ratios against the first.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build}
out=${2:-$(mktemp -d)}
ana_end=${3:-0.3}
fda_steps=${4:-12}
rounds=${5:-1}
shift $(($# < 5 ? $# : 5))
variants=("$@")
(( ${#variants[@]} )) || variants=("kept4:4:" "kept0:0:")
vm="$build/vesselmesh"
[[ -x $vm ]] || { echo "build first: $vm is needed" >&2; exit 2; }
mkdir -p "$out"
out=$(cd "$out" && pwd)
vm=$(cd "$(dirname "$vm")" && pwd)/vesselmesh
echo "vesselmesh $("$vm" --version 2>/dev/null | head -1), $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg); results in $out"

# The anastomosis study's curvature mesh (as examples/anastomosis_study.toml makes it, 8000 triangles).
"$vm" remesh "$here/../data/anastomosis.vtp" --size curvature --target-triangles 8000 -o "$out/anastomosis.vtp" -q
"$vm" volume "$out/anastomosis.vtp" -o "$out/anastomosis.msh" --layers 4 --thickness-ratio 0.1 --algorithm delaunay \
  --end inlet:-30.36,0,13.52 --end outlet:42.83,0,0 --end stump:-16.66,0,0 -q
sed -e "s|^mesh = .*|mesh = \"$out/anastomosis.msh\"|" -e "s|^end = .*|end = $ana_end|" \
  -e "s|\"popliteal_flow.csv\"|\"$here/../examples/popliteal_flow.csv\"|" "$here/../examples/anastomosis.toml" \
  > "$out/anastomosis.toml"

# The FDA nozzle at Re 500, coarse (23 points round the lumen, sizes at most 0.91 mm), from its Stokes flow.
# shellcheck source=bench/nozzle_case.sh
source "$here/nozzle_case.sh"
nozzle_mesh "$vm" "$out" 23 0.91 -q
write_nozzle_case "$out/nozzle.toml" "[time]
dt = 0.005
end = $(python3 -c "print($fda_steps * 0.005)")
save_every = $fda_steps
initial = \"stokes\""
printf '[output]\nfluid_every = 0\n' >> "$out/nozzle.toml"

variant() {  # case variant -> a case file with the variant's [solver] keys
  local name=${2%%:*} rest=${2#*:}
  local kept=${rest%%:*} options=${rest#*:}
  local file="$out/$1-$name.toml" keys="kept_solutions = $kept\npetsc_options = \"$options\""
  if grep -q '^\[solver\]' "$out/$1.toml"; then
    sed -e '/^petsc_options = /d' -e "s|^\[solver\]|[solver]\n$keys|" "$out/$1.toml" > "$file"
  else
    { cat "$out/$1.toml"; printf '[solver]\n%b\n' "$keys"; } > "$file"
  fi
  echo "$file"
}

cases=(anastomosis nozzle)
if [[ ${PIPE:-0} == 1 ]]; then  # bench/flow_scaling.sh's pipe at resolution 0.2 mm
  # shellcheck source=bench/pipe_case.sh
  source "$here/pipe_case.sh"
  "$vm" synth cylinder --radius 2 --length 20 --resolution 0.2 -o "$out/pipe.stl" -q
  "$vm" volume "$out/pipe.stl" -o "$out/pipe.msh" --end inlet:0,0,0 --end outlet_1:0,0,20 -q
  write_pipe_case "$out/pipe.toml" 0.01 0.2 20
  printf '[output]\nfluid_every = 0\n' >> "$out/pipe.toml"
  cases+=(pipe)
fi

printf "%-12s %-10s %9s %6s %-16s %10s %10s %6s %7s %8s\n" \
  case variant unknowns steps iterations solve_s total_s built cfl peak_mb
for case in "${cases[@]}"; do
  for round in $(seq "$rounds"); do
    for v in "${variants[@]}"; do
      "$vm" simulate "$(variant "$case" "$v")" -o "$out/$case-${v%%:*}-$round" -q
    done
  done
  python3 - "$out" "$case" "$rounds" "${variants[@]%%:*}" <<'PY'
import csv, json, sys
out, case, rounds, names = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4:]
figures = {}
for name in names:
    its, solve, total, built, cfl, peak, unknowns, steps = [], [], [], 0, 0.0, 0.0, 0, 0
    for r in range(1, rounds + 1):
        d = f"{out}/{case}-{name}-{r}"
        rows = list(csv.DictReader(open(f"{d}/log.csv")))
        settled = rows[5:]
        its += [int(x["linear_iterations"]) for x in settled]
        solve += [float(x["solve_seconds"]) for x in settled]
        total += [float(x["seconds"]) for x in settled]
        built += sum(int(x["preconditioners_built"]) > 0 for x in settled)
        cfl = max(cfl, max(float(x["max_cfl"]) for x in rows))
        summary = json.load(open(f"{d}/summary.json"))
        peak = max(peak, max(summary["peak_memory_mb"]))
        unknowns, steps = summary["dofs"], len(rows)
    mean = lambda v: sum(v) / len(v)
    figures[name] = (mean(its), mean(solve), mean(total), peak)
    print(f"{case:12s} {name:10s} {unknowns:9d} {steps:6d} {mean(its):6.1f} (max {max(its):3d})  "
          f"{mean(solve):10.3f} {mean(total):10.3f} {built:6d} {cfl:7.1f} {peak:8.0f}")
first = figures[names[0]]
for name in names[1:]:
    f = figures[name]
    print(f"{case:12s} {name} against {names[0]}: iterations x{f[0] / first[0]:.2f}, solve x{f[1] / first[1]:.2f}, "
          f"step x{f[2] / first[2]:.2f}, peak memory x{f[3] / first[3]:.2f}")
PY
done
