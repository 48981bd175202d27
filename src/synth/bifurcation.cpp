#include "synth/bifurcation.h"

#include "mesh/error.h"
#include "synth/tubes.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vesselmesh::synth {
namespace {

Vec3 daughter_direction(const BifurcationOptions& o, int k) {
  const double a = o.angle_deg[k] * std::numbers::pi / 180.0 * (k == 0 ? 1.0 : -1.0);
  return Vec3(std::sin(a), 0.0, std::cos(a));
}

void validate(const BifurcationOptions& o) {
  for (double r : {o.radius, o.daughter_radius[0], o.daughter_radius[1], o.resolution})
    if (!(r > 0.0) || !std::isfinite(r)) throw OptionError("radii and resolution must be positive lengths");
  for (double a : o.angle_deg)
    if (!(a >= 5.0 && a <= 85.0)) throw OptionError(fmt::format("daughter angles must be in [5, 85] degrees, got {}", a));
  if (!(o.jitter >= 0.0 && o.jitter <= 0.45)) throw OptionError("jitter must be in [0, 0.45]");
  if (!(o.blend >= 0.0)) throw OptionError("the blend radius must not be negative");
  const double largest = std::max({o.radius, o.daughter_radius[0], o.daughter_radius[1]});
  if (o.resolution > 0.5 * std::min({o.radius, o.daughter_radius[0], o.daughter_radius[1]}))
    throw OptionError(fmt::format("resolution {} is too coarse for the smallest radius: use at most half of it",
                                  o.resolution));
  const double clear = 2.0 * largest + o.blend;
  if (o.parent_length < clear || o.daughter_length < clear)
    throw OptionError(fmt::format("parent and daughter lengths must be at least {:.3g} mm (twice the largest radius "
                                  "plus the blend) so that the ends are cut where the tubes are straight",
                                  clear));
  const Vec3 e1 = o.daughter_length * daughter_direction(o, 0), e2 = o.daughter_length * daughter_direction(o, 1);
  if ((e1 - e2).norm() < o.daughter_radius[0] + o.daughter_radius[1] + 2.0 * o.resolution)
    throw OptionError("the daughters overlap at their ends: widen the angles or lengthen them");
  if (!(o.aneurysm_radius >= 0.0) || !std::isfinite(o.aneurysm_radius))
    throw OptionError("the aneurysm radius must not be negative");
  if (o.aneurysm_radius > 0.0) {
    if (o.resolution > 0.5 * o.aneurysm_radius)
      throw OptionError(fmt::format("resolution {} is too coarse for the aneurysm: use at most half its radius",
                                    o.resolution));
    // Clear of the daughters' ends (cut where the tubes are straight) and of the parent.
    const Vec3 c = aneurysm_center(o);
    for (int k = 0; k < 2; ++k) {
      const Vec3 end = o.daughter_length * daughter_direction(o, k);
      if ((c - end).norm() < o.aneurysm_radius + 2.0 * o.daughter_radius[k] + o.blend)
        throw OptionError(fmt::format("the aneurysm (radius {}) reaches the daughters' ends: lengthen them or make it "
                                      "smaller",
                                      o.aneurysm_radius));
    }
  }
  const double triangles = 4.0 * std::numbers::pi * largest * (o.parent_length + 2 * o.daughter_length) /
                           (o.resolution * o.resolution);
  if (triangles > 5e7) throw OptionError("too many triangles: choose a coarser resolution");
}

}  // namespace

Vec3 aneurysm_center(const BifurcationOptions& o) {
  const Vec3 d1 = daughter_direction(o, 0), d2 = daughter_direction(o, 1);
  const Vec3 bisector = (d1 + d2).normalized();
  const double half = 0.5 * std::acos(std::clamp(d1.dot(d2), -1.0, 1.0));
  const double apex = std::max(o.daughter_radius[0], o.daughter_radius[1]) / std::sin(half);
  return (apex + 0.7 * o.aneurysm_radius) * bisector;
}

std::array<TubeEnd, 3> bifurcation_ends(const BifurcationOptions& o) {
  return {TubeEnd{Vec3(0.0, 0.0, -o.parent_length), Vec3(0.0, 0.0, -1.0), o.radius},
          TubeEnd{o.daughter_length * daughter_direction(o, 0), daughter_direction(o, 0), o.daughter_radius[0]},
          TubeEnd{o.daughter_length * daughter_direction(o, 1), daughter_direction(o, 1), o.daughter_radius[1]}};
}

TriMesh bifurcation(const BifurcationOptions& o) {
  validate(o);
  const double h = o.resolution;
  // Tubes run past their ends, so the cut meets them where they are straight.
  const std::array<Vec3, 3> tips = {Vec3(0.0, 0.0, -o.parent_length - 2.0 * o.radius),
                                    (o.daughter_length + 2.0 * o.daughter_radius[0]) * daughter_direction(o, 0),
                                    (o.daughter_length + 2.0 * o.daughter_radius[1]) * daughter_direction(o, 1)};
  const std::array<double, 3> radii = {o.radius, o.daughter_radius[0], o.daughter_radius[1]};
  const Vec3 dome = o.aneurysm_radius > 0.0 ? aneurysm_center(o) : Vec3::Zero();
  const ImplicitFunction f = [&](const Vec3& p) {
    double d = distance_to_segment(p, tips[0], Vec3::Zero()) - radii[0];
    for (int k = 1; k < 3; ++k) d = smooth_min(d, distance_to_segment(p, Vec3::Zero(), tips[k]) - radii[k], o.blend);
    if (o.aneurysm_radius > 0.0) d = smooth_min(d, (p - dome).norm() - o.aneurysm_radius, o.blend);
    return d;
  };
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  for (const Vec3& t : tips) lo = lo.cwiseMin(t), hi = hi.cwiseMax(t);
  if (o.aneurysm_radius > 0.0) {
    lo = lo.cwiseMin(dome - Vec3::Constant(o.aneurysm_radius));
    hi = hi.cwiseMax(dome + Vec3::Constant(o.aneurysm_radius));
  }
  const double margin = *std::max_element(radii.begin(), radii.end()) + o.blend + 2.0 * h;
  lo -= Vec3::Constant(margin);
  hi += Vec3::Constant(margin);

  const std::array<TubeEnd, 3> ends = bifurcation_ends(o);
  return open_tube_surface(f, lo, hi, ends, {.resolution = h, .jitter = o.jitter, .seed = o.seed});
}

}  // namespace vesselmesh::synth
