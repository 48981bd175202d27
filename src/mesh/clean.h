// The mesh doctor: checks a triangle surface and repairs what can be repaired safely.
//
// In order: non-finite coordinates and out-of-range indices (errors); near-duplicate points
// merged (tolerance relative to the local edge length); triangles with a repeated corner and
// duplicate triangles removed; non-manifold edges (error); non-manifold vertices split into
// one vertex per fan; orientation made consistent (non-orientable: error); the largest
// connected component kept, the others reported; every component oriented outward (signed
// volume with the open ends fan-capped); zero-area triangles mended by flipping their
// longest edge (removed on a boundary); unreferenced points removed; self-intersecting
// triangle pairs found (reported, not repaired).
//
// Every finding is counted in `defects`, every change in `repairs`, and `notes` has one line
// per finding that says where (indices refer to the input of that step, positions in the
// mesh's unit). What cannot be repaired safely throws InputError saying where and what to do.
#pragma once

#include "mesh/reporter.h"
#include "mesh/trimesh.h"

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace vesselmesh::mesh {

struct CleanOptions {
  // Points closer than this fraction of their mean incident edge length are merged. The
  // default catches float round-off between exporters (1e-7 relative) and keeps the real
  // short edges of marching-cubes surfaces (seen down to 4e-4 of the mean edge).
  double merge_tolerance = 1e-4;
  // A triangle is zero-area when |(b-a)x(c-a)| <= this * (longest edge)^2.
  double zero_area_tolerance = 1e-12;
  bool keep_largest_component = true;
  bool orient_outward = true;
  bool find_self_intersections = true;
  int max_locations = 3;  // locations listed per finding in `notes`
};

struct CleanReport {
  int input_points = 0;
  int input_triangles = 0;
  int input_components = 0;
  std::map<std::string, int> defects;  // every kind, 0 when not found
  std::map<std::string, int> repairs;  // every kind, 0 when nothing was changed
  std::vector<std::string> notes;      // one line per finding, with locations
  std::vector<std::pair<int, int>> self_intersections;  // triangle pairs of the output
  std::vector<int> point_origin;     // output point -> an input point it came from
  std::vector<int> triangle_origin;  // output triangle -> the input triangle it came from

  int total_repairs() const;
};

CleanReport clean(TriMesh& mesh, const CleanOptions& options = {},
                  const Reporter& reporter = silent_reporter());

// Signed volume enclosed by a consistently oriented surface whose boundary loops are closed
// by fans from their centroids (positive when oriented outward). The mesh's unit cubed.
double signed_volume(const TriMesh& mesh);

}  // namespace vesselmesh::mesh
