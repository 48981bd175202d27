// A flow case run end to end: read the case and its mesh, solve (steady, or step by step in
// time), and write ParaView-ready results.
//
// Output folder:
//   fluid.pvd + fluid_NNNNNN.vtu   the volume per saved step: point data velocity (m/s), pressure (Pa)
//   wall.pvd  + wall_NNNNNN.vtp    the wall per saved step: point data wss (Pa, vector),
//                                  wss_magnitude (Pa); cell data tag
//   indices.vtp                    unsteady runs: tawss (Pa), osi, rrt (1/Pa), twssg (Pa/s) per
//                                  wall point over the last period (the whole run without one),
//                                  from every time step (post/indices.h)
//   log.csv                        per step: time, flux (m3/s, out of the domain) and mean
//                                  pressure (Pa) per boundary, linear iterations, CFL, seconds
//   ends/TAG.csv                   per step and end (every boundary but the wall): flux (m3/s and
//                                  mL/s, out of the domain), mean pressure (Pa and mmHg), and an rcr
//                                  end's capacitor pressure; formatted by end_logs from log.csv's rows
//   summary.json                   sizes, steps, times, the SI scale applied, units, status, how the
//                                  points are shared among the processes (partition: owned unknowns,
//                                  ghost points, neighbours per process) and each one's peak memory
//   checkpoint.bin                 unsteady runs: the state to go on from (flow/checkpoint.h), every
//                                  [output] checkpoint_every steps, at the last step, and when
//                                  SIGTERM or SIGINT stops the run (after the step under way: the
//                                  run then ends with status "stopped"); `restart` goes on from it
// Points stay in the mesh's unit (named in summary.json and in the PVD files); the fields are
// SI. Every file is written whole (atomically); the PVD collections, log and summary are
// rewritten at each save, so a run that stops early leaves a consistent folder behind.
// Under `mpirun -np K` each process reads the mesh, assembles the rows of its share of the
// points (consecutive ranges of the solver's numbering) and holds the whole solution; the first
// process writes.
#pragma once

#include "flow/case.h"
#include "flow/navier_stokes.h"
#include "mesh/reporter.h"

#include <map>
#include <string>
#include <vector>

namespace vesselmesh::flow {

struct SimulationSummary {
  std::string status;  // "completed", "diverged" or "stopped" (by `signal`, a checkpoint written)
  int signal = 0;
  int points = 0, tetrahedra = 0, dofs = 0, ranks = 1;
  int steps = 0, saved = 0, linear_iterations = 0;
  double seconds = 0.0, seconds_per_step = 0.0, setup_seconds = 0.0;
  // The run's parts, named (issue 49): setup_seconds is reading, distributing and setting up; the
  // initial state (the Stokes start; 0 from rest or a checkpoint); this run's first step (its
  // preconditioner built); the mean of its other steps ("settled", as bench/flow_scaling.sh times
  // them; seconds_per_step above averages every step of the run).
  double initial_seconds = 0.0, first_step_seconds = 0.0, settled_step_seconds = 0.0;
  int settled_steps = 0;
  // Seconds a step per million unknowns from a step's seconds (0 without unknowns).
  double per_million_dofs(double step_seconds) const { return dofs > 0 ? step_seconds / (dofs * 1e-6) : 0.0; }
  double length_scale = 1e-3;
  double indices_start = 0.0, indices_end = 0.0;  // s; the indices' window (equal: none written)
  std::string solver;
  PartitionReport partition;          // how the points are shared among the processes
  std::vector<double> peak_memory_mb;  // per process: its peak resident memory
  // per process: its resident pages of mapped files at the end (the shared libraries, shared by the
  // processes of a node); the peak less it is the process's own memory
  std::vector<double> library_memory_mb;
  std::vector<double> own_memory_mb;  // per process: peak_memory_mb less library_memory_mb
  double distribution_memory_mb = 0.0;  // the first process's peak once it had read, split and sent the mesh
  std::string indices_file;  // indices.vtp, or indices.pvtp under MPI
  // The time statistics ([output] statistics_from): statistics.vtu (.pvtu), their span (s), their steps.
  std::string statistics_file;
  double statistics_start = 0.0, statistics_end = 0.0;
  int statistics_steps = 0;
  double steady_residual = -1.0;  // a steady case's relative residual at its answer (StepReport::residual)
  // s: the steps' lengths, least and largest (this run's; equal to the case's dt but where it aims
  // at a CFL number, FlowCase::cfl_target), and the simulated time this run covered.
  double least_time_step = 0.0, largest_time_step = 0.0, simulated_seconds = 0.0;
  std::vector<BoundaryFlow> ends;      // per boundary at the end: flux, mean pressure (rcr: capacitor too)
};

// `extra_petsc_options` are applied after the case's. `restart`: go on from the output folder's
// checkpoint (the same mesh and dt; the case's end may be later: the run is extended), as if
// the run had not stopped (the same results to the linear solver's tolerance). Throws InputError
// for a bad case or mesh or checkpoint (before any solve), ComputationError when the solve
// diverges (after writing what it has).
SimulationSummary simulate(const FlowCase& flow_case, const std::string& output_dir,
                           const std::string& extra_petsc_options = "", const Reporter& reporter = silent_reporter(),
                           bool restart = false);

// Per end tag, its CSV (ends/TAG.csv) from the run's log.csv text: step, time_s, flux_m3_s,
// flux_mL_s, mean_pressure_Pa, mean_pressure_mmHg, and for an rcr end capacitor_pressure_Pa and
// _mmHg. InternalError when the log lacks a tag's columns.
std::map<std::string, std::string> end_logs(const std::string& log, const std::vector<std::string>& tags);

}  // namespace vesselmesh::flow
