#!/usr/bin/env bash
# Steady solves at a stated Reynolds number on real vessels (issue 29's acceptance): each open
# vessel of ../shared/data/vessels remeshed (uniform, TRIANGLES), its volume built (`volume`
# defaults: 4 layers), a parabolic inflow at its largest end at Reynolds number RE by that end's
# diameter (blood: 1060 kg/m3, 0.0035 Pa s), zero traction at the other ends, solved steady by
# Newton's method (`steady_method = "newton"`) to a change of 1e-8. One process.
#   bench/steady_vessels.sh [BUILD] [OUT] [RE=300] [TRIANGLES=20000] [VESSELS=...]
# VESSELS may name `aneurysm`: a bifurcation aneurysm made by `vesselmesh synth bifurcation
# --aneurysm-radius` (parent 1.5 mm, daughters 1.1 and 1.0 mm at 55 degrees, a 2.5 mm dome at the
# apex, where the parent's jet hits: the case the issue's real aneurysm stalled Picard on); it
# runs without the shared data too.
# Printed per vessel: unknowns, the inflow (mL/s), the nonlinear iterations, the steady residual
# (||A(u) u - b|| / ||b||), linear iterations, seconds, and whether it settled.
set -euo pipefail
build=${1:-build}
out=${2:-$(mktemp -d)}
re=${3:-300}
triangles=${4:-20000}
here=$(cd "$(dirname "$0")" && pwd)
data="$here/../../shared/data/vessels"
vessels=${5:-"aneurysm gmsh_carotid_bifurcation_open_m.stl gmsh_aortic_arch_open_cm.stl vmtk_aorta_iliac_bifurcation_open_mm.stl"}
vm="$build/vesselmesh"
[[ -x $vm ]] || { echo "build first: $vm is needed" >&2; exit 2; }
[[ -d $data ]] || { echo "the shared vessels ($data) are not here: the synthetic aneurysm only" >&2; vessels=aneurysm; }
mkdir -p "$out"
out=$(cd "$out" && pwd)
vm=$(cd "$(dirname "$vm")" && pwd)/vesselmesh
echo "vesselmesh $("$vm" --version 2>/dev/null | head -1), $(nproc) cores; Re $re, $triangles triangles; results in $out"
printf "%-44s %9s %8s %6s %11s %8s %8s %s\n" vessel unknowns mL/s iters residual linear seconds status
for v in $vessels; do
  name=${v%.stl}
  unit=${name##*_}
  dir="$out/$name"
  mkdir -p "$dir"
  source_file="$data/$v"
  if [[ $v == aneurysm ]]; then
    unit=mm source_file="$dir/aneurysm.stl"
    [[ -f $source_file ]] || "$vm" synth bifurcation --radius 1.5 --daughter-radii 1.1,1.0 --angles 55,55 \
      --parent-length 12 --daughter-length 12 --blend 0.8 --aneurysm-radius 2.5 --resolution 0.2 -o "$source_file" -q
  fi
  [[ -f $dir/volume.msh ]] || {
    "$vm" remesh "$source_file" --units "$unit" -o "$dir/surface.vtp" --size uniform --target-triangles "$triangles" -q
    "$vm" volume "$dir/surface.vtp" -o "$dir/volume.msh" -q
  }
  # The ends as `volume` tags them: inlet the largest, outlet_1, ... the others in `info`'s order
  # (the remeshed surface and its volume in mm, whatever the file's unit).
  "$vm" info "$dir/surface.vtp" --json -q >"$dir/info.json"
  python3 - "$dir" "$re" <<'PY'
import json, math, sys
d, re = sys.argv[1], float(sys.argv[2])
info = json.load(open(f"{d}/info.json"))
ends = info["open_ends"]
scale = 1e-3  # mm to m
inlet = max(ends, key=lambda e: e["area"])
diameter = 2.0 * inlet["radius"] * scale
rho, mu = 1060.0, 0.0035
flow_ml = re * mu * math.pi * diameter / (4.0 * rho) * 1e6
lines = [f'mesh = "volume.msh"', 'length_unit = "mm"', "[fluid]", f"density = {rho}", f"viscosity = {mu}",
         "[time]", "steady = true", 'steady_method = "newton"', "steady_tolerance = 1e-8",
         "steady_iterations = 60", "[[boundary]]", 'tag = "inlet"', 'type = "velocity"',
         'profile = "parabolic"', f"flow = {flow_ml:.6g}"]
for k in range(1, len(ends)):
    lines += ["[[boundary]]", f'tag = "outlet_{k}"', 'type = "traction"']
lines += ["[[boundary]]", 'tag = "wall"', 'type = "wall"']
open(f"{d}/case.toml", "w").write("\n".join(lines) + "\n")
open(f"{d}/flow_ml", "w").write(f"{flow_ml:.4g}")
PY
  status=settled
  "$vm" simulate "$dir/case.toml" -o "$dir/result" 2>"$dir/log" >/dev/null || status="failed (exit $?, see $dir/log)"
  python3 - "$dir" "$name" "$status" <<'PY'
import json, os, sys
d, name, status = sys.argv[1:]
s = json.load(open(f"{d}/result/summary.json")) if os.path.exists(f"{d}/result/summary.json") else {}
print(f"{name:44s} {s.get('dofs', 0):9d} {open(f'{d}/flow_ml').read():>8s} {s.get('steps', 0):6d} "
      f"{s.get('steady_residual', float('nan')):11.3e} {s.get('linear_iterations', 0):8d} "
      f"{s.get('seconds', float('nan')):8.1f} {status}")
PY
done
