#!/usr/bin/env bash
# Runs the STL-reading benchmark on one core and prints both readers' times and their ratio.
#   bench/read_stl.sh [BUILD_FOLDER]     (default: build)
set -euo pipefail
build=${1:-build}
out=$(mktemp)
trap 'rm -f "$out"' EXIT
taskset -c 0 "$build/bench/bench_read_stl" --benchmark_out="$out" --benchmark_out_format=json >/dev/null
python3 - "$out" <<'PY'
import json, sys
runs = {b["name"].split("/")[0]: b for b in json.load(open(sys.argv[1]))["benchmarks"]}
ours, peer = runs["BM_ReadStl_vesselmesh"], runs["BM_ReadStl_vtkSTLReader"]
print(f"binary STL, {int(ours['triangles'])} triangles, one core")
print(f"  vesselmesh io::read_stl   {ours['real_time']:8.1f} ms")
print(f"  VTK vtkSTLReader          {peer['real_time']:8.1f} ms")
print(f"  ratio (VTK / vesselmesh)  {peer['real_time'] / ours['real_time']:8.2f} x")
print(f"  goal under 1000 ms: {'met' if ours['real_time'] < 1000 else 'NOT met'}")
PY
