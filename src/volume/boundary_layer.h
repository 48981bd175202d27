// The boundary layer: N layers of prisms extruded inward from the wall of a lumen surface.
//
// Directions: Max-weighted vertex normals (analysis/normals.h) averaged over the one-ring
// `normal_smoothing` times, so that a segmentation's noise does not tilt the columns; on an
// open end's loop they are turned into the end's plane, so the layer ends flush with it.
// Thickness: `thickness_ratio` x the local radius (the distance map's inscribed-sphere
// radius), split into `layers` heights growing by `growth` from the wall (1: uniform).
// Where the wall's triangles are large against the thinnest layer's height, the thickness grows
// (up to half the radius), so that the prisms' tetrahedra keep `min_angle_deg`: a prism of
// height h over a triangle of largest altitude a splits into tetrahedra whose least dihedral
// angle is about atan(h / a); where the built prisms still fall short (inner levels widen where
// the wall is concave, columns lean), their columns grow again by what they missed (up to 3
// times). The growth spreads to the neighbours with the shrink's slope.
// Where columns converge (narrow places, tight bends, noisy spots) the thickness shrinks,
// smoothly (it changes by at most `shrink_slope` per unit length along the wall), until
//   - every layer prism splits into three positive tetrahedra whose top triangle turns less
//     than 60 degrees from the wall triangle's,
//   - an edge of the inner surface keeps at least a quarter of its wall length, and
//   - the layer's closed boundary (wall, end strips, inner surface) does not intersect
//     itself (exact predicates, CGAL).
// A column that would have to shrink below `min_thickness_fraction` of its target is an
// InputError naming the place: a layer is never left out silently.
//
// Points: the wall's points first (same indices), then one copy per level: the point of wall
// vertex v at level k (0 = wall, N = inner surface) has index k * n + v, n = wall points.
#pragma once

#include "mesh/reporter.h"
#include "mesh/tetmesh.h"
#include "mesh/trimesh.h"

#include <functional>
#include <vector>

namespace vesselmesh::volume {

struct BoundaryLayerOptions {
  int layers = 4;
  double thickness_ratio = 0.1;
  double growth = 1.0;  // each layer this many times thicker than the one nearer the wall
  int normal_smoothing = 4;
  double shrink_slope = 0.2;
  double min_thickness_fraction = 0.02;
  // The layer's tetrahedra keep this least dihedral angle (degrees) where the thickness may grow
  // for it (see above); 0: the thickness asked for, whatever the angles.
  double min_angle_deg = 5.0;
  // Wall triangles whose columns' tetrahedra stay under this angle (degrees) once the layer is
  // built (thin layers over stretched triangles: a prism of height h over a triangle of largest
  // altitude a has tetrahedra of about atan(h / a), whatever its cut) have their longest inner
  // edge halved and the layer is built again (split_long_edges; build_volume does it); the
  // thickness stays as asked. 0: the wall's triangles as given.
  double split_angle_deg = 5.0;
  // Where set, the first layer's height asked at a wall point (its units; <= 0 or not finite: none),
  // graded along the wall with the shrink's slope: where it is below the first layer's, the layers there
  // grow from it by the growth that fills the same thickness in as many layers (up to 2; beyond, the
  // thickness is cut to what growth 2 fills). The flow kind's height from the wall shear
  // (post::first_layer_heights).
  std::function<double(const Vec3&)> first_height = nullptr;
};

// An open end of the wall: its boundary loop (wall vertex indices, in the direction of the
// wall triangles' own edges) and the end's plane normal (out of the lumen).
struct WallEnd {
  std::vector<int> loop;
  Vec3 normal = Vec3::Zero();
};

struct BoundaryLayer {
  int levels = 0;  // layers + 1
  std::vector<Vec3> points;
  std::vector<Prism> prisms;      // TetMesh order: wall side first
  std::vector<int> prism_layer;   // 1 .. N from the wall
  std::vector<int> prism_column;  // the wall triangle below
  // The inner surface, oriented like the wall (toward it); indices into `points`.
  std::vector<Triangle> inner;
  // Per end: the strip of side faces (two triangles per loop edge and layer, outward along
  // the end's normal) and the inner loop (level N), in the wall loop's direction.
  std::vector<std::vector<Triangle>> end_strips;
  std::vector<std::vector<int>> inner_loops;
  // Per wall vertex: the thickness built and the one asked for (ratio x radius, or less where the first
  // height asks for more than growth 2 gives); `capped_vertices`: those whose layers the first height changed.
  std::vector<double> thickness, target;
  int capped_vertices = 0;
  // Per wall vertex: the thickness its prisms need for min_angle_deg (0 without that goal):
  // estimated from the wall's triangles, raised where the built prisms fell short.
  std::vector<double> angle_floor;
  std::vector<Vec3> direction;  // unit, inward
  // Shrink report: vertices below 99.9 % of their target, the least fraction kept and where.
  int shrunk_vertices = 0;
  double least_fraction = 1.0;
  Vec3 least_at = Vec3::Zero();
  // Thickening report: vertices above 100.1 % of their target, the most and where; the layer's
  // least dihedral angle (degrees) and where; prisms left under min_angle_deg (their columns
  // held at half the radius, or shrunk).
  int thickened_vertices = 0;
  double most_fraction = 1.0;
  Vec3 most_at = Vec3::Zero();
  double least_angle = 180.0;
  Vec3 least_angle_at = Vec3::Zero();
  int under_angle_prisms = 0;
  // Per wall triangle: the least dihedral angle (degrees) of its column's tetrahedra.
  std::vector<double> column_angle;
};

// `wall`: outward-oriented, manifold, its boundary loops exactly the `ends`; `radius` per wall
// point (> 0).
BoundaryLayer build_boundary_layer(const TriMesh& wall, const std::vector<double>& radius,
                                   const std::vector<WallEnd>& ends, const BoundaryLayerOptions& options,
                                   const Reporter& reporter = silent_reporter());

// Halves the longest inner edge (not on an end's loop) of each of `triangles` (wall triangle
// indices): the midpoint is appended to the wall's points (its radius the mean of the edge's),
// the two triangles beside the edge become four, oriented as they were; a triangle gets at most
// one split a call (longest edges first, so the result does not depend on the list's order).
// Returns the number of edges split. The wall keeps its shape and its ends' loops.
int split_long_edges(TriMesh& wall, std::vector<double>& radius, const std::vector<int>& triangles);

// Level heights as fractions of the thickness: levels + 1 values from 0 to 1.
std::vector<double> layer_fractions(int layers, double growth);

}  // namespace vesselmesh::volume
