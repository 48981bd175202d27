# Sourced by the FDA nozzle benchmarks: the nozzle (sudden expansion, inlet pipe 30 mm: the first
# pressure tap is at z = -90.32 mm, the inlet at -92.685 mm; outlet pipe 100 mm: the last velocity
# station at +80 mm), its surface sized by the distance to the axis, TetGen inside, and its flow case
# (fluid of the FDA's data files; flow rate theirs at Re_throat = 500 unless given).
#   nozzle_mesh VM DIR POINTS_PER_CIRCLE HMAX_MM [VOLUME_OPTIONS...]  -> DIR/volume.msh
#   write_nozzle_case FILE TIME_SECTION [FLOW_ML_S] [INLET_KEYS]  (the mesh: volume.msh beside FILE;
#   INLET_KEYS: more lines for the inlet's [[boundary]], e.g. "perturbation = 0.04")
nozzle_mesh() {
  local vm=$1 dir=$2 ppc=$3 hmax=$4
  shift 4
  "$vm" synth nozzle --inlet-length 30 --outlet-length 100 --resolution 0.3 -o "$dir/nozzle.vtp" -q
  "$vm" size "$dir/nozzle.vtp" -o "$dir/size.vtp" --size distance --points-per-circle "$ppc" --hmax "$hmax" -q
  "$vm" remesh "$dir/nozzle.vtp" --metric "$dir/size.vtp" -o "$dir/surface.vtp" -q
  "$vm" volume "$dir/surface.vtp" -o "$dir/volume.msh" --end inlet:0,0,-92.685 --end outlet:0,0,100 \
    --algorithm tetgen "$@"
}

write_nozzle_case() {
  cat >"$1" <<TOML
# FDA nozzle, sudden expansion (fluid and flow rate of the FDA's data files)
mesh = "volume.msh"
length_unit = "mm"
[fluid]
density = 1056.0
viscosity = 0.0035
$2
[[boundary]]
tag = "inlet"
type = "velocity"
profile = "parabolic"
flow = ${3:-5.20624}               # mL/s
${4:-}
[[boundary]]
tag = "outlet"
type = "traction"
[[boundary]]
tag = "wall"
type = "wall"
TOML
}
