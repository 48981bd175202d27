#!/usr/bin/env bash
# Volume meshing: the issue's 1-million-tetrahedron goal (layer + interior, under 15 s on 2
# cores) and the interior fill against TetGen (Debian's `tetgen`) on the same closed surface.
#   bench/volume.sh [BUILD] [RESOLUTION_MM] [LENGTH_MM]
# The vessel: a straight pipe of radius 3 mm (vesselmesh synth cylinder, jitter 0.1), by default
# 0.3 mm edges over 60 mm (about 1.1 M tetrahedra with 4 layers). Times: wall clock of the whole
# command (reading, centerlines, layer, caps, fill, checks, writing), the best of three.
# Interior: `vesselmesh volume --layers 0` (wall + caps filled by Gmsh Delaunay, HXT, then TetGen's
# library) against the `tetgen -pqQ` program on that same closed surface (the volume's boundary, as
# Medit .mesh).
set -euo pipefail
build=${1:-build}
resolution=${2:-0.3}
length=${3:-60}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
vm="$build/vesselmesh"
"$vm" synth cylinder --radius 3 --length "$length" --resolution "$resolution" --jitter 0.1 -o "$work/pipe.stl" -q
python3 - "$vm" "$work" <<'PY'
import json, shutil, subprocess, sys, time
vm, work = sys.argv[1:3]

def best(cmd, repeats=3):
    t, out = float("inf"), None
    for _ in range(repeats):
        start = time.perf_counter()
        out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
        t = min(t, time.perf_counter() - start)
    return t, out

pipe = f"{work}/pipe.stl"
print(f"pipe: {pipe}")
for algorithm in ["delaunay", "hxt", "tetgen"]:
    t, out = best([vm, "volume", pipe, "-o", f"{work}/full.msh", "--algorithm", algorithm, "--json", "-q"])
    j = json.loads(out)
    n = j["tetrahedra"]
    print(f"full volume ({algorithm}): {n} tetrahedra ({j['layer_cells']} layer + {j['interior_tetrahedra']} interior), "
          f"{t:.2f} s, {n / t / 1e3:.0f} k tets/s; min dihedral layer {j['dihedral_deg']['min_layer']}, "
          f"interior {j['dihedral_deg']['min_interior']}; goal: 1 M in < 15 s")

# The interior alone, against TetGen on the same closed surface.
rows = []
for algorithm in ["delaunay", "hxt", "tetgen"]:
    t, out = best([vm, "volume", pipe, "-o", f"{work}/fill_{algorithm}.msh", "--layers", "0", "--algorithm", algorithm,
                   "--json", "-q"])
    j = json.loads(out)
    engine = "TetGen library" if algorithm == "tetgen" else f"Gmsh {algorithm}"
    rows.append((f"vesselmesh/{engine}", j["tetrahedra"], t, j["dihedral_deg"]["min"]))
subprocess.run([vm, "info", f"{work}/fill_delaunay.msh", "-o", f"{work}/closed.mesh", "-q"], check=True,
               capture_output=True)
if shutil.which("tetgen"):
    t, _ = best(["tetgen", "-pqQ", f"{work}/closed.mesh"])
    with open(f"{work}/closed.1.ele") as f:
        tets = int(f.readline().split()[0])
    rows.append(("TetGen -pq", tets, t, None))
else:
    print("tetgen not found (apt-get install tetgen): no peer figures")
for name, tets, t, angle in rows:
    extra = f", min dihedral {angle}" if angle is not None else ""
    print(f"interior {name}: {tets} tetrahedra, {t:.2f} s, {tets / t / 1e3:.0f} k tets/s{extra}")
PY
