// The mesh the remesher edits (internal to remesh/): points with their metric, reference normal
// and kind; triangles with their label; each point's ball (its live triangles); and the edges
// that lie on feature curves. Local operations replace a few triangles at a time; dead
// triangles and points are dropped by compact().
#pragma once

#include "mesh/sym3.h"
#include "mesh/trimesh.h"
#include "remesh/surface_model.h"

#include <unordered_map>
#include <vector>

namespace vesselmesh::remesh {

class DynamicMesh {
 public:
  // Starts as a copy of the model's input surface.
  explicit DynamicMesh(const SurfaceModel& model);

  // Points.
  std::vector<Vec3> position;
  std::vector<Sym3> metric;
  std::vector<Vec3> normal;  // reference normal of the surface at the point (free points)
  std::vector<PointKind> kind;
  std::vector<int> curve;    // curve points: their curve
  std::vector<int> hint;     // an input triangle at or near the point (for local projections)
  std::vector<char> point_alive;
  // Set when a point's ball changes (a triangle added, removed or re-cornered there); the move
  // pass clears it and skips points where nothing changed since their last try.
  std::vector<char> dirty;

  // Triangles.
  std::vector<Triangle> triangles;
  std::vector<int> labels;
  std::vector<char> triangle_alive;
  std::vector<std::vector<int>> ball;  // per point, its live triangles

  int add_point(const Vec3& p, const Sym3& m, const Vec3& n, PointKind k, int c, int input_triangle);
  int add_triangle(const Triangle& f, int label);
  void kill_triangle(int t);
  void set_corner(int t, int corner, int point);  // moves a triangle corner to another point

  // Edge a-b: the curve it lies on, or -1.
  int curve_of_edge(int a, int b) const;
  void set_curve_edge(int a, int b, int curve);  // -1 removes it

  // Live triangles with both a and b, and whether a and b share an edge.
  std::vector<int> triangles_of_edge(int a, int b) const;
  bool connected(int a, int b) const;
  // The other points of a's ball, sorted.
  std::vector<int> neighbours(int a) const;

  // Length of a-b in the metric, with the size varying geometrically between the ends.
  double edge_length(int a, int b) const;
  // 4 sqrt(3) area / sum of squared edge lengths, all in the mean metric of the corners:
  // 1 for an equilateral triangle of the metric, 0 for a degenerate one. With `shapes_in_space`,
  // in space instead (the metric's sizes no longer matter, only the shape: the remesher's last
  // flips and moves on an isotropic kind whose bound stretched it along tubes, Remesher::run).
  double quality(const Triangle& f) const;
  bool shapes_in_space = false;
  // Radians: from this largest angle in space on, a triangle's quality falls linearly with it, to 0
  // when it is flat (0: not at all). Set for the last flips and moves where the metric is stretched
  // (Remesher::run): there an equilateral triangle of the metric with an edge along the stretch is
  // a cap in space.
  double caps_from = 0.0;
  double largest_angle(const Triangle& f) const;  // radians, in space

  // The surface: triangles, labels, and the metric per point (dead entries dropped).
  // With `hints`, each output point's input triangle (for local distance queries).
  TriMesh to_trimesh(std::vector<Sym3>* metrics = nullptr, std::vector<int>* hints = nullptr) const;

 private:
  static uint64_t key(int a, int b);
  std::unordered_map<uint64_t, int> curve_edges_;
  bool labelled_ = false;
};

}  // namespace vesselmesh::remesh
