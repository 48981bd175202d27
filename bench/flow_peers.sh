#!/usr/bin/env bash
# The flow solver against its peers on one pipe with a boundary layer (issue 8's benchmark):
# vesselmesh simulate, OpenFOAM's pimpleFoam (Debian's `openfoam`) and, when its binary is given,
# svMultiPhysics (svFSIplus before its rename), on the same mesh, with the same time step, steps
# and cores.
#   bench/flow_peers.sh [BUILD] [OUT] [RESOLUTION_MM=0.25] [STEPS=30]
#   SVFSI=/path/to/svmultiphysics bench/flow_peers.sh ...   (svFSIplus in older versions; built
#     outside the project; optional)
#   NP=2 (default): the processes of the parallel runs (0: none)
# The pipe: radius 2 mm, length 20 mm (vesselmesh synth cylinder), `vesselmesh volume` with 4
# layers (total 0.1 R); steady inflow 1 mL/s (Re 96), dt 1 ms, every solver started from the
# developed flow (ours: the Stokes flow, [time] initial = "stokes"; the peers: the Poiseuille
# field written into their initial conditions), so the wall shear stress after STEPS steps is
# compared with Poiseuille's 4 mu Q / (pi R^3) on the middle half of the pipe. R is the radius of
# the meshed pipe's cross-section (from its volume: the polygonal pipe is a little narrower).
# Meshes: ours and svMultiPhysics take the tetrahedra (each prism cut in three; its mesh-complete/
# from `vesselmesh export --format svfsi --units m`); pimpleFoam runs (its constant/polyMesh from
# `vesselmesh export --format openfoam`) on the layer's prisms (the same points; its WSS on pure
# tetrahedra is far worse) and, for the same-mesh figure, on the tetrahedra too.
# Printed: DOFs (4 per node for the FE codes, 4 per cell for FV), seconds per step (the first
# step, which holds the setup, left out), seconds per step per million DOFs, linear iterations,
# peak memory, WSS error.
set -euo pipefail
build=${1:-build}
out=${2:-$(mktemp -d)}
resolution=${3:-0.25}
steps=${4:-30}
np=${NP:-2}
vm="$build/vesselmesh"
tool="$build/bench/bench_flow_peers"
[[ -x $vm && -x $tool ]] || { echo "build first: $vm and $tool are needed" >&2; exit 2; }
mkdir -p "$out"
out=$(cd "$out" && pwd)
vm=$(cd "$(dirname "$vm")" && pwd)/vesselmesh
tool=$(cd "$(dirname "$tool")" && pwd)/bench_flow_peers
radius=2 length=20 flow_ml=1 density=1060 viscosity=0.0035 dt=0.001  # as bench/pipe_case.sh
# shellcheck source=bench/pipe_case.sh
source "$(dirname "$0")/pipe_case.sh"
end=$(python3 -c "print($steps * $dt)")
z0=$(python3 -c "print($length / 4)") z1=$(python3 -c "print(3 * $length / 4)")
export WM_PROJECT_DIR=${WM_PROJECT_DIR:-/usr/share/openfoam}

timed() {  # timed LOG CMD...: runs CMD, its output to LOG, the peak memory (MB) to LOG.mem
  local log=$1 status=0
  shift
  if [[ -x /usr/bin/time ]]; then
    /usr/bin/time -f "%M" -o "$log.mem" "$@" >"$log" 2>&1 || status=$?
    echo "$(($(tail -1 "$log.mem") / 1024))" >"$log.mem"
  else
    "$@" >"$log" 2>&1 || status=$?
    echo "?" >"$log.mem"
  fi
  return $status
}
value() { awk -v k="$1" '$1 == k { print $2 }' "$2"; }
mpi=(mpirun --allow-run-as-root --oversubscribe -np)

echo "== mesh (in $out)"
"$vm" synth cylinder --radius $radius --length $length --resolution "$resolution" -o "$out/pipe.stl" -q
"$vm" volume "$out/pipe.stl" -o "$out/pipe.msh" -q
"$vm" volume "$out/pipe.stl" -o "$out/pipe.vtu" -q
"$vm" volume "$out/pipe.stl" -o "$out/pipe_prisms.msh" --keep-prisms -q
volume_mm3=$("$vm" info "$out/pipe.msh" --json -q | python3 -c "import json,sys; print(json.load(sys.stdin)['volume'])")
read -r radius_eff exact < <(python3 -c "
import math
r = math.sqrt($volume_mm3 / (math.pi * $length))
print(r, 4 * $viscosity * $flow_ml * 1e-6 / (math.pi * (r * 1e-3) ** 3))")
export WSS_EXACT=$exact
echo "pipe R $radius mm (meshed cross-section: R = $radius_eff mm), L $length mm; Poiseuille WSS $exact Pa"

echo "== vesselmesh simulate"
write_pipe_case "$out/case.toml" "$dt" "$end" "$steps"
ours() {  # ours NAME NP
  local dir="$out/$1"
  if [[ $2 == 1 ]]; then
    timed "$dir.log" "$vm" simulate "$out/case.toml" -o "$dir" -q
  else
    timed "$dir.log" "${mpi[@]}" "$2" "$vm" simulate "$out/case.toml" -o "$dir" -q
  fi
  python3 - "$dir" <<'PY'
import csv, json, sys
d = sys.argv[1]
s = json.load(open(f"{d}/summary.json"))
rows = list(csv.DictReader(open(f"{d}/log.csv")))[1:]
t = sum(float(r["seconds"]) for r in rows) / len(rows)
its = sum(int(r["linear_iterations"]) for r in rows) / len(rows)
print(f"dofs {s['dofs']}\nseconds_per_step {t:.6g}\nlinear_iterations_per_step {its:.4g}\nsolver {s['solver'].replace(' ', '')}")
PY
}
ours ours_np1 1 >"$out/ours_np1.txt"
"$tool" vesselmesh-wss "$out/ours_np1" "$z0" "$z1" >>"$out/ours_np1.txt"
[[ $np -gt 1 ]] && ours ours_np$np "$np" >"$out/ours_np$np.txt"

echo "== OpenFOAM pimpleFoam"
openfoam_case() {  # openfoam_case DIR MESH.msh
  local dir=$1
  rm -rf "$dir"
  mkdir -p "$dir/system" "$dir/constant" "$dir/0"
  cat >"$dir/system/controlDict" <<EOF
FoamFile { version 2.0; format ascii; class dictionary; object controlDict; }
application pimpleFoam;
startFrom startTime; startTime 0; stopAt endTime; endTime $end; deltaT $dt;
writeControl timeStep; writeInterval $steps; writeFormat ascii; writePrecision 10;
timeFormat general; timePrecision 6; runTimeModifiable false;
functions
{
    wallShearStress { type wallShearStress; libs ("libfieldFunctionObjects.so"); patches (wall);
                      writeControl writeTime; log false; }
}
EOF
  # Second order in time (backward = BDF2, as ours) and space; PISO-like PIMPLE with one
  # non-orthogonal correction (tetrahedra); GAMG for the pressure.
  cat >"$dir/system/fvSchemes" <<'EOF'
FoamFile { version 2.0; format ascii; class dictionary; object fvSchemes; }
ddtSchemes { default backward; }
gradSchemes { default Gauss linear; }
divSchemes { default none; div(phi,U) Gauss linear; div((nuEff*dev2(T(grad(U))))) Gauss linear; }
laplacianSchemes { default Gauss linear corrected; }
interpolationSchemes { default linear; }
snGradSchemes { default corrected; }
EOF
  cat >"$dir/system/fvSolution" <<'EOF'
FoamFile { version 2.0; format ascii; class dictionary; object fvSolution; }
solvers
{
    p { solver GAMG; smoother DIC; tolerance 1e-6; relTol 0.01; }
    pFinal { $p; relTol 0; }
    U { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-6; relTol 0; }
    UFinal { $U; }
}
PIMPLE { momentumPredictor yes; nOuterCorrectors 1; nCorrectors 2; nNonOrthogonalCorrectors 1;
         pRefCell 0; pRefValue 0; }
EOF
  cat >"$dir/system/decomposeParDict" <<EOF
FoamFile { version 2.0; format ascii; class dictionary; object decomposeParDict; }
numberOfSubdomains $np;
method simple;  // slabs along the pipe (Debian's OpenFOAM has no scotch decomposition)
simpleCoeffs { n (1 1 $np); delta 0.001; }
EOF
  cat >"$dir/constant/transportProperties" <<EOF
FoamFile { version 2.0; format ascii; class dictionary; object transportProperties; }
transportModel Newtonian;
nu $(python3 -c "print($viscosity / $density)");
EOF
  cat >"$dir/constant/turbulenceProperties" <<'EOF'
FoamFile { version 2.0; format ascii; class dictionary; object turbulenceProperties; }
simulationType laminar;
EOF
  # The mesh from our own export (constant/polyMesh in metres, the wall patch of type wall).
  "$vm" export "$2" -o "$dir" --format openfoam -q
  (cd "$dir" && postProcess -case . -func writeCellCentres -time 0 >prepare.log 2>&1)
  "$tool" openfoam-fields "$dir" "$(python3 -c "print($radius * 1e-3)")" "$(python3 -c "print($flow_ml * 1e-6)")" >/dev/null
}
openfoam_run() {  # openfoam_run DIR NAME NP -> DIR/NAME.txt
  local dir=$1
  local status=0
  if [[ $3 == 1 ]]; then
    timed "$dir/$2.log" pimpleFoam -case "$dir" || status=$?
  else
    decomposePar -case "$dir" -force >"$dir/decompose.log" 2>&1
    timed "$dir/$2.log" "${mpi[@]}" "$3" pimpleFoam -case "$dir" -parallel || status=$?
  fi
  "$tool" openfoam-steps "$dir/$2.log" >"$dir/$2.txt"
  echo "cells $(grep -o 'nCells:[0-9]*' "$dir/constant/polyMesh/owner" | cut -d: -f2)" >>"$dir/$2.txt"
  if [[ $status != 0 ]]; then
    echo "pimpleFoam failed (exit $status) after $(value steps "$dir/$2.txt") steps: see $dir/$2.log" >&2
    echo "failed_after_steps $(value steps "$dir/$2.txt")" >>"$dir/$2.txt"
    return 1
  fi
}
openfoam_meshes="prisms tets"
if ! command -v pimpleFoam >/dev/null; then
  echo "pimpleFoam not found (apt-get install openfoam): no OpenFOAM figures" >&2
  openfoam_meshes=""
fi
for mesh in $openfoam_meshes; do
  dir="$out/openfoam_$mesh"
  [[ $mesh == prisms ]] && openfoam_case "$dir" "$out/pipe_prisms.msh" || openfoam_case "$dir" "$out/pipe.msh"
  openfoam_run "$dir" np1 1 || continue
  "$tool" openfoam-wss "$dir" "$end" "$density" "$(python3 -c "print($z0 * 1e-3)")" \
    "$(python3 -c "print($z1 * 1e-3)")" >>"$dir/np1.txt"
  [[ $np -gt 1 ]] && { openfoam_run "$dir" np$np "$np" || true; }
done

if [[ -n ${SVFSI:-} ]]; then
  echo "== svMultiPhysics ($SVFSI)"
  dir="$out/svfsi"
  rm -rf "$dir"
  # The mesh from our own export (mesh-complete/ in metres, a face per boundary tag: inlet,
  # outlet_1, wall); its solver.xml skeleton replaced below by the benchmark's own settings.
  "$vm" export "$out/pipe.vtu" -o "$dir" --format svfsi --units m -q
  "$tool" svfsi-initial "$dir/mesh-complete/mesh-complete.mesh.vtu" "$dir/initial.vtu" \
    "$(python3 -c "print($radius * 1e-3)")" "$(python3 -c "print($flow_ml * 1e-6)")" >"$dir/mesh.txt"
  faces=""
  for face in "$dir"/mesh-complete/mesh-surfaces/*.vtp; do
    name=$(basename "$face" .vtp)
    faces+="  <Add_face name=\"$name\"> <Face_file_path> mesh-complete/mesh-surfaces/$name.vtp </Face_file_path> </Add_face>
"
  done
  # Its own pipe test's settings (tests/cases/fluid/pipe_RCR_3d: 3 to 5 Newton iterations a
  # step, fsils' GMRES with its NS preconditioner), the Newton tolerance 1e-4; generalized-alpha
  # in time, started from the Poiseuille flow.
  cat >"$dir/solver.xml" <<EOF
<?xml version="1.0" encoding="UTF-8" ?>
<svMultiPhysicsFile version="0.1">
<GeneralSimulationParameters>
  <Continue_previous_simulation> false </Continue_previous_simulation>
  <Number_of_spatial_dimensions> 3 </Number_of_spatial_dimensions>
  <Number_of_time_steps> $steps </Number_of_time_steps>
  <Time_step_size> $dt </Time_step_size>
  <Spectral_radius_of_infinite_time_step> 0.5 </Spectral_radius_of_infinite_time_step>
  <Save_results_to_VTK_format> true </Save_results_to_VTK_format>
  <Name_prefix_of_saved_VTK_files> result </Name_prefix_of_saved_VTK_files>
  <Increment_in_saving_VTK_files> $steps </Increment_in_saving_VTK_files>
  <Start_saving_after_time_step> 1 </Start_saving_after_time_step>
  <Increment_in_saving_restart_files> 100000 </Increment_in_saving_restart_files>
  <Verbose> true </Verbose>
  <Warning> true </Warning>
  <Debug> false </Debug>
</GeneralSimulationParameters>
<Add_mesh name="fluid">
  <Mesh_file_path> mesh-complete/mesh-complete.mesh.vtu </Mesh_file_path>
$faces  <Initial_velocities_file_path> initial.vtu </Initial_velocities_file_path>
</Add_mesh>
<Add_equation type="fluid">
  <Coupled> true </Coupled>
  <Min_iterations> 3 </Min_iterations>
  <Max_iterations> 5 </Max_iterations>
  <Tolerance> 1e-4 </Tolerance>
  <Backflow_stabilization_coefficient> 0.2 </Backflow_stabilization_coefficient>
  <Density> $density </Density>
  <Viscosity model="Constant"> <Value> $viscosity </Value> </Viscosity>
  <Output type="Spatial"> <Velocity> true </Velocity> <Pressure> true </Pressure> <WSS> true </WSS> </Output>
  <LS type="NS">
    <Linear_algebra type="fsils"> <Preconditioner> fsils </Preconditioner> </Linear_algebra>
    <Max_iterations> 15 </Max_iterations>
    <NS_GM_max_iterations> 10 </NS_GM_max_iterations>
    <NS_CG_max_iterations> 300 </NS_CG_max_iterations>
    <Tolerance> 1e-3 </Tolerance>
    <NS_GM_tolerance> 1e-3 </NS_GM_tolerance>
    <NS_CG_tolerance> 1e-3 </NS_CG_tolerance>
    <Absolute_tolerance> 1e-17 </Absolute_tolerance>
    <Krylov_space_dimension> 250 </Krylov_space_dimension>
  </LS>
  <Add_BC name="inlet">
    <Type> Dir </Type> <Time_dependence> Steady </Time_dependence>
    <Value> $(python3 -c "print(-$flow_ml * 1e-6)") </Value> <Profile> Parabolic </Profile> <Impose_flux> true </Impose_flux>
  </Add_BC>
  <Add_BC name="outlet_1">
    <Type> Neu </Type> <Time_dependence> Steady </Time_dependence> <Value> 0.0 </Value>
  </Add_BC>
  <Add_BC name="wall">
    <Type> Dir </Type> <Time_dependence> Steady </Time_dependence> <Value> 0.0 </Value>
  </Add_BC>
</Add_equation>
</svMultiPhysicsFile>
EOF
  svfsi_run() {  # svfsi_run NAME NP -> DIR/NAME.txt
    rm -rf "$dir/$2-procs"
    (cd "$dir" && timed "$dir/$1.log" "${mpi[@]}" "$2" "$SVFSI" solver.xml)
    "$tool" svfsi-steps "$dir/$1.log" >"$dir/$1.txt"
    echo "dofs $((4 * $(value nodes "$dir/mesh.txt")))" >>"$dir/$1.txt"
  }
  svfsi_run np1 1
  result=$(ls "$dir"/1-procs/result_*.vtu | tail -1)
  "$tool" svfsi-wss "$result" "$dir/mesh-complete/mesh-surfaces/wall.vtp" "$(python3 -c "print($z0 * 1e-3)")" "$(python3 -c "print($z1 * 1e-3)")" >>"$dir/np1.txt"
  [[ $np -gt 1 ]] && svfsi_run np$np "$np"
fi

echo
echo "== results: pipe R $radius mm, $steps steps of $dt s, Poiseuille WSS $exact Pa"
python3 - "$out" "$np" <<'PY'
import os, sys
out, np = sys.argv[1], int(sys.argv[2])
exact = float(os.environ["WSS_EXACT"])

def read(path):
    if not os.path.exists(path):
        return None
    return dict(line.split(None, 1) for line in open(path).read().split("\n") if line.strip())

# name, folder prefix, the count that gives the DOFs, DOFs per count
solvers = [("vesselmesh (tets)", f"{out}/ours_np", "dofs", 1),
           ("pimpleFoam (prism layer)", f"{out}/openfoam_prisms/np", "cells", 4),
           ("pimpleFoam (same tets)", f"{out}/openfoam_tets/np", "cells", 4),
           ("svMultiPhysics (same tets)", f"{out}/svfsi/np", "dofs", 1)]
print(f"{'solver':26} {'DOFs':>8} {'s/step':>8} {'s/step/MDOF':>11} {'its/step':>8} {'MB':>6} {'WSS Pa':>8} "
      f"{'error':>7} {'rms err':>7} {f'np {np} s/step':>11} {'speedup':>7}")
ours = read(f"{out}/ours_np1.txt")
for name, prefix, count, per in solvers:
    a = read(prefix + "1.txt")
    if a is None:
        continue
    dofs = int(a[count]) * per
    t = float(a["seconds_per_step"])
    its = a.get("linear_iterations_per_step", a.get("pressure_iterations_per_step", "?"))
    mem = open(prefix + "1.log.mem").read().strip() if os.path.exists(prefix + "1.log.mem") else "?"
    if "failed_after_steps" in a:
        wss = f"{'diverged after ' + a['failed_after_steps'] + ' steps':>24}"
    else:
        m = float(a["mean_pa"])
        wss = f"{m:8.4f} {(m - exact) / exact * 100:+6.2f}% {float(a['rms_error_pa']) / exact * 100:6.2f}%"
    b = read(prefix + f"{np}.txt") if np > 1 else None
    par = f"{float(b['seconds_per_step']):11.4g} {t / float(b['seconds_per_step']):7.2f}" \
        if b and "failed_after_steps" not in b else f"{'-':>11} {'-':>7}"
    print(f"{name:26} {dofs:8d} {t:8.4g} {t / dofs * 1e6:11.4g} {its:>8} {mem:>6} {wss} {par}")
    if name != solvers[0][0] and ours is not None:
        print(f"{'':26} its time per step over vesselmesh's: {t / float(ours['seconds_per_step']):.2f}")
PY
echo "(files in $out)"
