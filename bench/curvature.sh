#!/usr/bin/env bash
# Curvature of a one-million-point jittered torus: vesselmesh (1 and 2 threads; fitted and
# Max normals) against VTK's vtkCurvatures, times and median errors of H, with the ratios; and
# the memory floor of vesselmesh's passes (the same arrays with trivial arithmetic).
#   bench/curvature.sh [BUILD_FOLDER]     (default: build)
set -euo pipefail
build=${1:-build}
out=$(mktemp)
trap 'rm -f "$out"' EXIT
"$build/bench/bench_curvature" --benchmark_out="$out" --benchmark_out_format=json >/dev/null 2>&1
python3 - "$out" <<'PY'
import json, sys
runs = json.load(open(sys.argv[1]))["benchmarks"]
print(f"jittered torus, {int(runs[0]['points'])} points: normals, areas, curvature tensors, principal values")
rows = []
for b in runs:
    name = b["name"].split("/")[0].replace("BM_Curvature_", "")
    rows.append((name, int(b["threads"]), b["real_time"], b["H_error_percent"]))
    error = f"{b['H_error_percent']:6.2f} %" if b["H_error_percent"] >= 0 else "     - (memory floor: the same arrays, trivial arithmetic)"
    print(f"  {name:28s} threads {int(b['threads'])}  {b['real_time']:8.1f} ms   H error (median) {error}")
vtk = next(r for r in rows if r[0] == "vtkCurvatures")
for r in rows:
    if r[0] not in ("vtkCurvatures", "ArraysOnly"):
        print(f"  speed vs vtkCurvatures: {r[0]} ({r[1]} threads) {vtk[2] / r[2]:.2f} x")
PY
