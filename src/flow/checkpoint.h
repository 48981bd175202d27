// A run's checkpoint: what `vesselmesh simulate --restart` needs to go on from a step as if the
// run had not stopped. Binary (native doubles, little-endian machines), written atomically
// (io/atomic_file.h: a checkpoint is whole or absent), checked on reading (a truncated or
// foreign file, or one of another mesh or time step, is an InputError naming it).
// Fields are in the mesh's numbering, so the file does not depend on how the solver numbers
// or shares the points. The flow's fields are in pieces beside it, one per process (its own
// points, by mesh number: nothing gathered on one process), written before it and named by its
// step (checkpoint_piece_path), so that a run stopped while writing them keeps the checkpoint
// before.
#pragma once

#include "flow/navier_stokes.h"
#include "flow/statistics.h"
#include "post/indices.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace vesselmesh::flow {

struct Checkpoint {
  uint64_t fingerprint = 0;  // of the mesh and the time step (run_fingerprint)
  FlowState flow;  // its time, steps and capacitor pressures; its fields whole only when pieces is 0
  int pieces = 0;  // the flow's fields are in this many piece files
  int saved = 0, linear_iterations = 0;
  std::string log;  // log.csv so far
  std::vector<std::pair<double, std::string>> fluid_files, wall_files;  // the PVD collections so far
  // The hemodynamic indices' running sums per wall point, and per entry that point's number in
  // the mesh (sorted), whatever process computed it.
  post::WssIndexAccumulator::State indices;
  std::vector<int> index_points;
  // The flow's time statistics ([output] statistics_from): their span, weight and steps here, their
  // fields by point in the pieces.
  FlowStatistics::State statistics;
};

// The run a checkpoint belongs to: its mesh's points, cells and boundary, and the time step.
uint64_t run_fingerprint(const TetMesh& mesh, double dt);

void write_checkpoint(const std::string& path, const Checkpoint& checkpoint);
Checkpoint read_checkpoint(const std::string& path);

// Piece `piece` of the flow's fields of the checkpoint `path` at step `steps`.
std::string checkpoint_piece_path(const std::string& path, int steps, int piece);
// A process's own points' state (FlowState::points set) and their time statistics' fields (in
// the same order; none when the run keeps none), atomically.
void write_checkpoint_piece(const std::string& path, const FlowState& own,
                            const FlowStatistics::State& statistics = {});
// The checkpoint's flow at the mesh points `wanted` (sorted; a process's local points), from its
// pieces, `points` set (read one piece at a time, each process keeping what it wants), and into
// `statistics` (when given and the checkpoint has them) their time statistics at the same points in
// the same order; InputError when a piece is missing or of another step, holds a point outside the
// mesh of `mesh_points`, or a wanted point is in none.
FlowState read_checkpoint_pieces(const std::string& path, const Checkpoint& checkpoint,
                                 const std::vector<int>& wanted, int mesh_points,
                                 FlowStatistics::State* statistics = nullptr);

}  // namespace vesselmesh::flow
