#!/usr/bin/env bash
# Issue 47: the FDA nozzle's steady jet at Re_throat = 500 on three meshes, coarse to fine, each by
# bench/fda_nozzle.sh with STEADY=1, then the grid convergence of the centreline velocity at the
# laboratories' stations (bench_fda_nozzle --series: the observed order, the extrapolated value,
# the finest level's GCI, each level's RMS difference and stations within the labs' range).
#   bench/fda_nozzle_series.sh [BUILD] [OUT]
# Levels (points around the lumen, largest size in mm, jet size in mm): 23/0.91/0.35, 30/0.7/0.27,
# 39/0.54/0.21, ratios about 1.3 in the sizes; the jet refined within 3 mm of the axis from the
# expansion to z = 85 mm (fda_nozzle.sh JET=). NOJET=1 leaves the jet at the outlet pipe's sizes.
# Measured with NP=2 (2 cores): 185,961 / 389,867 / 713,337 points (ratios 1.28 and 1.22 in h), the
# first two 433 s and 1651 s (1.1 and 2.3 GB a process), the third over an hour (stopped at its ninth
# Newton iteration after 58 minutes: ILU's factors fail at half the inflow and the SOR sweeps then take
# 4000+ linear iterations a Newton iteration): more cores for it.
# OUT/coarse, OUT/medium, OUT/fine hold each level's run; OUT/series the comparison.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build}
out=${2:-$build/fda-nozzle-series}
levels=("coarse 23 0.91 0.35" "medium 30 0.7 0.27" "fine 39 0.54 0.21")
for level in "${levels[@]}"; do
  read -r name ppc hmax jet <<<"$level"
  if [[ -n "${NOJET:-}" ]]; then jet=""; fi
  echo "fda_nozzle_series.sh: $name level ($ppc points around, sizes at most $hmax mm, jet ${jet:-not refined})"
  JET="$jet" STEADY=1 "$here/fda_nozzle.sh" "$build" "$out/$name" "$ppc" "$hmax" | grep -E "RMS|pressure drop|simulate:"
done
"$build/bench/bench_fda_nozzle" --series "$out/fine" "$out/medium" "$out/coarse" "$out/series"
