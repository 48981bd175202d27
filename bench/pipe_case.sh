# Sourced by the flow benchmarks: the pipe's flow case (blood, 1 mL/s parabolic inflow at the
# end tagged inlet, zero traction at outlet_1, from the Stokes flow), its mesh pipe.msh beside it.
#   write_pipe_case FILE DT END SAVE_EVERY [PETSC_OPTIONS]
#   THREADS=N: the assembly's threads ([solver] threads; default 0, automatic).
write_pipe_case() {
  cat >"$1" <<EOT
mesh = "pipe.msh"
length_unit = "mm"
[fluid]
density = 1060.0
viscosity = 0.0035
[time]
dt = $2
end = $3
save_every = $4
initial = "stokes"
[[boundary]]
tag = "inlet"
type = "velocity"
profile = "parabolic"
flow = 1.0
[[boundary]]
tag = "outlet_1"
type = "traction"
[[boundary]]
tag = "wall"
type = "wall"
[solver]
petsc_options = "${5:-}"
threads = ${THREADS:-0}
EOT
}
