#!/usr/bin/env bash
# The exports checked by the solvers' own tools (issue 33): the benchmark pipe (radius 2 mm, length
# 20 mm, `volume`'s defaults, with its prisms cut and kept) exported to OpenFOAM's polyMesh and run
# through OpenFOAM's checkMesh (Debian's `openfoam`; skipped with a message where it is absent);
# and exported to Fluent's .msh, read by OpenFOAM's own Fluent reader (fluent3DMeshToFoam, which
# takes each face's orientation and cells from the file) and checked the same way.
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
  check() {  # $1 the case folder, $2 the row's name
    checkMesh -case "$1" >"$1/checkMesh.log" 2>&1 || true
    cells=$(grep -m1 "cells:" "$1/checkMesh.log" | awk '{print $2}')
    verdict=$(grep -E "^Mesh OK\.|Failed [0-9]+ mesh checks" "$1/checkMesh.log" || echo "no verdict: see $1/checkMesh.log")
    patches=$(awk '/^Checking patch topology/,/^Checking faceZone/' "$1/checkMesh.log" | awk 'NF >= 4 && $1 != "Patch" && $1 != "Checking" {printf "%s ", $1}')
    printf "%-16s %9s cells  %s  patches: %s\n" "$2" "${cells:-?}" "$verdict" "$patches"
  }
  check "$dir" "$kind openfoam"
  if command -v fluent3DMeshToFoam >/dev/null; then
    fluent="$dir/fluent"
    mkdir -p "$fluent"
    cp -r "$dir/system" "$fluent/"
    "$vm" export "$dir/pipe.msh" -o "$fluent/pipe_fluent.msh" --format fluent -q
    fluent3DMeshToFoam -case "$fluent" "$fluent/pipe_fluent.msh" >"$fluent/convert.log" 2>&1 || true
    check "$fluent" "$kind fluent"
  fi
done
