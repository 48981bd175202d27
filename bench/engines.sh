#!/usr/bin/env bash
# The two remeshing engines side by side (issue 11): `vesselmesh remesh --engine native` and
# `--engine gmsh` (Gmsh's reparametrization, the seed paper's route; for the anisotropic field also
# `--gmsh-algorithm bamg`, which takes the whole metric) on the same input, the same
# size field (the four kinds) and the same target count; both measured by the same code against
# the field they met (vesselmesh's --json figures: triangles, smallest angle, mean quality in the
# metric, fraction of edges of unit metric length, Hausdorff distance from the input).
#   bench/engines.sh [BUILD] [TARGET_TRIANGLES] [SURFACE:UNITS ...]
# Defaults: build, 12000 triangles, the vessels of ../shared/data/vessels (open ones, their units).
# Times: one run each (the count corrections included), wall clock from the --json "seconds".
set -euo pipefail
build=${1:-build}
target=${2:-12000}
shift $(( $# > 2 ? 2 : $# ))
shared=$(dirname "$0")/../../shared/data/vessels
surfaces=("$@")
if [ ${#surfaces[@]} -eq 0 ]; then
  for f in vmtk_aorta_iliac_bifurcation_open_mm.stl:mm gmsh_aortic_arch_open_cm.stl:cm gmsh_carotid_bifurcation_open_m.stl:m; do
    [ -f "$shared/${f%%:*}" ] && surfaces+=("$shared/$f")
  done
fi
[ ${#surfaces[@]} -gt 0 ] || { echo "bench/engines.sh: no surfaces (give SURFACE:UNITS)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf '%-44s %-12s %-7s %8s %9s %9s %8s %9s %10s\n' surface size engine seconds triangles min_angle quality unit_edges hausdorff
for entry in "${surfaces[@]}"; do
  surface=${entry%%:*}
  units=${entry##*:}
  for kind in uniform distance curvature anisotropic; do
    engines="native gmsh"
    [ "$kind" = anisotropic ] && engines="native gmsh bamg"  # bamg: Gmsh's BAMG with the whole metric
    for engine in $engines; do
      args=(--engine "$engine")
      [ "$engine" = bamg ] && args=(--engine gmsh --gmsh-algorithm bamg)
      if json=$("$build/vesselmesh" remesh "$surface" --units "$units" --size "$kind" --target-triangles "$target" \
                  "${args[@]}" -o "$work/out.vtp" --json -q 2>"$work/err"); then
        python3 -c '
import json, sys
j = json.loads(sys.argv[1])
print("%-44s %-12s %-7s %8.1f %9d %9.1f %8.3f %9.3f %10.4f" % (sys.argv[2][-44:], sys.argv[3], sys.argv[4], j["seconds"],
      j["triangles"], j["min_angle_deg"], j["mean_quality"], j["edges_in_unit_range"], j["hausdorff"]))' \
          "$json" "$(basename "$surface")" "$kind" "$engine"
      else
        printf '%-44s %-12s %-7s failed: %s\n' "$(basename "$surface")" "$kind" "$engine" "$(tail -1 "$work/err")"
      fi
    done
  done
done
echo "(lengths in mm; quality and unit edges measured in the field each engine met; gmsh (Delaunay) meets an anisotropic field through its smallest size, bamg through the whole metric)"
