#include "remesh/surface_model.h"

#include "mesh/error.h"
#include "mesh/geometry.h"
#include "sizing/metric.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace vesselmesh::remesh {

struct SurfaceModel::Curve {
  std::vector<std::array<int, 2>> segments;  // input points
  std::unique_ptr<mesh::SegmentLocator> locator;
};

namespace {

// Barycentric coordinates of q (in the plane of the triangle), clamped to the triangle.
Vec3 barycentric(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& q) {
  const Vec3 v0 = b - a, v1 = c - a, v2 = q - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1), d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double det = d00 * d11 - d01 * d01;
  if (!(det > 0.0)) return Vec3(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0);
  const double v = (d11 * d20 - d01 * d21) / det, w = (d00 * d21 - d01 * d20) / det;
  Vec3 l(1.0 - v - w, v, w);
  l = l.cwiseMax(0.0);
  return l / l.sum();
}

}  // namespace

SurfaceModel::SurfaceModel(const TriMesh& input, const std::vector<Sym3>& metrics, const FeatureOptions& options)
    : SurfaceModel(input, metrics, analysis::detect_features(input, options)) {}

SurfaceModel::SurfaceModel(const TriMesh& input, const std::vector<Sym3>& metrics, analysis::Features features)
    : input_(input), metrics_(metrics), locator_(input), incidence_(mesh::build_vertex_triangles(input)),
      features_(std::move(features)) {
  VM_CHECK(metrics.size() == input.points.size(), "one metric per input point");
  VM_CHECK(features_.corner_copy.size() == input.triangles.size(), "features of another surface");
  spheres_.reserve(input.triangles.size());
  for (int t = 0; t < input.num_triangles(); ++t) {
    const Vec3 c = mesh::triangle_centroid(input, t);
    double r = 0.0;
    for (int v : input.triangles[t]) r = std::max(r, (input.points[v] - c).norm());
    spheres_.push_back({c, r});
  }
  logs_.reserve(metrics.size());
  for (const Sym3& m : metrics) logs_.push_back(sizing::metric_log(m));
  copy_normals_.assign(features_.num_copies(), Vec3::Zero());
  for (int t = 0; t < input.num_triangles(); ++t)
    for (int copy : features_.corner_copy[t]) copy_normals_[copy] += mesh::triangle_area_vector(input, t);
  for (Vec3& n : copy_normals_)
    if (n.squaredNorm() > 0.0) n.normalize();
  curves_.resize(features_.num_curves);
  for (auto& curve : curves_) curve = std::make_unique<Curve>();
  const mesh::EdgeMap& edges = features_.edges;
  for (int e = 0; e < edges.num_edges(); ++e)
    if (features_.curve_of_edge[e] >= 0) curves_[features_.curve_of_edge[e]]->segments.push_back(edges.edges[e]);
  for (auto& curve : curves_) {
    std::vector<std::array<Vec3, 2>> segments;
    for (const auto& s : curve->segments) segments.push_back({input.points[s[0]], input.points[s[1]]});
    curve->locator = std::make_unique<mesh::SegmentLocator>(segments);
  }
}

SurfaceModel::~SurfaceModel() = default;

void SurfaceModel::refine_metric(int v, double factor) {
  VM_CHECK(factor > 0.0, "a metric factor must be positive");
  const double log_factor = std::log(factor);
  for (double& x : metrics_[v].v) x *= factor;
  for (int i : {0, 3, 5}) logs_[v].v[i] += log_factor;  // log(f M) = log f I + log M
}

Sym3 SurfaceModel::metric_at(int triangle, const Vec3& l) const {
  const Triangle& f = input_.triangles[triangle];
  const Sym3 logs[3] = {logs_[f[0]], logs_[f[1]], logs_[f[2]]};
  const double weights[3] = {l[0], l[1], l[2]};
  return sizing::interpolate_logs(logs, weights, 3);
}

Projection SurfaceModel::finish(const Vec3& point, int triangle) const {
  const Triangle& f = input_.triangles[triangle];
  const Vec3 l = barycentric(input_.points[f[0]], input_.points[f[1]], input_.points[f[2]], point);
  Projection out;
  out.point = point;
  out.triangle = triangle;
  const auto& c = features_.corner_copy[triangle];
  out.normal = l[0] * copy_normals_[c[0]] + l[1] * copy_normals_[c[1]] + l[2] * copy_normals_[c[2]];
  if (out.normal.norm() > 0.0) out.normal.normalize();
  out.metric = metric_at(triangle, l);
  return out;
}


SurfaceModel::Nearest SurfaceModel::walk(const Vec3& p, int hint) const {
  constexpr int kMaxVisits = 256;
  auto closest = [&](int t) {
    const Triangle& f = input_.triangles[t];
    return mesh::closest_point_on_triangle(p, input_.points[f[0]], input_.points[f[1]], input_.points[f[2]]);
  };
  Vec3 best = closest(hint);
  double best_d = (best - p).squaredNorm();
  double best_length = std::sqrt(best_d);
  int best_t = hint;
  // Expand from every triangle that is the best so far: a descent to a local minimum over
  // triangles sharing a point, whose last step has looked at the whole ring of the result.
  // Visited triangles carry the number of this walk (per thread: queries stay const and safe).
  thread_local std::vector<uint32_t> stamp;
  thread_local uint32_t walk_number = 0;
  if (stamp.size() != input_.triangles.size() || ++walk_number == 0) {
    stamp.assign(input_.triangles.size(), 0);
    walk_number = 1;
  }
  stamp[hint] = walk_number;
  int visits = 1;
  thread_local std::vector<int> stack;
  stack.assign(1, hint);
  while (!stack.empty()) {
    const int t = stack.back();
    stack.pop_back();
    for (int v : input_.triangles[t])
      for (int u : incidence_.of(v)) {
        if (stamp[u] == walk_number) continue;
        if (++visits > kMaxVisits) return {Vec3::Zero(), -1};
        stamp[u] = walk_number;
        // No point of u is nearer than its sphere allows: skip it when that is no better.
        const Sphere& sphere = spheres_[u];
        const double reach = sphere.radius + best_length;
        if ((p - sphere.center).squaredNorm() >= reach * reach) continue;
        const Vec3 q = closest(u);
        const double d = (q - p).squaredNorm();
        if (d < best_d) {
          best = q;
          best_d = d;
          best_length = std::sqrt(d);
          best_t = u;
          stack.push_back(u);
        }
      }
  }
  return {best, best_t};
}

SurfaceModel::Nearest SurfaceModel::nearest(const Vec3& p, int hint) const {
  if (hint >= 0) {
    const Nearest local = walk(p, hint);
    if (local.triangle >= 0) return local;
  }
  const mesh::SurfaceLocator::Hit hit = locator_.closest(p);
  return {hit.point, hit.triangle};
}

Projection SurfaceModel::project(const Vec3& p, int hint) const {
  const Nearest n = nearest(p, hint);
  return finish(n.point, n.triangle);
}

Projection SurfaceModel::project_on_curve(int curve, const Vec3& p) const {
  const Curve& c = *curves_[curve];
  const mesh::SegmentLocator::Hit hit = c.locator->closest(p);
  const auto [a, b] = c.segments[hit.segment];
  Projection out;
  out.point = hit.point;
  const Sym3 logs[2] = {logs_[a], logs_[b]};
  const double weights[2] = {1.0 - hit.t, hit.t};
  out.metric = sizing::interpolate_logs(logs, weights, 2);
  return out;
}

}  // namespace vesselmesh::remesh
