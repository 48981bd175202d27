#include "remesh/surface_model.h"

#include "analysis/normals.h"
#include "mesh/error.h"
#include "mesh/geometry.h"
#include "sizing/metric.h"

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

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

// Phong tessellation with shape factor 1/2 at weights l of corners v with normals n (zero: no
// bulge from that corner): q + 1/2 sum_i l_i n_i n_i^T (v_i - q), q the flat point. The one formula
// of the patches, their edges (a zero weight) and the Gauss-Newton steps.
Vec3 phong(const std::array<Vec3, 3>& v, const std::array<Vec3, 3>& n, const Vec3& l) {
  const Vec3 q = l[0] * v[0] + l[1] * v[1] + l[2] * v[2];
  Vec3 s = q;
  for (int i = 0; i < 3; ++i) s += 0.5 * l[i] * Vec3(n[i].dot(v[i] - q) * n[i]);
  return s;
}

// Its derivatives along l1 and l2 (l0 = 1 - l1 - l2): dq/dl_k = v_k - v0, and each corner's term
// n_i n_i^T (v_i - q) changes by -n_i n_i^T dq.
void phong_tangents(const std::array<Vec3, 3>& v, const std::array<Vec3, 3>& n, const Vec3& l, Vec3& su, Vec3& sv) {
  const Vec3 q = l[0] * v[0] + l[1] * v[1] + l[2] * v[2];
  Vec3 d[3];
  for (int i = 0; i < 3; ++i) d[i] = n[i].dot(v[i] - q) * n[i];
  for (int k = 1; k <= 2; ++k) {
    const Vec3 e = v[k] - v[0];
    Vec3 ds = e + 0.5 * (d[k] - d[0]);
    for (int i = 0; i < 3; ++i) ds -= 0.5 * l[i] * n[i].dot(e) * n[i];
    (k == 1 ? su : sv) = ds;
  }
}

}  // namespace

SurfaceModel::SurfaceModel(const TriMesh& input, const std::vector<Sym3>& metrics, const FeatureOptions& options,
                           Reconstruction reconstruction)
    : SurfaceModel(input, metrics, analysis::detect_features(input, options), reconstruction) {}

SurfaceModel::SurfaceModel(const TriMesh& input, const std::vector<Sym3>& metrics, analysis::Features features,
                           Reconstruction reconstruction)
    : input_(input), reconstruction_(reconstruction), metrics_(metrics), locator_(input), incidence_(mesh::build_vertex_triangles(input)),
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
  const mesh::EdgeMap& edges = features_.edges;
  // Phong's normals: the quadric fit's (second order on irregular meshes; a face-weighted mean
  // is first order, and the patch's bulge is only as good as its normals: on a jittered coarse
  // sphere the area-weighted ones leave it a third of the facets' depth off, the fitted ones a
  // tenth or less). The points on a crease or a label border keep the facets along it (both
  // sides meet there); an open end's rim, with one side only, follows the surface (a coarse end's
  // polygon becomes the vessel's section: its radius no longer the inscribed polygon's).
  if (reconstruction_ == Reconstruction::phong) {
    fitted_normals_ = analysis::vertex_normals(input);
    rigid_.assign(input.points.size(), 0);
    for (int e = 0; e < edges.num_edges(); ++e)
      if (features_.curve_of_edge[e] >= 0 && !edges.is_boundary(e)) rigid_[edges.edges[e][0]] = rigid_[edges.edges[e][1]] = 1;
    in_rim_planes(edges);
    // How far each patch strays from its facet at most: |S - q| <= 1/2 max_i |n_i . (v_i - q)|,
    // and q is a mean of the corners.
    bulge_.assign(input.triangles.size(), 0.0);
    for (int t = 0; t < input.num_triangles(); ++t) {
      const Triangle& g = input.triangles[t];
      const std::array<Vec3, 3> n = corner_normals(t);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          bulge_[t] = std::max(bulge_[t], 0.5 * std::abs(n[i].dot(input.points[g[i]] - input.points[g[j]])));
    }
  }
  curves_.resize(features_.num_curves);
  for (auto& curve : curves_) curve = std::make_unique<Curve>();
  for (int e = 0; e < edges.num_edges(); ++e)
    if (features_.curve_of_edge[e] >= 0) curves_[features_.curve_of_edge[e]]->segments.push_back(edges.edges[e]);
  for (auto& curve : curves_) {
    std::vector<std::array<Vec3, 2>> segments;
    for (const auto& s : curve->segments) segments.push_back({input.points[s[0]], input.points[s[1]]});
    curve->locator = std::make_unique<mesh::SegmentLocator>(segments);
  }
}

SurfaceModel::~SurfaceModel() = default;

// An open end is a cut, its rim in a plane: the rim points' normals are turned into the plane of
// their curve (the least-squares plane of its points; none for a straight one), so that its
// points, moved along them, stay in it (the one-sided fit tilts them by a little).
void SurfaceModel::in_rim_planes(const mesh::EdgeMap& edges) {
  std::vector<std::vector<int>> rim(features_.num_curves);
  std::vector<char> open(features_.num_curves, 1);
  for (int e = 0; e < edges.num_edges(); ++e) {
    const int c = features_.curve_of_edge[e];
    if (c < 0) continue;
    if (!edges.is_boundary(e)) open[c] = 0;
    rim[c].push_back(edges.edges[e][0]);
    rim[c].push_back(edges.edges[e][1]);
  }
  for (int c = 0; c < features_.num_curves; ++c) {
    if (!open[c]) continue;
    std::sort(rim[c].begin(), rim[c].end());
    rim[c].erase(std::unique(rim[c].begin(), rim[c].end()), rim[c].end());
    Vec3 centre = Vec3::Zero();
    for (int v : rim[c]) centre += input_.points[v];
    centre /= static_cast<double>(rim[c].size());
    Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
    for (int v : rim[c]) spread += (input_.points[v] - centre) * (input_.points[v] - centre).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(spread);
    if (!(eigen.eigenvalues()[1] > 1e-6 * eigen.eigenvalues()[2])) continue;  // a straight rim
    const Vec3 axis = eigen.eigenvectors().col(0);
    for (int v : rim[c]) {
      Vec3& n = fitted_normals_[v];
      n -= n.dot(axis) * axis;
      if (n.squaredNorm() > 0.0) n.normalize();
    }
  }
}

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

Projection SurfaceModel::finish(const Vec3& point, int triangle, const Vec3& l) const {
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

std::array<Vec3, 3> SurfaceModel::corner_normals(int t) const {
  std::array<Vec3, 3> n;
  for (int i = 0; i < 3; ++i) {
    const int v = input_.triangles[t][i];
    n[i] = rigid_[v] ? Vec3::Zero() : fitted_normals_[v];
  }
  return n;
}

Vec3 SurfaceModel::surface_point(int t, const Vec3& l) const {
  const Triangle& f = input_.triangles[t];
  const std::array<Vec3, 3> v = {input_.points[f[0]], input_.points[f[1]], input_.points[f[2]]};
  if (reconstruction_ == Reconstruction::facets) return l[0] * v[0] + l[1] * v[1] + l[2] * v[2];
  return phong(v, corner_normals(t), l);
}

// Gauss-Newton on |p - S(l)|^2 over the triangle's barycentric coordinates (l1, l2 free, l0 =
// 1 - l1 - l2), each step clamped to the triangle; S is quadratic in l, so from the flat
// triangle's closest point (off by the patch's displacement, a small fraction of the edge) a few
// steps converge. A sliver's ill-conditioned steps stop it where it is.
SurfaceModel::OnPatch SurfaceModel::onto_patch(const Vec3& p, const Nearest& facet) const {
  const Triangle& f = input_.triangles[facet.triangle];
  const std::array<Vec3, 3> v = {input_.points[f[0]], input_.points[f[1]], input_.points[f[2]]};
  Vec3 l = barycentric(v[0], v[1], v[2], facet.point);
  if (reconstruction_ == Reconstruction::facets) return {facet.point, l};
  const std::array<Vec3, 3> n = corner_normals(facet.triangle);
  if (n[0].squaredNorm() + n[1].squaredNorm() + n[2].squaredNorm() == 0.0) return {facet.point, l};
  Vec3 s = phong(v, n, l);
  for (int it = 0; it < 4; ++it) {
    Vec3 su, sv;
    phong_tangents(v, n, l, su, sv);
    const Vec3 r = p - s;
    const double a = su.dot(su), b = su.dot(sv), c = sv.dot(sv);
    const double det = a * c - b * b;
    if (!(det > 1e-12 * (a + c) * (a + c))) break;
    const double gu = su.dot(r), gv = sv.dot(r);
    const double du = (c * gu - b * gv) / det, dv = (a * gv - b * gu) / det;
    Vec3 next(l[0] - du - dv, l[1] + du, l[2] + dv);
    next = next.cwiseMax(0.0);
    next /= next.sum();
    const Vec3 moved = phong(v, n, next);
    if ((p - moved).squaredNorm() > r.squaredNorm()) break;  // clamped against the triangle's edge
    const bool settled = (moved - s).squaredNorm() <= 1e-24 * (a + c);
    l = next;
    s = moved;
    if (settled) break;
  }
  return {s, l};
}

// The patch of the closest triangle, or, when its closest point sits on the triangle's rim
// (the smooth surface's closest point may lie across it), the best of the patches around that
// edge or point, each from its own triangle's closest point. With `whole_ring`, every patch round
// the triangle's corners that may hold a closer point still: where the input creases without a
// feature curve, a neighbour's patch bulges past the closest triangle's (measured on the capped
// SimVascular aorta's 60-degree folds, facets of 1-4.7 mm: a point 0.19 mm from the closest
// facet's patch lay 0.016 mm from its neighbour's). A patch lies within bulge_ of its facet, so
// a neighbour whose facet is farther than that from the best point so far is skipped unread.
SurfaceModel::OnPatch SurfaceModel::onto_surface(const Vec3& p, Nearest& facet, bool whole_ring) const {
  OnPatch best = onto_patch(p, facet);
  if (reconstruction_ == Reconstruction::facets) return best;
  const int from = facet.triangle;
  const Triangle f = input_.triangles[from];
  double best_d = (best.point - p).squaredNorm();
  const auto try_patch = [&](int u) {
    const double reach = std::sqrt(best_d) + bulge_[u];
    const Sphere& sphere = spheres_[u];  // first the sphere round the facet: cheaper than its closest point
    if ((p - sphere.center).squaredNorm() >= (reach + sphere.radius) * (reach + sphere.radius)) return;
    const Triangle& g = input_.triangles[u];
    const Nearest other{mesh::closest_point_on_triangle(p, input_.points[g[0]], input_.points[g[1]], input_.points[g[2]]),
                        u};
    if ((other.point - p).squaredNorm() >= reach * reach) return;
    const OnPatch on = onto_patch(p, other);
    const double d = (on.point - p).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best = on;
      facet = other;
    }
  };
  if (whole_ring) {
    for (int v : f)
      for (int u : incidence_.of(v))
        if (u != from) try_patch(u);
    return best;
  }
  int inside[3], count = 0;
  for (int i = 0; i < 3; ++i)
    if (best.barycentric[i] > 1e-9) inside[count++] = f[i];
  if (count == 3) return best;
  for (int u : incidence_.of(inside[0])) {
    const Triangle& g = input_.triangles[u];
    if (u != from && (count == 1 || std::find(g.begin(), g.end(), inside[1]) != g.end())) try_patch(u);
  }
  return best;
}

SurfaceModel::Nearest SurfaceModel::nearest(const Vec3& p, int hint, bool whole_ring) const {
  Nearest facet = nearest_facet(p, hint);
  return {onto_surface(p, facet, whole_ring).point, facet.triangle};
}

SurfaceModel::Nearest SurfaceModel::nearest_facet(const Vec3& p, int hint) const {
  if (hint >= 0) {
    const Nearest local = walk(p, hint);
    if (local.triangle >= 0) return local;
  }
  const mesh::SurfaceLocator::Hit hit = locator_.closest(p);
  return {hit.point, hit.triangle};
}

Projection SurfaceModel::project(const Vec3& p, int hint, bool whole_ring) const {
  Nearest facet = nearest_facet(p, hint);
  const OnPatch on = onto_surface(p, facet, whole_ring);
  return finish(on.point, facet.triangle, on.barycentric);
}

Projection SurfaceModel::project_on_curve(int curve, const Vec3& p) const {
  const Curve& c = *curves_[curve];
  const mesh::SegmentLocator::Hit hit = c.locator->closest(p);
  const auto [a, b] = c.segments[hit.segment];
  Projection out;
  out.point = hit.point;
  if (reconstruction_ == Reconstruction::phong) {
    // On the smooth surface's edge between a and b (what the patch of the triangle on it gives
    // there: only a's and b's normals count on an edge); zero on a crease or label border.
    // (phong() on the edge, l = (1 - t, t), written out: the same point to the last bit as the
    // tests' figures were measured with.)
    const Vec3 q = hit.point;
    const Vec3 na = rigid_[a] ? Vec3::Zero() : fitted_normals_[a], nb = rigid_[b] ? Vec3::Zero() : fitted_normals_[b];
    out.point += 0.5 * ((1.0 - hit.t) * na.dot(input_.points[a] - q) * na + hit.t * nb.dot(input_.points[b] - q) * nb);
  }
  const Sym3 logs[2] = {logs_[a], logs_[b]};
  const double weights[2] = {1.0 - hit.t, hit.t};
  out.metric = sizing::interpolate_logs(logs, weights, 2);
  return out;
}

std::vector<Sym3> carry_metric(const TriMesh& from, const std::vector<Sym3>& metrics, const TriMesh& to,
                               const std::string& what) {
  const SurfaceModel field(from, metrics, FeatureOptions{});
  std::vector<Sym3> out(to.points.size());
  double farthest = 0.0;
  for (size_t v = 0; v < out.size(); ++v) {
    const Projection p = field.project(to.points[v]);
    farthest = std::max(farthest, (p.point - to.points[v]).norm());
    out[v] = p.metric;
  }
  const auto box = mesh::bounding_box(to.points);
  if (farthest > 0.01 * (box[1] - box[0]).norm())
    throw InputError(fmt::format("{} lies up to {:.3g} mm from the surface to remesh: it belongs to another surface "
                                 "or vessel (or is in another unit: see --units)",
                                 what, farthest));
  return out;
}

}  // namespace vesselmesh::remesh
