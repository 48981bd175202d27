#!/usr/bin/env bash
# The exports checked by the solvers' own tools (issue 33): the benchmark pipe (radius 2 mm, length
# 20 mm, `volume`'s defaults, with its prisms cut and kept) exported to OpenFOAM's polyMesh and run
# through OpenFOAM's checkMesh (Debian's `openfoam`; skipped with a message where it is absent).
#   bench/export_check.sh [BUILD] [OUT] [RESOLUTION=0.48]
# Printed per mesh: the cells checkMesh counts and its verdict ("Mesh OK." or its failed checks).
set -euo pipefail
build=${1:-build}
out=${2:-$(mktemp -d)}
resolution=${3:-0.48}
vm="$build/vesselmesh"
[[ -x $vm ]] || { echo "build first: $vm is needed" >&2; exit 2; }
if ! command -v checkMesh >/dev/null; then
  echo "skipped: OpenFOAM's checkMesh not found (apt-get install openfoam)" >&2
  exit 0
fi
export WM_PROJECT_DIR=${WM_PROJECT_DIR:-/usr/share/openfoam}  # Debian's bashrc does not set it
mkdir -p "$out"
"$vm" synth cylinder --radius 2 --length 20 --resolution "$resolution" -o "$out/pipe.stl" -q
for kind in tets prisms; do
  dir="$out/$kind"
  mkdir -p "$dir/system"
  flags=()
  [[ $kind == prisms ]] && flags=(--keep-prisms)
  "$vm" volume "$out/pipe.stl" -o "$dir/pipe.msh" --end inlet:0,0,0 --end outlet_1:0,0,20 "${flags[@]}" -q
  "$vm" export "$dir/pipe.msh" -o "$dir" --format openfoam -q
  cat >"$dir/system/controlDict" <<EOT
FoamFile { version 2.0; format ascii; class dictionary; object controlDict; }
application checkMesh; startFrom startTime; startTime 0; stopAt endTime; endTime 1; deltaT 1;
writeControl timeStep; writeInterval 1;
EOT
  cat >"$dir/system/fvSchemes" <<EOT
FoamFile { version 2.0; format ascii; class dictionary; object fvSchemes; }
ddtSchemes { default Euler; } gradSchemes { default Gauss linear; } divSchemes { default none; }
laplacianSchemes { default Gauss linear corrected; } interpolationSchemes { default linear; }
snGradSchemes { default corrected; }
EOT
  cat >"$dir/system/fvSolution" <<EOT
FoamFile { version 2.0; format ascii; class dictionary; object fvSolution; }
solvers {}
EOT
  checkMesh -case "$dir" >"$dir/checkMesh.log" 2>&1 || true
  cells=$(grep -m1 "cells:" "$dir/checkMesh.log" | awk '{print $2}')
  verdict=$(grep -E "^Mesh OK\.|Failed [0-9]+ mesh checks" "$dir/checkMesh.log" || echo "no verdict: see $dir/checkMesh.log")
  printf "%-7s %9s cells  %s\n" "$kind" "${cells:-?}" "$verdict"
done
