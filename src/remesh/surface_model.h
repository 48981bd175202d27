// The input surface as the remesher sees it: where points may go and what size they ask for.
//
// Features (analysis/features.h): open ends, label borders and creases above the feature
// angle form curves; their corners stay where they are.
// Projection: a point goes to the closest point of the input triangles (AABB tree), a curve
// point to the closest point of its own curve. The normal there is interpolated from corner
// normals that do not cross creases (area-weighted, so slivers weigh nothing); the metric is
// interpolated log-Euclidean from the input points' metrics.
#pragma once

#include "analysis/features.h"
#include "mesh/connectivity.h"
#include "mesh/locator.h"
#include "mesh/sym3.h"
#include "mesh/trimesh.h"

#include <memory>
#include <vector>

namespace vesselmesh::remesh {

using analysis::FeatureOptions;
using analysis::PointKind;

struct Projection {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::Zero();  // unit, on the side of the triangle it landed on
  Sym3 metric;
  int triangle = -1;  // input triangle (surface projections)
};

class SurfaceModel {
 public:
  SurfaceModel(const TriMesh& input, const std::vector<Sym3>& metrics, const FeatureOptions& options);
  // With the features found already (analysis::detect_features on `input`).
  SurfaceModel(const TriMesh& input, const std::vector<Sym3>& metrics, analysis::Features features);
  ~SurfaceModel();

  const TriMesh& input() const { return input_; }
  const analysis::Features& features() const { return features_; }
  PointKind kind(int input_point) const { return features_.kind[input_point]; }
  // The curve an input point lies on (kind curve), or -1.
  int curve_of_point(int input_point) const { return features_.curve_of_point[input_point]; }
  int num_curves() const { return features_.num_curves; }
  const Sym3& metric(int input_point) const { return metrics_[input_point]; }
  // Multiplies the metric at an input point by `factor` (> 1: sizes shrink by its square root).
  void refine_metric(int input_point, double factor);

  // The closest point of the input (AABB tree); with a `hint`, the closest point near input
  // triangle `hint` (p lies near the surface there): a descent over triangles sharing a point
  // with the best one so far, then the global query when it wanders too far. A local closest
  // point: on a thin vessel it stays on the same wall.
  Projection project(const Vec3& p, int hint = -1) const;
  Projection project_on_curve(int curve, const Vec3& p) const;
  // Only the closest point and its input triangle (no normal, no metric), found as project()
  // finds it; and the distance to it (global without a hint; local with one: never smaller).
  struct Nearest {
    Vec3 point;
    int triangle;
  };
  Nearest nearest(const Vec3& p, int hint = -1) const;
  double distance(const Vec3& p, int hint = -1) const { return (nearest(p, hint).point - p).norm(); }
  // An input triangle at input point v.
  int triangle_at(int input_point) const { return incidence_.triangles[incidence_.offsets[input_point]]; }

 private:
  struct Curve;
  Sym3 metric_at(int triangle, const Vec3& barycentric) const;
  Projection finish(const Vec3& point, int triangle) const;
  // The local closest point, or triangle -1 when the walk gave up.
  Nearest walk(const Vec3& p, int hint) const;

  const TriMesh& input_;
  std::vector<Sym3> metrics_, logs_;
  mesh::SurfaceLocator locator_;
  mesh::VertexTriangles incidence_;
  struct Sphere {
    Vec3 center;
    double radius;
  };
  std::vector<Sphere> spheres_;  // per input triangle, a sphere holding it (walk's pruning)
  analysis::Features features_;
  std::vector<Vec3> copy_normals_;  // per point copy (analysis::Features)
  std::vector<std::unique_ptr<Curve>> curves_;
};

}  // namespace vesselmesh::remesh
