#include "volume/boundary_layer.h"

#include "analysis/normals.h"
#include "mesh/connectivity.h"
#include "mesh/error.h"
#include "mesh/geometry.h"
#include "mesh/self_intersections.h"
#include "sizing/gradation.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace vesselmesh::volume {
namespace {

void check_options(const BoundaryLayerOptions& o) {
  if (o.layers < 1 || o.layers > 100) throw OptionError(fmt::format("--layers {}: give 1 to 100 layers", o.layers));
  if (!(o.thickness_ratio > 0.0 && o.thickness_ratio <= 0.5))
    throw OptionError(fmt::format("--thickness-ratio {}: give a fraction of the radius in (0, 0.5]", o.thickness_ratio));
  if (!(o.growth >= 0.2 && o.growth <= 5.0))
    throw OptionError(fmt::format("--growth {}: give a ratio of successive layer heights in [0.2, 5]", o.growth));
  if (o.normal_smoothing < 0) throw OptionError("normal smoothing passes must be >= 0");
  if (!(o.shrink_slope > 0.0)) throw OptionError("the shrink slope must be > 0");
  if (!(o.min_thickness_fraction > 0.0 && o.min_thickness_fraction < 1.0))
    throw OptionError("the least thickness fraction must be in (0, 1)");
  if (!(o.min_angle_deg >= 0.0 && o.min_angle_deg <= 30.0))
    throw OptionError(fmt::format("--layer-angle {}: give an angle in [0, 30] degrees (0: no thickening)", o.min_angle_deg));
  if (!(o.split_angle_deg >= 0.0 && o.split_angle_deg <= 30.0))
    throw OptionError(fmt::format("--layer-split-angle {}: give an angle in [0, 30] degrees (0: no splits)", o.split_angle_deg));
}

// Per wall point: the unit normal of its end's plane for loop points, zero elsewhere.
std::vector<Vec3> end_planes(int n, const std::vector<WallEnd>& ends) {
  std::vector<Vec3> plane(n, Vec3::Zero());
  for (const WallEnd& end : ends)
    for (int v : end.loop) plane[v] = end.normal.normalized();
  return plane;
}

// Smoothed inward directions: Max normals, averaged over the one-ring, turned into the end's
// plane on an end's loop.
std::vector<Vec3> column_directions(const TriMesh& wall, const mesh::EdgeMap& edges, const std::vector<Vec3>& plane,
                                    int passes) {
  const int n = wall.num_points();
  std::vector<Vec3> normal = analysis::vertex_normals(wall, analysis::NormalMethod::max);
  auto into_plane = [&](std::vector<Vec3>& dirs) {
    for (int v = 0; v < n; ++v) {
      if (plane[v].squaredNorm() > 0) dirs[v] -= dirs[v].dot(plane[v]) * plane[v];
      const double len = dirs[v].norm();
      if (len > 0) dirs[v] /= len;
    }
  };
  into_plane(normal);
  for (int pass = 0; pass < passes; ++pass) {
    std::vector<Vec3> sum = normal;
    for (const auto& [a, b] : edges.edges) {
      sum[a] += normal[b];
      sum[b] += normal[a];
    }
    into_plane(sum);
    normal.swap(sum);
  }
  for (int v = 0; v < n; ++v) {
    if (!(normal[v].squaredNorm() > 0.5))
      throw InputError(fmt::format("the wall has no normal at point {} {}: a degenerate or folded neighbourhood; "
                                   "remesh the surface first",
                                   v, mesh::format_point(wall.points[v])));
    normal[v] = -normal[v];
  }
  return normal;
}

// Per wall vertex: the thickness under which its prisms' tetrahedra fall below `angle_deg`. A
// prism of height h over a triangle whose largest altitude is a splits into tetrahedra whose
// least dihedral angle is atan(h / a) when the column stands straight; a column leaning from
// the triangle's normal shortens h by the cosine. The thinnest layer counts.
std::vector<double> angle_floors(const TriMesh& wall, const std::vector<Vec3>& direction,
                                 const std::vector<double>& fraction, int levels, double angle_deg) {
  std::vector<double> floor(wall.num_points(), 0.0);
  if (!(angle_deg > 0.0)) return floor;
  std::vector<double> slope(wall.num_points());  // per point: its thinnest layer's share of the thickness
  for (int v = 0; v < wall.num_points(); ++v) {
    double step = 1.0;
    for (int k = 0; k + 1 < levels; ++k) step = std::min(step, fraction[v * levels + k + 1] - fraction[v * levels + k]);
    slope[v] = std::tan(angle_deg * std::numbers::pi / 180.0) / step;
  }
  for (const Triangle& f : wall.triangles) {
    const Vec3 cross = (wall.points[f[1]] - wall.points[f[0]]).cross(wall.points[f[2]] - wall.points[f[0]]);
    double shortest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) shortest = std::min(shortest, (wall.points[f[(i + 1) % 3]] - wall.points[f[i]]).norm());
    if (!(cross.norm() > 0.0 && shortest > 0.0)) continue;
    const double altitude = cross.norm() / shortest;
    const Vec3 inward = -cross.normalized();
    for (int v : f) floor[v] = std::max(floor[v], slope[v] * altitude / std::max(0.3, direction[v].dot(inward)));
  }
  return floor;
}

// The first height asked (options.first_height, graded along the wall at the shrink's slope) where it
// is below the first layer's: the layers at that point grow from it by the growth that fills the
// thickness in as many layers, up to kMostFirstGrowth; beyond that, the thickness too is cut to what
// that growth fills from it. Points so changed: out.capped_vertices.
constexpr double kMostFirstGrowth = 2.0;
void first_heights(const TriMesh& wall, const BoundaryLayerOptions& options, double slope_growth, BoundaryLayer& out,
                   std::vector<double>& fraction) {
  const int n = wall.num_points(), levels = out.levels;
  std::vector<double> asked(n, 1e300);
  for (int v = 0; v < n; ++v)
    if (const double h = options.first_height(wall.points[v]); h > 0.0 && std::isfinite(h)) asked[v] = h;
  sizing::grade_sizes(wall, asked, slope_growth);
  // The first layer's share of the thickness at growth g: (g - 1) / (g^N - 1), 1 / N at g = 1.
  const auto first_share = [N = options.layers](double g) {
    return g == 1.0 ? 1.0 / N : (g - 1.0) / (std::pow(g, N) - 1.0);
  };
  const double least_share = first_share(kMostFirstGrowth);
  for (int v = 0; v < n; ++v) {
    const double share = asked[v] / out.target[v];
    if (!(share < fraction[v * levels + 1] * (1.0 - 1e-9))) continue;
    ++out.capped_vertices;
    double g = kMostFirstGrowth;
    if (share > least_share) {  // the first share falls as the growth rises: bisection
      double low = std::max(options.growth, 1.0), high = kMostFirstGrowth;
      for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (low + high);
        (first_share(mid) > share ? low : high) = mid;
      }
      g = 0.5 * (low + high);
    } else {
      out.target[v] = asked[v] / least_share;
    }
    const std::vector<double> f = layer_fractions(options.layers, g);
    std::copy(f.begin(), f.end(), fraction.begin() + v * levels);
  }
}

// The prism over wall triangle f between levels k and k + 1 (n wall points a level).
Prism prism_between(int n, const Triangle& f, int k) {
  return {k * n + f[0], k * n + f[1], k * n + f[2], (k + 1) * n + f[0], (k + 1) * n + f[1], (k + 1) * n + f[2]};
}

// Per prism, wall triangle by wall triangle and level by level (the order of BoundaryLayer::prisms): the
// least dihedral angle (degrees) of its tetrahedra, the levels' points as `points` has them.
std::vector<double> prism_angles(const TriMesh& wall, const std::vector<Vec3>& points, int levels) {
  const int n = wall.num_points(), layers = levels - 1;
  std::vector<double> angle(wall.triangles.size() * layers);
  for (size_t t = 0; t < wall.triangles.size(); ++t)
    for (int k = 0; k < layers; ++k) {
      double least = 180.0;
      for (const Tet& c : mesh::split_prism(prism_between(n, wall.triangles[t], k)))
        least = std::min(least, mesh::least_dihedral_angle(points[c[0]], points[c[1]], points[c[2]], points[c[3]]) *
                                    180.0 / std::numbers::pi);
      angle[t * layers + k] = least;
    }
  return angle;
}

// The strips at the ends: side quads (u_k, u_k+1, v_k+1, v_k) of each loop edge u -> v, cut along the
// diagonal through their least index, as the prisms beside them are; and the inner loops.
void build_strips(const std::vector<WallEnd>& ends, int n, int levels, BoundaryLayer& out) {
  out.end_strips.assign(ends.size(), {});
  out.inner_loops.assign(ends.size(), {});
  for (size_t e = 0; e < ends.size(); ++e) {
    const std::vector<int>& loop = ends[e].loop;
    for (size_t i = 0; i < loop.size(); ++i) {
      const int u = loop[i], v = loop[(i + 1) % loop.size()];
      for (int k = 0; k + 1 < levels; ++k) {
        const int u0 = k * n + u, u1 = (k + 1) * n + u, v0 = k * n + v, v1 = (k + 1) * n + v;
        if (std::min(u0, v1) < std::min(u1, v0)) {
          out.end_strips[e].push_back({u0, u1, v1});
          out.end_strips[e].push_back({u0, v1, v0});
        } else {
          out.end_strips[e].push_back({u0, u1, v0});
          out.end_strips[e].push_back({u1, v1, v0});
        }
      }
      out.inner_loops[e].push_back((levels - 1) * n + u);
    }
  }
}

// A column nearly tangent to one of its triangles (direction d at wall point v, `plane` its end's plane
// normal or zero) turned toward that triangle's normal, in steps, until every
// triangle around sees it at 0.3 or more.
void turn_toward_visible(const TriMesh& wall, const mesh::VertexTriangles& around, int v, const Vec3& plane, Vec3& d) {
  for (int step = 0; step < 20; ++step) {
    double least = 1.0;
    Vec3 worst = Vec3::Zero();
    for (int t : around.of(v)) {
      const Triangle& f = wall.triangles[t];
      const Vec3 inward =
          -(wall.points[f[1]] - wall.points[f[0]]).cross(wall.points[f[2]] - wall.points[f[0]]).normalized();
      if (inward.allFinite() && d.dot(inward) < least) least = d.dot(inward), worst = inward;
    }
    if (least >= 0.3) return;
    Vec3 turned = d + 0.5 * worst;
    if (plane.squaredNorm() > 0) turned -= turned.dot(plane) * plane;
    if (!(turned.norm() > 1e-9)) return;
    d = turned.normalized();
  }
}

// The built layer's prisms, inner surface and reports (out.thickness set; `angle` per prism, in
// out.prisms' order: measure_angles in build_boundary_layer).
void record_layer(const TriMesh& wall, const BoundaryLayerOptions& options, const std::vector<double>& angle,
                  BoundaryLayer& out) {
  const int n = wall.num_points(), levels = out.levels, layers = levels - 1;
  for (const Triangle& f : wall.triangles) {
    for (int k = 0; k + 1 < levels; ++k) {
      out.prisms.push_back(prism_between(n, f, k));
      out.prism_layer.push_back(k + 1);
      out.prism_column.push_back(static_cast<int>(&f - wall.triangles.data()));
    }
    out.inner.push_back({(levels - 1) * n + f[0], (levels - 1) * n + f[1], (levels - 1) * n + f[2]});
  }
  for (int v = 0; v < n; ++v) {
    const double kept = out.thickness[v] / out.target[v];
    if (kept < 0.999) ++out.shrunk_vertices;
    if (kept < out.least_fraction) out.least_fraction = kept, out.least_at = wall.points[v];
    if (kept > 1.001) ++out.thickened_vertices;
    if (kept > out.most_fraction) out.most_fraction = kept, out.most_at = wall.points[v];
  }
  out.column_angle.assign(wall.triangles.size(), 180.0);
  for (size_t p = 0; p < angle.size(); ++p) {
    out.column_angle[p / layers] = std::min(out.column_angle[p / layers], angle[p]);
    if (angle[p] < out.least_angle)
      out.least_angle = angle[p], out.least_angle_at = wall.points[wall.triangles[p / layers][0]];
    if (options.min_angle_deg > 0.0 && angle[p] < options.min_angle_deg) ++out.under_angle_prisms;
  }
}


}  // namespace

int split_long_edges(TriMesh& wall, std::vector<double>& radius, const std::vector<int>& triangles) {
  const mesh::EdgeMap edges = mesh::build_edge_map(wall);
  // The edges wanted, the longest first (ties by index, so the order of `triangles` is moot).
  std::vector<std::pair<double, int>> wanted;
  for (int t : triangles) {
    const Triangle& f = wall.triangles[t];
    int best = -1;
    double longest = 0.0;
    for (int i = 0; i < 3; ++i) {
      const int e = edges.triangle_edges[t][i];
      if (e < 0 || edges.valence(e) != 2) continue;  // an end's loop (or a non-manifold edge) stays
      const double length = (wall.points[f[(i + 1) % 3]] - wall.points[f[i]]).norm();
      if (length > longest) longest = length, best = e;
    }
    if (best >= 0) wanted.emplace_back(-longest, best);
  }
  std::sort(wanted.begin(), wanted.end());
  wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
  std::vector<int> split_at(wall.triangles.size(), -1);  // per triangle: the edge it splits
  int count = 0;
  for (const auto& [length, e] : wanted) {
    const auto faces = edges.triangles_of(e);
    if (split_at[faces[0]] >= 0 || split_at[faces[1]] >= 0) continue;
    split_at[faces[0]] = split_at[faces[1]] = e;
    ++count;
  }
  std::vector<int> midpoint(edges.edges.size(), -1);
  const size_t before = wall.triangles.size();
  for (size_t t = 0; t < before; ++t) {
    const int e = split_at[t];
    if (e < 0) continue;
    const auto [a, b] = edges.edges[e];
    if (midpoint[e] < 0) {
      midpoint[e] = wall.num_points();
      wall.points.push_back(0.5 * (wall.points[a] + wall.points[b]));
      radius.push_back(0.5 * (radius[a] + radius[b]));
    }
    const Triangle f = wall.triangles[t];
    const auto& sides = edges.triangle_edges[t];
    const int i = static_cast<int>(std::find(sides.begin(), sides.end(), e) - sides.begin());  // f[i] -> f[i + 1]
    const int p = f[i], q = f[(i + 1) % 3], r = f[(i + 2) % 3], m = midpoint[e];
    wall.triangles[t] = {p, m, r};
    wall.triangles.push_back({m, q, r});
  }
  return count;
}

std::vector<double> layer_fractions(int layers, double growth) {
  std::vector<double> f(layers + 1, 0.0);
  double height = 1.0;
  for (int k = 1; k <= layers; ++k, height *= growth) f[k] = f[k - 1] + height;
  for (double& x : f) x /= f[layers];
  return f;
}

BoundaryLayer build_boundary_layer(const TriMesh& wall, const std::vector<double>& radius,
                                   const std::vector<WallEnd>& ends, const BoundaryLayerOptions& options,
                                   const Reporter& reporter) {
  check_options(options);
  const int n = wall.num_points();
  VM_CHECK(static_cast<int>(radius.size()) == n, "build_boundary_layer: one radius per wall point");
  const mesh::EdgeMap edges = mesh::build_edge_map(wall);
  BoundaryLayer out;
  out.levels = options.layers + 1;
  const std::vector<Vec3> plane = end_planes(n, ends);
  out.direction = column_directions(wall, edges, plane, options.normal_smoothing);
  out.target.resize(n);
  for (int v = 0; v < n; ++v) {
    if (!(radius[v] > 0.0 && std::isfinite(radius[v])))
      throw InputError(fmt::format("no local radius at wall point {} {}: the distance map did not reach it", v,
                                   mesh::format_point(wall.points[v])));
    out.target[v] = options.thickness_ratio * radius[v];
  }
  const int levels = out.levels;
  const std::vector<double> uniform = layer_fractions(options.layers, options.growth);
  // Per wall point its levels' fractions of the thickness (point v's from v x levels): the options'
  // growth, or where a first height is asked below the first layer's, the growth that makes it so.
  std::vector<double> fraction(static_cast<size_t>(n) * levels);
  for (int v = 0; v < n; ++v) std::copy(uniform.begin(), uniform.end(), fraction.begin() + v * levels);
  const double growth = std::exp(options.shrink_slope);
  if (options.first_height) first_heights(wall, options, growth, out, fraction);
  // The thickness to start from: the target, or more where the angle floor asks (5 % above it,
  // spread to the neighbours with the shrink's slope, at most half the radius).
  out.angle_floor = angle_floors(wall, out.direction, fraction, levels, options.min_angle_deg);
  auto start_from = [&](const std::vector<double>& floor) {
    std::vector<double> spread(n), start = out.target;
    for (int v = 0; v < n; ++v) spread[v] = -1.05 * floor[v];
    sizing::grade_sizes(wall, spread, growth);
    for (int v = 0; v < n; ++v) start[v] = std::max(start[v], std::min(-spread[v], 0.5 * radius[v]));
    return start;
  };
  out.points.resize(static_cast<size_t>(levels) * n);
  auto level_prism = [n](const Triangle& f, int k) { return prism_between(n, f, k); };
  auto place = [&](const std::vector<double>& thickness) {
    for (int k = 0; k < levels; ++k)
      for (int v = 0; v < n; ++v)
        out.points[k * n + v] = wall.points[v] + fraction[v * levels + k] * thickness[v] * out.direction[v];
  };

  build_strips(ends, n, levels, out);

  const mesh::VertexTriangles around = mesh::build_vertex_triangles(wall);
  const int layers = levels - 1;
  std::vector<double> angle;  // per prism (prism_angles)
  std::vector<char> bad(n, 0);
  constexpr int kMaxRounds = 60, kAnglePasses = 4;
  std::vector<double> limit;
  for (int pass = 0;; ++pass) {
    const std::vector<double> start = start_from(out.angle_floor);
    limit = start;
    for (int round = 0;; ++round) {
      sizing::grade_sizes(wall, limit, growth);
      place(limit);
      std::fill(bad.begin(), bad.end(), 0);
      int local_failures = 0;
      // Inner edges keep a quarter of their wall length (in the edge's own direction).
      for (const auto& [a, b] : edges.edges) {
        const Vec3 e = wall.points[b] - wall.points[a];
        const Vec3 inner = out.points[(levels - 1) * n + b] - out.points[(levels - 1) * n + a];
        if (inner.dot(e) < 0.25 * e.squaredNorm()) bad[a] = bad[b] = 1, ++local_failures;
      }
      // Prisms: positive tetrahedra (at least 5 % of a right prism's volume) and top faces that
      // turn less than 60 degrees.
      for (const Triangle& f : wall.triangles) {
        const Vec3 base = (wall.points[f[1]] - wall.points[f[0]]).cross(wall.points[f[2]] - wall.points[f[0]]);
        bool ok = true;
        for (int k = 0; ok && k + 1 < levels; ++k) {
          const Prism p = level_prism(f, k);
          double height = 0.0;  // the prism's mean
          for (int v : f) height += (fraction[v * levels + k + 1] - fraction[v * levels + k]) * limit[v] / 3.0;
          for (const Tet& t : mesh::split_prism(p))
            if (mesh::tet_volume6(out.points[t[0]], out.points[t[1]], out.points[t[2]], out.points[t[3]]) <
                0.05 * base.norm() * height)
              ok = false;
          const Vec3& a = out.points[p[3]];
          const Vec3 top = (out.points[p[4]] - a).cross(out.points[p[5]] - a);
          if (top.dot(base) < 0.5 * top.norm() * base.norm()) ok = false;
        }
        if (!ok) bad[f[0]] = bad[f[1]] = bad[f[2]] = 1, ++local_failures;
      }
      int crossings = 0;
      if (local_failures == 0) {
        // The layer's closed boundary: wall, strips, inner surface turned inside out.
        TriMesh closed;
        closed.points = out.points;
        closed.triangles = wall.triangles;
        for (const auto& strip : out.end_strips) closed.triangles.insert(closed.triangles.end(), strip.begin(), strip.end());
        for (const Triangle& f : wall.triangles)
          closed.triangles.push_back({(levels - 1) * n + f[0], (levels - 1) * n + f[2], (levels - 1) * n + f[1]});
        for (const auto& [s, t] : mesh::self_intersecting_pairs(closed)) {
          for (int v : closed.triangles[s]) bad[v % n] = 1;
          for (int v : closed.triangles[t]) bad[v % n] = 1;
          ++crossings;
        }
      }
      if (local_failures == 0 && crossings == 0) break;
      // Shrink the marked columns; one that cannot shrink further is an error naming it. A
      // column nearly tangent to one of its triangles folds at any height: it turns toward that
      // triangle's normal first (the direction every triangle around sees best).
      for (int v = 0; v < n; ++v) {
        if (!bad[v]) continue;
        turn_toward_visible(wall, around, v, plane[v], out.direction[v]);
        limit[v] *= 0.7;
        if (limit[v] < options.min_thickness_fraction * out.target[v] || round == kMaxRounds) {
          throw InputError(fmt::format(
              "the boundary layer cannot be built near wall point {} {}: its columns {} even at {:.1f} % of the "
              "thickness asked for; remesh the surface finer there or lower --thickness-ratio",
              v, mesh::format_point(wall.points[v]),
              local_failures > 0 ? "fold or invert" : "cross another part of the layer",
              100.0 * options.min_thickness_fraction));
        }
      }
      reporter.info(fmt::format("boundary layer: round {}: {} folding places, {} crossing pairs; shrinking there",
                                round + 1, local_failures, crossings));
    }
    angle = prism_angles(wall, out.points, levels);
    // Prisms still under the angle where nothing held their columns down (no shrink, no cap at
    // half the radius): the floor's estimate fell short (inner levels widen where the wall is
    // concave; leaning columns). Raise those floors by what the angle missed and build again.
    if (!(options.min_angle_deg > 0.0) || pass + 1 == kAnglePasses) break;
    const double wanted = std::tan(options.min_angle_deg * std::numbers::pi / 180.0);
    bool raised = false;
    for (size_t t = 0; t < wall.triangles.size(); ++t) {
      const Triangle& f = wall.triangles[t];
      const double least = *std::min_element(angle.begin() + t * layers, angle.begin() + (t + 1) * layers);
      if (least >= options.min_angle_deg) continue;
      const double factor = wanted / std::tan(std::max(least, 0.5) * std::numbers::pi / 180.0);
      for (int v : f) {
        if (limit[v] < 0.999 * start[v] || start[v] >= 0.5 * radius[v] * (1.0 - 1e-9)) continue;
        out.angle_floor[v] = std::max(out.angle_floor[v], factor * limit[v]);
        raised = true;
      }
    }
    if (!raised) break;
    reporter.info(fmt::format("boundary layer: angle pass {}: columns under {} degrees thickened", pass + 1,
                              options.min_angle_deg));
  }
  out.thickness = limit;
  record_layer(wall, options, angle, out);
  return out;
}

}  // namespace vesselmesh::volume
