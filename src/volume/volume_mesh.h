// The volume mesh of a lumen: boundary layer, caps and interior tetrahedra, with the boundary
// tagged for the solver.
//
// Input: the lumen surface (outward, manifold; a remeshed surface is best) and its ends as
// `analysis::open_ends` finds them (largest first, the order of `vesselmesh info`). Capped
// ends (flat caps of a closed surface) are cut off and built again like open ends, so every
// end gets the same layer ending and cap; their tag keeps the cap's label when it has one.
// Steps: the boundary layer on the wall (boundary_layer.h; none with layers = 0), a cap on
// each end's inner loop (cap.h), the tetrahedra inside the inner surface and the caps (fill.h),
// sized by the interior's own field (interior_size.h: the wall's area-equivalent sizes carried
// inward and graded, the core bounded by the radius), each prism cut into three tetrahedra (or
// kept). Then every cell's volume and the
// boundary's closure are checked: an inverted cell or an open boundary is an error, never an
// output.
// Tags: wall, then one per end, named `inlet` (the largest end, or the one chosen) and
// `outlet_1`, `outlet_2`, ... in the ends' order, unless names are given. The end's strip of
// layer faces and its cap carry its tag.
#pragma once

#include "analysis/open_ends.h"
#include "mesh/reporter.h"
#include "mesh/tetmesh.h"
#include "volume/boundary_layer.h"
#include "volume/sliver.h"
#include "volume/fill.h"
#include "volume/interior_size.h"

#include <string>
#include <vector>

namespace vesselmesh::volume {

// An end named by a point near its centre (`vesselmesh volume --end NAME:x,y,z`): names that
// stay with their ends whatever order the ends come in.
struct EndAt {
  std::string name;
  Vec3 point = Vec3::Zero();
};

struct VolumeOptions {
  BoundaryLayerOptions layer;  // layer.layers = 0: no boundary layer
  FillAlgorithm algorithm = FillAlgorithm::delaunay;  // deterministic; HXT is not run to run
  InteriorSizeOptions interior;  // the interior's sizes, whatever the engine
  bool keep_prisms = false;
  int inlet = -1;                      // index into the ends; -1: the largest
  std::vector<std::string> end_names;  // in the ends' order; empty: inlet, outlet_1, ...
  std::vector<EndAt> end_at;           // or: every end named by the point nearest its centre
  int threads = 0;
  // Interior tetrahedra with a dihedral angle under this (degrees) are improved after the fill
  // (volume/sliver.h); 0: the fill is kept as it comes.
  double sliver_angle_deg = 10.0;
};

// The ends' names in their order from one point per end: each end takes the name of the point
// nearest its centre. OptionError when the count differs, when two points pick the same end, or
// when a point is farther than three radii from its end's centre (listing the centres).
std::vector<std::string> names_of_ends(const std::vector<analysis::OpenEnd>& ends, const std::vector<EndAt>& named);

struct VolumeEnd {
  std::string name;
  int tag = 0;
  Vec3 center = Vec3::Zero();
  Vec3 normal = Vec3::Zero();
  double radius = 0.0;
  bool capped = false;
  int cap_triangles = 0;  // triangles of the new cap
};

struct VolumeReport {
  int layers = 0;
  int layer_tets = 0, layer_prisms = 0, interior_tets = 0;
  int interior_points = 0;  // points the fill added inside
  double interior_factor = 1.0;  // the interior size factor used (options.interior.factor)
  // The interior size field at the wall's points (mm): least, median, largest.
  double interior_size_min = 0.0, interior_size_median = 0.0, interior_size_max = 0.0;
  int shrunk_vertices = 0;     // wall points whose layer is thinner than asked
  int first_height_capped = 0;  // wall points whose layer the first height asked made thinner (layer.first_height)
  SliverReport slivers;        // the interior's clean-up
  double least_fraction = 1.0;  // of the thickness asked for, and where
  Vec3 least_at = Vec3::Zero();
  int thickened_vertices = 0;        // wall points whose layer is thicker than asked (for its angles)
  double most_fraction = 1.0;        // of the thickness asked for, and where
  Vec3 most_at = Vec3::Zero();
  int under_angle_prisms = 0;        // layer prisms whose tetrahedra stay under the angle asked
  int split_edges = 0;               // wall edges halved for the layer's angles (split_angle_deg)
  double least_layer_angle = 180.0;  // degrees, over the layer's tetrahedra
  double min_thickness_ratio = 0.0, max_thickness_ratio = 0.0;  // layer thickness / local radius
  std::vector<VolumeEnd> ends;
  int wall_tag = 1;
};

struct VolumeResult {
  TetMesh mesh;
  VolumeReport report;
  std::vector<double> radius;  // per mesh point: the wall radius under it (layer points), else 0
};

// `radius`: the local radius (distance map) per surface point; may be empty with layers = 0 (then
// the interior's core is not bounded by the radius).
VolumeResult build_volume(const TriMesh& surface, const std::vector<analysis::OpenEnd>& ends,
                          const std::vector<double>& radius, const VolumeOptions& options,
                          const Reporter& reporter = silent_reporter());

// The volume of about `target_points` points (within `tolerance`, relative), for comparing meshes
// of equal volume counts (the study): options.interior.factor is scaled, the layer and the wall
// kept, so only the interior's count moves, about as the factor to the power -3. Starts from
// options.interior.factor; at most four builds (the last is returned if none is within the
// tolerance); the factor used is in the report (interior_factor). InputError when the layer and
// the caps alone have more points than the target.
VolumeResult build_volume_with_points(const TriMesh& surface, const std::vector<analysis::OpenEnd>& ends,
                                      const std::vector<double>& radius, const VolumeOptions& options,
                                      int target_points, double tolerance = 0.02,
                                      const Reporter& reporter = silent_reporter());

// Checks a tetrahedral mesh the way build_volume does before handing it on: every tetrahedron
// (and prism split) positive, and the boundary triangles exactly the faces used by one cell,
// oriented outward. Throws InputError (inverted cell, naming it and where) or InternalError.
void check_volume(const TetMesh& mesh);

}  // namespace vesselmesh::volume
