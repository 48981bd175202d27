// The pieces of a flow's results that a process computes and writes (flow/simulate.cpp): the
// wall, whose shear stress it takes, and the fluid volume. On one process the whole mesh's; under
// MPI each process's own part, joined by the .pvtu / .pvtp files the first writes.
#pragma once

#include "flow/case.h"
#include "flow/mesh_part.h"
#include "mesh/tetmesh.h"
#include "mesh/trimesh.h"
#include "post/wss.h"

#include <optional>
#include <vector>

namespace vesselmesh::flow {

// The wall whose shear stress this process computes and writes, and how its points lead back to
// the mesh.
struct WallPiece {
  post::WallSurface surface;  // the wall the operator works on
  std::optional<post::WallShearOperator> shear;
  TriMesh mesh;                    // the triangles this process writes, in the mesh's unit (labels: tags)
  std::vector<int> surface_point;  // per point of `mesh`, its point of `surface`
  std::vector<int> mesh_point;     // per point of `mesh`, its number in the mesh read
  // The wall points this process owns (each counted on one process) and those of them that took
  // the face value.
  int owned_points = 0, owned_fallbacks = 0;

  // Per point of `mesh`, Pa; `velocity` per point of the volume the operator was made on.
  std::vector<Vec3> stress(const std::vector<Vec3>& velocity, double viscosity) const {
    const std::vector<Vec3> all = shear->apply(velocity, viscosity);
    std::vector<Vec3> out(surface_point.size());
    for (size_t i = 0; i < out.size(); ++i) out[i] = all[surface_point[i]];
    return out;
  }
};

// One process: the whole wall of the mesh read.
WallPiece whole_wall(const TetMesh& mesh, const std::vector<int>& wall_tags, const FlowCase& fc);
// Under MPI: the process's part of the wall (MeshPart::wall), the operator on its cells within
// the stencils' reach (its local points), and the triangles it writes.
WallPiece distributed_wall(const MeshPart& part, const std::vector<int>& wall_tags, const FlowCase& fc);

// Under MPI, the piece of the fluid a process writes: its cells whose least point (in the mesh's
// numbering) it owns, and per point of the piece its local point.
struct FluidPiece {
  TetMesh mesh;
  std::vector<int> local;
};
FluidPiece own_fluid_piece(const MeshPart& part);

}  // namespace vesselmesh::flow
