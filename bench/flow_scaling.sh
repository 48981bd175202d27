#!/usr/bin/env bash
# How the flow solver's cost per step and memory grow with the mesh (issue 29's benchmark): the
# pipe (radius 2 mm, length 20 mm, `vesselmesh volume` defaults: 4 layers over 10 % of the radius)
# at several resolutions, STEPS time steps of 1 ms from the Stokes flow at 1 mL/s, one process.
#   bench/flow_scaling.sh [BUILD] [OUT] [STEPS=6] [RESOLUTIONS="0.48 0.326 0.223 0.147"]
#   (0.48 / 0.326 / 0.223 / 0.147 mm: 36k / 86k / 220k / 420k unknowns; 0.075: 1.40 M, 2.2 GB)
#   PETSC="..." adds PETSc options to the case's [solver] (to compare preconditioners); THREADS=N
#   sets the assembly's threads ([solver] threads; default automatic: the cores).
# Printed per mesh: unknowns, seconds a time step (steps 2..STEPS: the first builds the
# preconditioner), the same per million unknowns and against the smallest mesh's, linear
# iterations per step, assembly and solve seconds a step, the Stokes start (seconds,
# iterations), the peak resident memory of the whole process and per unknown.
set -euo pipefail
build=${1:-build}
out=${2:-$(mktemp -d)}
steps=${3:-6}
resolutions=${4:-"0.48 0.326 0.223 0.147"}
vm="$build/vesselmesh"
# shellcheck source=bench/pipe_case.sh
source "$(dirname "$0")/pipe_case.sh"
[[ -x $vm ]] || { echo "build first: $vm is needed" >&2; exit 2; }
[[ -x /usr/bin/time ]] || { echo "/usr/bin/time is needed (apt-get install time)" >&2; exit 2; }
mkdir -p "$out"
out=$(cd "$out" && pwd)
vm=$(cd "$(dirname "$vm")" && pwd)/vesselmesh
end=$(python3 -c "print($steps * 0.001)")
echo "vesselmesh $("$vm" --version 2>/dev/null | head -1), $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg); results in $out"
printf "%-6s %9s %9s %12s %7s %-22s %8s %8s %15s %9s %8s\n" res_mm unknowns s/step s/step/M ratio iterations assembly solve stokes_start peak_MB KB/unk
base=""
for r in $resolutions; do
  dir="$out/r$r"
  mkdir -p "$dir"
  [[ -f $dir/pipe.msh ]] || {
    "$vm" synth cylinder --radius 2 --length 20 --resolution "$r" -o "$dir/pipe.stl" -q
    "$vm" volume "$dir/pipe.stl" -o "$dir/pipe.msh" --end inlet:0,0,0 --end outlet_1:0,0,20 -q
  }
  write_pipe_case "$dir/case.toml" 0.001 "$end" "$steps" "${PETSC:-}"
  /usr/bin/time -f "%M" -o "$dir/mem" "$vm" simulate "$dir/case.toml" -o "$dir/result" 2>"$dir/log" >/dev/null
  line=$(python3 - "$dir" "$base" <<'PY'
import csv, json, re, sys
d, base = sys.argv[1], sys.argv[2]
s = json.load(open(f"{d}/result/summary.json"))
rows = list(csv.DictReader(open(f"{d}/result/log.csv")))[1:]
n = max(len(rows), 1)
step = sum(float(r["seconds"]) for r in rows) / n
assembly = sum(float(r["assembly_seconds"]) for r in rows) / n
solve = sum(float(r["solve_seconds"]) for r in rows) / n
its = "/".join(r["linear_iterations"] for r in rows)
m = re.search(r"Stokes flow at t = \S+ s \((\d+) linear iterations, (\S+) s\)", open(f"{d}/log").read())
stokes = f"{float(m.group(2)):.1f}s/{m.group(1)}it" if m else "?"
mb = int(open(f"{d}/mem").read().split()[-1]) / 1024
per_m = step / s["dofs"] * 1e6
ratio = per_m / float(base) if base else 1.0
print(f"{s['dofs']} {step:.3f} {per_m:.2f} {ratio:.2f} {its} {assembly:.3f} {solve:.3f} {stokes} {mb:.0f} {mb * 1024 / s['dofs']:.2f}")
PY
)
  read -r dofs step per_m ratio its assembly solve stokes mb kb <<<"$line"
  [[ -n $base ]] || base=$per_m
  printf "%-6s %9s %9s %12s %7s %-22s %8s %8s %15s %9s %8s\n" "$r" "$dofs" "$step" "$per_m" "$ratio" "$its" "$assembly" "$solve" "$stokes" "$mb" "$kb"
done
