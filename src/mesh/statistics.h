// Size, shape and topology figures of a surface, as `vesselmesh info` reports them.
// Lengths in the mesh's unit, angles in degrees.
#pragma once

#include "mesh/trimesh.h"

namespace vesselmesh::mesh {

struct Range {
  double min = 0.0, mean = 0.0, median = 0.0, max = 0.0;
};

struct Statistics {
  int points = 0;
  int triangles = 0;
  int edges = 0;
  int boundary_edges = 0;
  int boundary_loops = 0;
  int components = 0;
  bool closed = false;  // no boundary edge
  int euler_characteristic = 0;
  int genus = 0;  // of a manifold orientable surface: (2c - chi - loops) / 2
  double area = 0.0;
  double volume = 0.0;  // signed, open ends fan-capped; > 0 when oriented outward
  Vec3 box_min = Vec3::Zero(), box_max = Vec3::Zero();
  Range edge_length;
  Range min_angle;      // per triangle, its smallest angle (degrees)
  double max_angle = 0.0;  // largest angle of any triangle (degrees)
  int sliver_triangles = 0;  // smallest angle below 5 degrees
};

// Input: a manifold surface (after clean). Linear time apart from two sorts for medians.
Statistics statistics(const TriMesh& mesh);

}  // namespace vesselmesh::mesh
