// A process's part of the volume mesh under MPI (issue 28): the first process reads the whole
// mesh, numbers its points for the solver, splits them among the processes (PT-Scotch over the
// point graph, partition_graph) and sends each process its part; the others never hold the whole
// mesh (nor read its file).
//
// The solver's (global) numbering: reverse Cuthill-McKee over the whole mesh
// (mesh::cuthill_mckee_order), then the points grouped by the process the partitioner gives them:
// each process's points a consecutive range, in RCM order inside (a narrow band: the assembly and
// the solver touch nearby memory). A process's part: its cells (those with a point it owns; the
// prisms cut into tetrahedra in the global numbering) and their points, numbered locally: its own
// points first (global process_begin[rank] + local), then its ghosts (the others' points of its
// cells) by global number.
#pragma once

#include "mesh/tetmesh.h"

#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace vesselmesh::flow {

// What a process needs for the wall shear stress of its wall (the quadratic recovery's 2-ring
// stencils reach two edges into the volume, past the cells the process assembles): its wall
// triangles (those whose least global point it owns) and the wall points they and its own wall
// points hold (`points`, where the stress must be right), with every wall triangle through those
// points (their normals), and the cells within the stencils' reach (`cells`: those with a point
// within one edge of them). Their points are local points (ghosts beyond the assembly's where
// needed), all in local numbers.
struct WallPart {
  std::vector<Tet> cells;
  std::vector<Triangle> triangles;
  std::vector<int> tags;
  std::vector<char> written;  // per triangle: this process's (it writes it)
  std::vector<int> points;    // sorted
};

struct MeshPart {
  int total_points = 0;
  std::vector<int> process_begin;  // per process its first global point; one more: the total
  int owned = 0;                   // local points 0 .. owned - 1 are this process's
  std::vector<int> local_global;   // per local point its global number
  std::vector<int> mesh_point;     // per local point its number in the mesh read
  std::vector<Vec3> points;        // per local point, in the mesh's unit
  std::vector<Tet> tets;           // local numbers
  // The boundary triangles whose points are all local and one at least owned (local numbers, in
  // the mesh's order) with their tags, and every (local point, tag) of a boundary triangle through
  // a local point (sorted, once each).
  std::vector<Triangle> boundary;
  std::vector<int> boundary_tags;
  std::vector<std::array<int, 2>> point_tags;
  std::map<int, std::string> tag_names;  // every boundary tag of the mesh
  // The whole mesh's counts (every process) and, on the first process only, per global point its
  // number in the mesh read (for gathering whole fields in the mesh's numbering).
  int mesh_tetrahedra = 0;  // prisms cut in three
  std::vector<int> global_mesh_point;
  WallPart wall;  // when the split was asked for the wall
};

// The point split: every point of the graph's process, given the graph (CSR rows `start`,
// `neighbours` by number, the point itself possibly among them) and the process count.
using Partitioner =
    std::function<std::vector<int>(const std::vector<int>& start, const std::vector<int>& neighbours, int parts)>;

// Numbers and splits a whole mesh for `parts` processes, then makes each process's part on
// demand (one at a time: the first process sends each before it makes the next). InputError when
// a tetrahedron is inverted or flat (naming it), the mesh has no tetrahedra, or a process would
// own no point (more processes than points).
class MeshSplitter {
 public:
  // `wall_names`: the boundary tags (by name) whose shear stress the processes compute (each
  // part's WallPart); none: no WallPart.
  MeshSplitter(const TetMesh& mesh, const std::string& path, int parts, const Partitioner& partition,
               const std::vector<std::string>& wall_names = {});
  ~MeshSplitter();
  MeshSplitter(const MeshSplitter&) = delete;
  MeshSplitter& operator=(const MeshSplitter&) = delete;

  int parts() const;
  // Process `rank`'s part (global_mesh_point set in the first's only).
  MeshPart part(int rank) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A part as bytes and back (what the first process sends); unpack throws InternalError on bytes
// that are not a part.
std::string pack(const MeshPart& part);
MeshPart unpack(std::string bytes);

// Collective: on the first process `mesh` is the whole mesh read from `path` (the others: null),
// or `failure` the error its reading raised; the first splits it (PT-Scotch) and sends each
// process its part, and every process returns its own. An error on the first process (reading,
// checking or splitting the mesh) is thrown on every process alike: the first's own, the others
// an error of the same kind (InputError, OptionError, ComputationError or InternalError) with its
// message, so that every process stops at once and a caller may leave the telling to the first.
// `wall_names` as MeshSplitter's.
MeshPart distribute_mesh(const TetMesh* mesh, const std::string& path, std::exception_ptr failure = nullptr,
                         const std::vector<std::string>& wall_names = {});

}  // namespace vesselmesh::flow
