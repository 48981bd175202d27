// Size fields for the surface remesher: an SPD metric M per surface point (isotropic: I / h^2)
// from one of the four fields the seed paper compares:
//   uniform      h constant;
//   distance     h = 2 pi d / N, d the distance to the centerline (N points around the vessel);
//   curvature    h = 2 pi / (|H| N), N points on the osculating circle of the mean curvature;
//   anisotropic  M = P diag(1/h1^2, 1/h2^2, 1/hn^2) P^T, P = [dir1, dir2, n], h_i =
//                2 pi / (|k_i| N) along each principal direction, hn = min(h1, h2);
//   flow         the same form from a flow's error metric (sizing/hessian.h: where the WSS's
//                linear interpolation errs most, finest; issue 52), carried onto the surface:
//                its principal sizes and directions in the surface's tangent plane, scaled so
//                that unclamped they give the target count (which it needs: the flow says
//                where, the count how fine), hn = min(h1, h2).
// Every size is clamped to [hmin, hmax] (defaults from the vessel's radii, never from its
// bounding box), bounded by the chord error when asked (h <= sqrt(8 eps / |k|) along each
// direction of normal curvature k: isotropic kinds with the largest |k|, the anisotropic
// kind along each principal direction), and
// graded (sizing/gradation.h). A target triangle count scales the whole field (clamps
// included) so that the predicted count, (4 / sqrt 3) x integral of the metric's tangent
// density over the surface (unit equilateral triangles), meets it.
// Lengths in the mesh's unit; curvature in its inverse.
#pragma once

#include "analysis/curvature.h"
#include "centerline/distance_map.h"
#include "mesh/reporter.h"
#include "mesh/sym3.h"
#include "mesh/trimesh.h"

#include <string>
#include <vector>

namespace vesselmesh::sizing {

enum class SizeKind { uniform, distance, curvature, anisotropic, flow };

// "uniform", "distance", "curvature", "anisotropic", "flow"; OptionError otherwise.
SizeKind parse_size_kind(const std::string& name);
std::string size_kind_name(SizeKind kind);

struct SizingOptions {
  SizeKind kind = SizeKind::curvature;
  double h = 0.0;                    // uniform: the size
  double points_per_circle = 20.0;   // N
  double hmin = 0.0, hmax = 0.0;     // <= 0: derived (see SizeInputs)
  double gradation = 1.3;            // growth per unit of metric length; <= 1: none
  double max_chord_error = 0.0;      // > 0: bound the size by this chord error
  double target_triangles = 0.0;     // > 0: scale the field to this predicted count
};

// What the kinds need: curvature (curvature, anisotropic, chord error) and the distance map
// (distance). The vessel's radius range sets the default clamps: hmin = r_low / 10, hmax = r_high.
// The flow kind needs the flow's error metric (per point, SPD; its scale does not matter).
struct SizeInputs {
  const analysis::CurvatureField* curvature = nullptr;
  const centerline::DistanceMap* distance = nullptr;
  double radius_low = 0.0, radius_high = 0.0;
  const std::vector<Sym3>* flow = nullptr;
};

// The radius range of a vessel: 5th and 95th percentiles of the distance map's radius, or,
// without one, of 1 / k2 where the surface is convex around.
void radius_range(const TriMesh& mesh, const SizeInputs& inputs, double& low, double& high);

struct SizeField {
  SizeKind kind = SizeKind::uniform;
  std::vector<Sym3> metric;   // per point
  std::vector<double> size;   // per point: the isotropic size (anisotropic, flow: the smallest)
  double hmin = 0.0, hmax = 0.0;
  double scale = 1.0;         // applied for the target count
  double predicted_triangles = 0.0;
  int gradation_passes = 0;
};

SizeField make_size_field(const TriMesh& mesh, const SizingOptions& options, const SizeInputs& inputs,
                          const Reporter& reporter = silent_reporter());

// The chord bound at point v: the largest metric whose unit edges stray at most eps from the
// surface, an edge of length h along a direction of normal curvature k lying k h^2 / 8 (its
// sagitta) away at its middle. Isotropic: h = sqrt(8 eps / max(|k1|, |k2|)); anisotropic:
// h_i = sqrt(8 eps / |k_i|) along each principal direction (no bound where |k_i| = 0), the
// normal direction as the finer one.
Sym3 chord_metric(const analysis::CurvatureField& curvature, int v, double eps, bool anisotropic);
// The isotropic chord bound with its size along the smaller principal curvature's direction
// `stretch` times the other's (a tube: the bound lies round it); the normal as the finer.
Sym3 stretched_chord_metric(const analysis::CurvatureField& curvature, int v, double eps, double stretch);

// (4 / sqrt 3) sum over points of (mixed area) x (tangent density of the metric).
double predicted_triangles(const TriMesh& mesh, const std::vector<Sym3>& metrics);

}  // namespace vesselmesh::sizing
