#!/usr/bin/env bash
# What a time step's linear solve costs on the flows a study runs (issue 48's benchmark): the
# anastomosis study's curvature mesh under examples/anastomosis.toml's pulsatile flow (CFL up to
# about 30) and the FDA nozzle at Re 500 on a coarse mesh from its Stokes flow (CFL about 50), each
# run twice in the same session with one binary, interleaved: the solves starting from the least-
# residual combination of the extrapolated flow and the last solutions (`[solver] kept_solutions`,
# the default 4) and from the extrapolation alone (0). One process.
#   bench/time_steps.sh [BUILD] [OUT] [ANASTOMOSIS_END_S=0.3] [FDA_STEPS=12] [ROUNDS=1]
# Printed per case and variant: unknowns, steps, linear iterations a step (mean and largest over the
# steps after the fifth: the first ones start the flow), solve and whole seconds a step over the
# same steps, the largest CFL number, and the kept variant's ratios against the other.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build}
out=${2:-$(mktemp -d)}
ana_end=${3:-0.3}
fda_steps=${4:-12}
rounds=${5:-1}
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

variant() {  # case kept -> a case file with [solver] kept_solutions = kept
  local file="$out/$1-kept$2.toml"
  if grep -q '^\[solver\]' "$out/$1.toml"; then
    sed "s|^\[solver\]|[solver]\nkept_solutions = $2|" "$out/$1.toml" > "$file"
  else
    { cat "$out/$1.toml"; printf '[solver]\nkept_solutions = %s\n' "$2"; } > "$file"
  fi
  echo "$file"
}

printf "%-12s %-6s %9s %6s %-16s %10s %10s %7s\n" case kept unknowns steps iterations solve_s total_s cfl
for case in anastomosis nozzle; do
  for round in $(seq "$rounds"); do
    for kept in 4 0; do
      "$vm" simulate "$(variant "$case" "$kept")" -o "$out/$case-kept$kept-$round" -q
    done
  done
  python3 - "$out" "$case" "$rounds" <<'PY'
import csv, json, sys
out, case, rounds = sys.argv[1], sys.argv[2], int(sys.argv[3])
figures = {}
for kept in (4, 0):
    its, solve, total, cfl, unknowns, steps = [], [], [], 0.0, 0, 0
    for r in range(1, rounds + 1):
        d = f"{out}/{case}-kept{kept}-{r}"
        rows = list(csv.DictReader(open(f"{d}/log.csv")))
        settled = rows[5:]
        its += [int(x["linear_iterations"]) for x in settled]
        solve += [float(x["solve_seconds"]) for x in settled]
        total += [float(x["seconds"]) for x in settled]
        cfl = max(cfl, max(float(x["max_cfl"]) for x in rows))
        unknowns, steps = json.load(open(f"{d}/summary.json"))["dofs"], len(rows)
    mean = lambda v: sum(v) / len(v)
    figures[kept] = (mean(its), mean(solve), mean(total))
    print(f"{case:12s} {kept:<6d} {unknowns:9d} {steps:6d} {mean(its):6.1f} (max {max(its):3d})  "
          f"{mean(solve):10.3f} {mean(total):10.3f} {cfl:7.1f}")
k, o = figures[4], figures[0]
print(f"{case:12s} kept 4 against 0: iterations x{k[0] / o[0]:.2f}, solve x{k[1] / o[1]:.2f}, step x{k[2] / o[2]:.2f}")
PY
done
