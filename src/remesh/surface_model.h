// The input surface as the remesher sees it: where points may go and what size they ask for.
//
// Features (analysis/features.h): open ends, label borders and creases above the feature
// angle form curves; their corners stay where they are.
// Projection: a point goes to the closest point of the smooth surface the input's triangles stand
// for (Reconstruction::phong, the default) or of the triangles themselves (facets, as mmgs), a
// curve point to the closest point of its own curve.
// The smooth surface: per input triangle, Phong tessellation (T. Boubekeur, M. Alexa, "Phong
// tessellation", SIGGRAPH Asia 2008) with shape factor 1/2,
//   S(l) = q + 1/2 sum_i l_i n_i n_i^T (v_i - q),   q = sum_i l_i v_i,
// which interpolates the input points and their normals n_i (the quadric fit's,
// analysis/normals.h) and, on a polygon inscribed in a
// circle or a sphere, is the circle to second order in the edge length (the facets are off by
// (edge/2)^2 / 2R; Phong's usual 3/4 overshoots). A point on a crease or a label border has no
// smooth normal there: it contributes nothing, so the surface meets those curves' polylines from
// both sides without gaps and is continuous across every input edge. An open end's rim (one side)
// keeps its normals: its curve points go onto the smooth surface's edges (a coarse end's polygon
// becomes the section it stands for). On a coarse, faceted segmentation (edges as long as a
// small branch's radius) the remesher's points then lie on the vessel the facets stand for, and
// the distance bound measures against it, instead of refining to reproduce the facets. The normal there is interpolated from corner
// normals that do not cross creases (area-weighted, so slivers weigh nothing); the metric is
// interpolated log-Euclidean from the input points' metrics.
#pragma once

#include "analysis/features.h"
#include "mesh/connectivity.h"
#include "mesh/locator.h"
#include "mesh/sym3.h"
#include "mesh/trimesh.h"

#include <array>
#include <memory>
#include <string>
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

enum class Reconstruction { facets, phong };

class SurfaceModel {
 public:
  SurfaceModel(const TriMesh& input, const std::vector<Sym3>& metrics, const FeatureOptions& options,
               Reconstruction reconstruction = Reconstruction::phong);
  // With the features found already (analysis::detect_features on `input`).
  SurfaceModel(const TriMesh& input, const std::vector<Sym3>& metrics, analysis::Features features,
               Reconstruction reconstruction = Reconstruction::phong);
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

  Reconstruction reconstruction() const { return reconstruction_; }
  // The closest point of the input (AABB tree); with a `hint`, the closest point near input
  // triangle `hint` (p lies near the surface there): a descent over triangles sharing a point
  // with the best one so far, then the global query when it wanders too far. A local closest
  // point: on a thin vessel it stays on the same wall. On the smooth surface (phong): the closest
  // triangle's patch, from the triangle's closest point by Gauss-Newton steps in its barycentric
  // coordinates (within the triangle; the patches meet continuously at its edges).
  // `whole_ring`: as nearest() below.
  Projection project(const Vec3& p, int hint = -1, bool whole_ring = false) const;
  Projection project_on_curve(int curve, const Vec3& p) const;
  // Only the closest point and its input triangle (no normal, no metric), found as project()
  // finds it; and the distance to it (global without a hint; local with one: never smaller).
  // `whole_ring`: also the patches round the closest facet's corners that may hold a closer
  // point (where the input creases without a feature curve, a neighbour's patch can bulge past
  // the closest facet's: 0.19 mm against 0.016 on the capped SimVascular aorta). Never farther,
  // and dearer: the distance bound's checks ask for it only where the first answer is over.
  struct Nearest {
    Vec3 point;
    int triangle;
  };
  Nearest nearest(const Vec3& p, int hint = -1, bool whole_ring = false) const;
  double distance(const Vec3& p, int hint = -1, bool whole_ring = false) const {
    return (nearest(p, hint, whole_ring).point - p).norm();
  }
  // The distance to the input's triangles themselves, whatever the reconstruction.
  double facet_distance(const Vec3& p, int hint = -1) const {
    return (nearest_facet(p, hint).point - p).norm();
  }
  // The smooth surface's point at barycentric coordinates `l` of input triangle `triangle` (the
  // triangle's own point with facets).
  Vec3 surface_point(int triangle, const Vec3& l) const;
  // An input triangle at input point v.
  int triangle_at(int input_point) const { return incidence_.triangles[incidence_.offsets[input_point]]; }

 private:
  struct Curve;
  Sym3 metric_at(int triangle, const Vec3& barycentric) const;
  Projection finish(const Vec3& point, int triangle, const Vec3& barycentric) const;
  Nearest nearest_facet(const Vec3& p, int hint) const;
  // From the closest point of a triangle to the closest point of its patch: the point and its
  // barycentric coordinates.
  struct OnPatch {
    Vec3 point, barycentric;
  };
  OnPatch onto_patch(const Vec3& p, const Nearest& facet) const;
  // The same over the patches around the rim point it may stop at (`whole_ring`: round the
  // triangle's corners, as nearest() says); `facet` becomes the winner's.
  OnPatch onto_surface(const Vec3& p, Nearest& facet, bool whole_ring) const;
  void in_rim_planes(const mesh::EdgeMap& edges);
  // Phong's normal at each corner of a triangle (zero at feature points: no displacement).
  std::array<Vec3, 3> corner_normals(int triangle) const;
  // The local closest point, or triangle -1 when the walk gave up.
  Nearest walk(const Vec3& p, int hint) const;

  const TriMesh& input_;
  Reconstruction reconstruction_;
  std::vector<Sym3> metrics_, logs_;
  mesh::SurfaceLocator locator_;
  mesh::VertexTriangles incidence_;
  struct Sphere {
    Vec3 center;
    double radius;
  };
  std::vector<Sphere> spheres_;  // per input triangle, a sphere holding it (walk's pruning)
  analysis::Features features_;
  std::vector<Vec3> copy_normals_;    // per point copy (analysis::Features)
  std::vector<Vec3> fitted_normals_;  // per point, for the smooth surface (analysis::vertex_normals)
  std::vector<char> rigid_;           // per point: on a crease or label border (no smooth normal)
  std::vector<double> bulge_;         // per triangle: how far its patch strays from it at most
  std::vector<std::unique_ptr<Curve>> curves_;
};

// `metrics` given at `from`'s points carried onto each of `to`'s points: the point projected onto
// `from` (log-Euclidean interpolation inside the triangle it lands in). InputError, beginning with
// `what` (the field's name for the user), where a point of `to` lies farther from `from` than 1 % of
// `to`'s bounding box: the field belongs to another surface, or is in another unit.
std::vector<Sym3> carry_metric(const TriMesh& from, const std::vector<Sym3>& metrics, const TriMesh& to,
                               const std::string& what);

}  // namespace vesselmesh::remesh
