#include "post/ring.h"

#include "mesh/clean.h"
#include "mesh/error.h"
#include "mesh/locator.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

namespace vesselmesh::post {
namespace {

struct Crossing {
  Vec3 point;
  Vec3 value;
  std::vector<int> neighbours;  // crossings joined by a segment
};

// Chains the crossing graph (each node of degree 1 or 2) into paths; a closed loop repeats no node.
std::vector<std::pair<std::vector<int>, bool>> chain(const std::vector<Crossing>& nodes) {
  std::vector<std::pair<std::vector<int>, bool>> paths;
  std::vector<char> used(nodes.size(), 0);
  const auto walk = [&](int start) {
    std::vector<int> path = {start};
    used[start] = 1;
    int previous = -1, current = start;
    for (;;) {
      int next = -1;
      for (int n : nodes[current].neighbours)
        if (n != previous && !used[n]) {
          next = n;
          break;
        }
      if (next < 0) break;
      used[next] = 1;
      path.push_back(next);
      previous = current;
      current = next;
    }
    const bool closed = path.size() > 2 && std::find(nodes[current].neighbours.begin(),
                                                     nodes[current].neighbours.end(), start) !=
                                               nodes[current].neighbours.end();
    paths.emplace_back(std::move(path), closed);
  };
  for (size_t i = 0; i < nodes.size(); ++i)  // open paths first, from an end
    if (!used[i] && nodes[i].neighbours.size() == 1) walk(static_cast<int>(i));
  for (size_t i = 0; i < nodes.size(); ++i)
    if (!used[i]) walk(static_cast<int>(i));
  return paths;
}

Vec3 default_reference(const Vec3& n) {
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(n[k]) < std::abs(n[axis])) axis = k;
  return Vec3::Unit(axis);
}

}  // namespace

RingSpec centerline_ring(const centerline::Centerlines& centerlines, const std::string& name, const Vec3& near) {
  RingSpec spec;
  spec.name = name;
  double best = std::numeric_limits<double>::infinity();
  for (const centerline::Branch& b : centerlines.branches) {
    const std::vector<Vec3>& p = b.points;
    for (size_t k = 0; k + 1 < p.size(); ++k) {
      const Vec3 d = p[k + 1] - p[k];
      const double t = d.squaredNorm() > 0.0 ? std::clamp((near - p[k]).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
      const Vec3 foot = p[k] + t * d;
      const double distance = (near - foot).norm();
      if (distance >= best) continue;
      best = distance;
      spec.point = foot;
      // The direction over the neighbouring segments, so that a kink does not tilt the plane.
      const size_t lo = k > 0 ? k - 1 : k, hi = std::min(p.size() - 1, k + 2);
      spec.normal = (p[hi] - p[lo]).normalized();
    }
  }
  if (!std::isfinite(best)) throw InputError(fmt::format("ring {}: no centerline to place it on", name));
  return spec;
}

std::vector<RingSpec> place_rings(const TriMesh& surface, const std::vector<RingRequest>& requests,
                                  const Reporter& reporter) {
  std::optional<centerline::Centerlines> centerlines;
  std::vector<RingSpec> specs;
  for (const RingRequest& request : requests) {
    if (!request.on_centerline) {
      specs.push_back(request.spec);
      continue;
    }
    if (!centerlines) {
      reporter.info("centerlines of the wall, for rings placed on them");
      TriMesh clean = surface;
      mesh::clean(clean);
      centerlines = centerline::extract(clean, {}, reporter);
    }
    RingSpec spec = centerline_ring(*centerlines, request.spec.name, request.spec.point);
    spec.reference = request.spec.reference;
    specs.push_back(spec);
  }
  return specs;
}

Ring cut_ring(const TriMesh& wall, const std::vector<Vec3>& values, const RingSpec& spec) {
  if (values.size() != wall.points.size())
    throw InputError(fmt::format("ring {}: {} values for {} wall points", spec.name, values.size(), wall.points.size()));
  if (!(spec.normal.norm() > 0.0)) throw InputError(fmt::format("ring {}: the plane's normal is zero", spec.name));
  const Vec3 n = spec.normal.normalized();
  std::vector<double> side(wall.points.size());
  for (size_t i = 0; i < side.size(); ++i) side[i] = (wall.points[i] - spec.point).dot(n);
  const auto above = [&](int v) { return side[v] >= 0.0; };

  std::vector<Crossing> nodes;
  std::map<std::pair<int, int>, int> node_of_edge;
  const auto crossing = [&](int a, int b) {
    const std::pair<int, int> key = std::minmax(a, b);
    const auto [it, fresh] = node_of_edge.try_emplace(key, static_cast<int>(nodes.size()));
    if (fresh) {
      const auto [lo, hi] = key;
      const double t = side[lo] / (side[lo] - side[hi]);
      nodes.push_back({wall.points[lo] + t * (wall.points[hi] - wall.points[lo]),
                       values[lo] + t * (values[hi] - values[lo]), {}});
    }
    return it->second;
  };
  for (const Triangle& tri : wall.triangles) {
    std::vector<int> ends;
    for (int k = 0; k < 3; ++k) {
      const int a = tri[k], b = tri[(k + 1) % 3];
      if (above(a) != above(b)) ends.push_back(crossing(a, b));
    }
    if (ends.size() != 2) continue;
    nodes[ends[0]].neighbours.push_back(ends[1]);
    nodes[ends[1]].neighbours.push_back(ends[0]);
  }
  if (nodes.empty())
    throw InputError(fmt::format("ring {}: the plane through ({:.4g}, {:.4g}, {:.4g}) with normal ({:.3g}, {:.3g}, "
                                 "{:.3g}) does not cut the wall",
                                 spec.name, spec.point.x(), spec.point.y(), spec.point.z(), n.x(), n.y(), n.z()));

  auto paths = chain(nodes);
  // The loop nearest the plane's point: the least distance to its segments' points.
  size_t best = 0;
  double best_distance = std::numeric_limits<double>::infinity();
  for (size_t p = 0; p < paths.size(); ++p) {
    if (paths[p].first.size() < 2) continue;
    for (int v : paths[p].first) {
      const double d = (nodes[v].point - spec.point).norm();
      if (d < best_distance) {
        best_distance = d;
        best = p;
      }
    }
  }
  std::vector<int> path = paths[best].first;
  Ring ring;
  ring.name = spec.name;
  ring.normal = n;
  ring.closed = paths[best].second;
  for (size_t p = 0; p < paths.size(); ++p) ring.other_loops += (p != best && paths[p].first.size() >= 2);
  if (path.size() < 2)
    throw InputError(fmt::format("ring {}: the plane only touches the wall at one point", spec.name));

  // Centroid by segment length, orientation counter-clockwise about n.
  const size_t segments = ring.closed ? path.size() : path.size() - 1;
  Vec3 centroid = Vec3::Zero();
  double total = 0.0;
  for (size_t k = 0; k < segments; ++k) {
    const Vec3& a = nodes[path[k]].point;
    const Vec3& b = nodes[path[(k + 1) % path.size()]].point;
    centroid += (b - a).norm() * 0.5 * (a + b);
    total += (b - a).norm();
  }
  centroid = total > 0.0 ? Vec3(centroid / total) : nodes[path[0]].point;
  double turning = 0.0;
  for (size_t k = 0; k < segments; ++k)
    turning += (nodes[path[k]].point - centroid).cross(nodes[path[(k + 1) % path.size()]].point - centroid).dot(n);
  if (turning < 0.0) std::reverse(path.begin(), path.end());
  ring.centroid = centroid;

  Vec3 e1 = spec.reference.value_or(default_reference(n));
  e1 -= e1.dot(n) * n;
  if (!(e1.norm() > 1e-12)) throw InputError(fmt::format("ring {}: the reference direction is along the normal", spec.name));
  e1.normalize();
  const Vec3 e2 = n.cross(e1);
  const auto angle_of = [&](const Vec3& p) { return std::atan2((p - centroid).dot(e2), (p - centroid).dot(e1)); };

  // Closed: start where the angle passes zero going counter-clockwise (split the segment there).
  std::vector<std::pair<Vec3, Vec3>> points;  // position, value
  for (int v : path) points.emplace_back(nodes[v].point, nodes[v].value);
  bool found = false;  // closed and started where the angle passes zero
  if (ring.closed) {
    size_t start = 0;
    for (size_t k = 0; k < points.size() && !found; ++k) {
      const auto& a = points[k];
      const auto& b = points[(k + 1) % points.size()];
      const double ta = angle_of(a.first), tb = angle_of(b.first);
      if (ta < 0.0 && tb >= 0.0 && tb - ta < std::numbers::pi) {
        // Where the chord meets the half-plane of angle zero.
        const double da = (a.first - centroid).dot(e2), db = (b.first - centroid).dot(e2);
        const double t = da < db ? -da / (db - da) : 1.0;
        found = true;
        if (t > 1.0 - 1e-12) {  // the zero lies on b itself
          start = (k + 1) % points.size();
          break;
        }
        const std::pair<Vec3, Vec3> cut = {a.first + t * (b.first - a.first), a.second + t * (b.second - a.second)};
        points.insert(points.begin() + static_cast<long>(k) + 1, cut);
        start = k + 1;
      }
    }
    std::rotate(points.begin(), points.begin() + static_cast<long>(start), points.end());
    points.push_back(points.front());
  }
  double s = 0.0;
  for (size_t k = 0; k < points.size(); ++k) {
    if (k > 0) s += (points[k].first - points[k - 1].first).norm();
    RingSample sample;
    sample.arc_length = s;
    double angle = angle_of(points[k].first) * 180.0 / std::numbers::pi;
    if (angle < 0.0) angle += 360.0;
    if (found && k == 0) angle = 0.0;  // the start: where the angle passes zero
    if (found && k + 1 == points.size()) angle = 360.0;
    sample.angle = angle;
    sample.point = points[k].first;
    sample.value = points[k].second;
    Vec3 radial = points[k].first - centroid;
    radial -= radial.dot(n) * n;
    const Vec3 tangent = radial.norm() > 0.0 ? Vec3(n.cross(radial).normalized()) : Vec3::Zero();
    sample.axial = sample.value.dot(n);
    sample.circumferential = sample.value.dot(tangent);
    sample.magnitude = sample.value.norm();
    ring.samples.push_back(sample);
  }
  ring.length = s;
  for (size_t k = 1; k < ring.samples.size(); ++k)
    if (ring.samples[k].magnitude < ring.samples[ring.minimum].magnitude) ring.minimum = static_cast<int>(k);
  return ring;
}

std::vector<PointProbe> probe_points(const TriMesh& wall, const std::vector<Vec3>& values,
                                     const std::vector<PointSpec>& points) {
  std::vector<PointProbe> probes;
  if (points.empty()) return probes;
  const mesh::SurfaceLocator locator(wall);
  for (const PointSpec& spec : points) {
    const mesh::SurfaceLocator::Hit hit = locator.closest(spec.point);
    PointProbe probe;
    probe.name = spec.name;
    probe.requested = spec.point;
    probe.point = hit.point;
    probe.distance = hit.distance;
    probe.triangle = hit.triangle;
    const Triangle& tri = wall.triangles[hit.triangle];
    const Vec3 &a = wall.points[tri[0]], &b = wall.points[tri[1]], &c = wall.points[tri[2]];
    const Vec3 normal = (b - a).cross(c - a);
    const double area = normal.squaredNorm();
    if (area > 0.0) {  // barycentric weights of the hit
      const double wa = (c - b).cross(hit.point - b).dot(normal) / area;
      const double wb = (a - c).cross(hit.point - c).dot(normal) / area;
      probe.value = wa * values[tri[0]] + wb * values[tri[1]] + (1.0 - wa - wb) * values[tri[2]];
    } else {
      probe.value = (values[tri[0]] + values[tri[1]] + values[tri[2]]) / 3.0;
    }
    probes.push_back(probe);
  }
  return probes;
}

std::vector<double> resampled_magnitude(const Ring& ring, int count) {
  std::vector<double> at(ring.samples.size()), value(ring.samples.size());
  for (size_t k = 0; k < ring.samples.size(); ++k) {
    at[k] = ring.closed ? ring.samples[k].angle : ring.samples[k].arc_length / std::max(ring.length, 1e-300);
    value[k] = ring.samples[k].magnitude;
  }
  std::vector<size_t> order(at.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return at[a] < at[b]; });
  const double period = ring.closed ? 360.0 : 1.0;
  std::vector<double> out(count, NAN);
  if (order.empty()) return out;
  for (int i = 0; i < count; ++i) {
    const double x = period * i / count;
    // The first sample at or after x (wrapping on a closed ring).
    const auto it = std::lower_bound(order.begin(), order.end(), x, [&](size_t k, double v) { return at[k] < v; });
    size_t hi = it == order.end() ? order.front() : *it;
    size_t lo = it == order.begin() ? order.back() : *(it - 1);
    double x_lo = at[lo], x_hi = at[hi];
    if (it == order.begin()) x_lo -= ring.closed ? period : 0.0;
    if (it == order.end()) x_hi += ring.closed ? period : 0.0;
    const double w = x_hi > x_lo ? std::clamp((x - x_lo) / (x_hi - x_lo), 0.0, 1.0) : 0.0;
    out[i] = (1.0 - w) * value[lo] + w * value[hi];
  }
  return out;
}

}  // namespace vesselmesh::post
