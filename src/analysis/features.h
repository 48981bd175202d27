// Feature lines of a surface: what a remesher must keep and what curvature must not smooth over.
//
// Feature edges: boundary edges (open ends), edges between triangles of different labels, and
// creases, edges whose dihedral angle (between the two triangles' normals) exceeds the feature
// angle, e.g. where a flat cap meets the wall. A segmentation's slivers make isolated sharp
// edges that are noise, not creases: chains of fewer than `min_crease_edges` crease edges
// (connected through shared points) are dropped.
// Feature edges chain into curves; a curve point where other than two feature edges meet, or
// where the curve turns by more than the corner angle, is a corner, and corners end curves.
// Smooth patches: creases (not open ends, not label borders on a smooth wall) cut the surface
// into patches; each point has one copy per patch around it, which gives normals and
// curvature on each side of a crease.
#pragma once

#include "analysis/curvature.h"
#include "mesh/connectivity.h"
#include "mesh/reporter.h"
#include "mesh/trimesh.h"

#include <cstdint>
#include <vector>

namespace vesselmesh::analysis {

enum class PointKind : uint8_t { free, curve, corner };

struct FeatureOptions {
  double feature_angle_deg = 60.0;  // dihedral angle above which an edge is a crease
  double corner_angle_deg = 60.0;   // turn of a curve above which its point is a corner
  int min_crease_edges = 5;         // shorter connected sets of crease edges are noise
};

struct Features {
  mesh::EdgeMap edges;
  std::vector<char> crease;         // per edge: a kept crease (cuts patches)
  std::vector<int> curve_of_edge;   // per edge: its curve, or -1 (not a feature)
  std::vector<PointKind> kind;      // per point
  std::vector<int> curve_of_point;  // per point: its curve (kind curve), else -1
  int num_curves = 0;
  int num_creases = 0;              // crease edges kept
  int dropped_creases = 0;          // isolated sharp edges taken for noise
  // Per triangle corner, the copy of its point on that corner's side of the creases; per
  // copy, its point. A point off creases has one copy.
  std::vector<std::array<int, 3>> corner_copy;
  std::vector<int> copy_point;

  int num_copies() const { return static_cast<int>(copy_point.size()); }
};

Features detect_features(const TriMesh& mesh, const FeatureOptions& options = {});

// The surface cut along its creases: point i is copy i (at the position of copy_point[i]),
// triangles and labels as in `mesh`.
TriMesh split_at_creases(const TriMesh& mesh, const Features& features);

// Curvature of each smooth patch (the surface cut along its creases); a point on a crease takes
// the values of the side that curves most (the largest |k|). Equal to curvature() on a surface
// without creases.
CurvatureField patch_curvature(const TriMesh& mesh, const Features& features, const CurvatureOptions& options = {},
                               const Reporter& reporter = silent_reporter());

}  // namespace vesselmesh::analysis
