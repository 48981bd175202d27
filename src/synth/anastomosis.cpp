#include "synth/anastomosis.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

namespace vesselmesh::synth {
namespace {

constexpr double kReach = 1.5;  // the cuts' reach, in radii of the end cut (open_tube_surface)

Vec3 heading(double angle) { return Vec3(std::cos(angle), 0.0, -std::sin(angle)); }  // down from +x

// Where everything lies; see the header for the picture.
struct Geometry {
  double rh = 0.0, rg = 0.0, fillet = 0.0, h = 0.0;
  // Graft, downstream order: tip (past the inlet) - inlet - p2 - arc - p1 - end (above the host's axis).
  Vec3 end, p1, arc_center, arc_u, arc_v, p2, inlet, inlet_direction, tip, direction;
  double arc_radius = 0.0, sweep = 0.0;
  // Host along x: the stump's end, the outlet, the tubes' tips past them; an S-bend in y
  // between wiggle_from and wiggle_to.
  double heel_x = 0.0, toe_x = 0.0, stump_x = 0.0, outlet_x = 0.0;
  double wiggle_from = 0.0, wiggle_to = 0.0, amplitude = 0.0;
  std::vector<Vec3> host;  // the host's axis, a polyline from tip to tip

  double host_offset(double x) const {
    if (amplitude == 0.0 || x <= wiggle_from || x >= wiggle_to) return 0.0;
    const double u = (x - wiggle_from) / (wiggle_to - wiggle_from), s = std::sin(std::numbers::pi * u);
    return amplitude * std::sin(2.0 * std::numbers::pi * u) * s * s;
  }
  double graft_distance(const Vec3& p) const {
    return std::min({distance_to_segment(p, end, p1), distance_to_arc(p, arc_center, arc_u, arc_v, arc_radius, sweep),
                     distance_to_segment(p, p2, tip)}) - rg;
  }
  double host_distance(const Vec3& p) const {
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i + 1 < host.size(); ++i) {
      const Vec3 &a = host[i], &b = host[i + 1];
      // Segments are along x give or take the bend: skip those that cannot be nearer.
      const double gap = std::max({a.x() - p.x(), p.x() - b.x(), 0.0});
      if (gap >= best) continue;
      best = std::min(best, distance_to_segment(p, a, b));
    }
    return best - rh;
  }
  double f(const Vec3& p) const { return smooth_min(host_distance(p), graft_distance(p), fillet); }
  // The graft's axis sampled downstream, every `step` at most.
  std::vector<Vec3> graft_axis(double step) const {
    std::vector<Vec3> out;
    auto line = [&](const Vec3& a, const Vec3& b) {
      const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
      for (int i = 0; i < n; ++i) out.push_back(a + (b - a) * (static_cast<double>(i) / n));
    };
    line(tip, p2);
    const int n = std::max(1, static_cast<int>(std::ceil(arc_radius * sweep / step)));
    for (int i = 0; i < n; ++i) {
      const double a = sweep * (1.0 - static_cast<double>(i) / n);
      out.push_back(arc_center + arc_radius * (std::cos(a) * arc_u + std::sin(a) * arc_v));
    }
    line(p1, end);
    out.push_back(end);
    return out;
  }
};

// Bisection for the x where g changes sign between a and b (g(a), g(b) of opposite signs).
double crossing(const std::function<double(double)>& g, double a, double b) {
  const bool a_inside = g(a) <= 0.0;
  for (int i = 0; i < 60; ++i) {
    const double m = 0.5 * (a + b);
    ((g(m) <= 0.0) == a_inside ? a : b) = m;
  }
  return 0.5 * (a + b);
}

void check_options(const AnastomosisOptions& o) {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) throw OptionError(fmt::format("{} must be a positive length (mm), got {}", name, v));
  };
  positive(o.host_radius, "--host-radius");
  positive(o.graft_radius, "--graft-radius");
  positive(o.resolution, "--resolution");
  positive(o.graft_length, "--graft-length");
  positive(o.stump_length, "--stump-length");
  positive(o.outlet_length, "--outlet-length");
  if (!(o.angle_deg >= 10.0 && o.angle_deg <= 90.0))
    throw OptionError(fmt::format("--angle must be in [10, 90] degrees, got {}", o.angle_deg));
  if (!(o.graft_bend_deg >= 0.0 && o.graft_bend_deg <= o.angle_deg))
    throw OptionError(fmt::format("--graft-bend must be in [0, {}] degrees (at most the angle: the graft's inlet then "
                                  "runs parallel to the host), got {}",
                                  o.angle_deg, o.graft_bend_deg));
  if (!(o.graft_bend_radius == 0.0 || o.graft_bend_radius >= 1.5 * o.graft_radius) || !std::isfinite(o.graft_bend_radius))
    throw OptionError(fmt::format("--graft-bend-radius must be 0 (4 graft radii) or at least 1.5 graft radii ({:.3g} mm), "
                                  "got {}",
                                  1.5 * o.graft_radius, o.graft_bend_radius));
  if (!(o.fillet >= 0.0 && o.fillet <= std::min(o.host_radius, o.graft_radius)))
    throw OptionError(fmt::format("--fillet must be in [0, {:.3g}] mm (the smaller radius), got {}",
                                  std::min(o.host_radius, o.graft_radius), o.fillet));
  if (!(o.tortuosity >= 0.0) || !std::isfinite(o.tortuosity))
    throw OptionError(fmt::format("--tortuosity must not be negative, got {}", o.tortuosity));
  if (!(o.jitter >= 0.0 && o.jitter <= 0.45)) throw OptionError("--jitter must be in [0, 0.45]");
  const double smallest = std::min(o.host_radius, o.graft_radius);
  if (o.resolution > 0.5 * smallest)
    throw OptionError(fmt::format("--resolution {} is too coarse for the smaller radius {}: use at most half of it",
                                  o.resolution, smallest));
  if (o.stump_length < 2.0 * o.host_radius + o.fillet)
    throw OptionError(fmt::format("--stump-length must be at least {:.3g} mm (a host diameter plus the fillet), so that "
                                  "the stump is cut where it is straight",
                                  2.0 * o.host_radius + o.fillet));
  const double outlet_needed = (o.tortuosity > 0.0 ? 15.0 : 6.0) * o.host_radius;
  if (o.outlet_length < outlet_needed)
    throw OptionError(fmt::format("--outlet-length must be at least {:.3g} mm ({} host radii{}): the host runs straight "
                                  "below the toe, past the second ring",
                                  outlet_needed, o.tortuosity > 0.0 ? 15 : 6,
                                  o.tortuosity > 0.0 ? ", with room for the tortuous stretch" : ""));
}

Geometry make_geometry(const AnastomosisOptions& o) {
  check_options(o);
  Geometry g;
  g.rh = o.host_radius, g.rg = o.graft_radius, g.fillet = o.fillet, g.h = o.resolution;
  const double alpha = o.angle_deg * std::numbers::pi / 180.0, beta = o.graft_bend_deg * std::numbers::pi / 180.0;
  g.direction = heading(alpha);
  // The graft's axis ends above the host's: its rounded end stays a fillet's width off the
  // floor (a graft far wider than the host still ends below the host's top).
  const double lift = std::clamp(g.rg - g.rh + g.fillet, 0.0, 0.75 * g.rh);
  g.end = Vec3(0.0, 0.0, lift);
  // Straight until the graft is clear of the host by the fillet, then the turn.
  const double clear = (g.rg + g.rh + g.fillet - lift) / std::sin(alpha) + 0.05 * g.rg;  // the shape does not depend on the resolution
  g.p1 = g.end - clear * g.direction;
  g.arc_radius = o.graft_bend_radius > 0.0 ? o.graft_bend_radius : 4.0 * g.rg;
  g.sweep = beta;
  g.arc_u = Vec3(std::sin(alpha), 0.0, std::cos(alpha));
  g.arc_v = -g.direction;
  g.arc_center = g.p1 - g.arc_radius * g.arc_u;
  g.p2 = g.arc_center + g.arc_radius * (std::cos(beta) * g.arc_u + std::sin(beta) * g.arc_v);
  g.inlet_direction = heading(alpha - beta);
  g.inlet = g.p2 - o.graft_length * g.inlet_direction;
  g.tip = g.inlet - 2.0 * g.rg * g.inlet_direction;

  // Heel and toe of the unblended tubes: where the graft meets the host's top (z = rh) in the
  // plane of symmetry.
  auto inside_graft = [&](double x) { return g.graft_distance(Vec3(x, 0.0, g.rh)); };
  const double step = 0.25 * g.h;
  double x = g.end.x() + g.rg + g.h;
  while (inside_graft(x) > 0.0) x -= step;
  g.toe_x = crossing(inside_graft, x, x + step);
  while (inside_graft(x) <= 0.0) x -= step;
  g.heel_x = crossing(inside_graft, x, x + step);
  g.stump_x = g.heel_x - o.stump_length;
  g.outlet_x = g.toe_x + o.outlet_length;

  g.amplitude = o.tortuosity;
  g.wiggle_from = g.toe_x + 6.0 * g.rh;
  g.wiggle_to = g.outlet_x - 3.0 * g.rh;
  g.host.push_back(Vec3(g.stump_x - 2.0 * g.rh, 0.0, 0.0));
  if (g.amplitude > 0.0) {
    const int n = std::max(16, static_cast<int>(std::ceil((g.wiggle_to - g.wiggle_from) / std::min(0.5, g.rh / 4.0))));
    for (int i = 0; i <= n; ++i) {
      const double xi = g.wiggle_from + (g.wiggle_to - g.wiggle_from) * i / n;
      g.host.push_back(Vec3(xi, g.host_offset(xi), 0.0));
    }
    // The bend's tightest radius of curvature, from the samples: at least twice the radius.
    double tightest = std::numeric_limits<double>::infinity();
    for (size_t i = 2; i + 1 < g.host.size(); ++i) {
      const Vec3 a = g.host[i - 1], b = g.host[i], c = g.host[i + 1];
      const double twice_area = (b - a).cross(c - a).norm();
      if (twice_area > 0.0) tightest = std::min(tightest, (b - a).norm() * (c - b).norm() * (c - a).norm() / (2.0 * twice_area));
    }
    if (tightest < 2.0 * g.rh)
      throw OptionError(fmt::format("--tortuosity {} bends the host to a radius of {:.3g} mm, less than its diameter: "
                                    "use a smaller amplitude or a longer --outlet-length",
                                    o.tortuosity, tightest));
  } else {
    g.host.push_back(Vec3(g.wiggle_from, 0.0, 0.0));
  }
  g.host.push_back(Vec3(g.outlet_x + 2.0 * g.rh, 0.0, 0.0));

  // A cut must not reach the other vessel: the stump's plane and the graft's inlet plane are
  // the ones that could.
  const std::vector<Vec3> graft = g.graft_axis(0.5 * g.h);
  for (const Vec3& c : graft)
    if (c.x() - g.rg <= g.stump_x && std::hypot(c.y(), c.z()) - g.rg <= kReach * g.rh + g.h)
      throw OptionError(fmt::format("the graft passes over the stump's end at x = {:.3g} mm: lengthen --stump-length",
                                    g.stump_x));
  for (double xi = g.stump_x; xi <= g.outlet_x; xi += 0.5 * g.h) {
    const Vec3 c(xi, g.host_offset(xi), 0.0);
    const Vec3 d = c - g.inlet;
    const double beyond = -d.dot(g.inlet_direction);
    if (beyond + g.rh >= 0.0 && (d + beyond * g.inlet_direction).norm() - g.rh <= kReach * g.rg + g.h)
      throw OptionError("the graft's inlet lies over the host: shorten --graft-length or lengthen the turn");
  }
  return g;
}


AnastomosisLandmarks landmarks_of(const Geometry& g) {
  const ImplicitFunction f = [&g](const Vec3& p) { return g.f(p); };
  const double dh = 1e-3 * g.h;
  AnastomosisLandmarks l;
  l.ends = {{"inlet", {g.inlet, -g.inlet_direction, g.rg}},
            {"outlet", {Vec3(g.outlet_x, 0.0, 0.0), Vec3::UnitX(), g.rh}},
            {"stump", {Vec3(g.stump_x, 0.0, 0.0), -Vec3::UnitX(), g.rh}}};
  l.heel = project_to_zero_set(f, Vec3(g.heel_x, 0.0, g.rh), dh);
  l.toe = project_to_zero_set(f, Vec3(g.toe_x, 0.0, g.rh), dh);
  l.floor = project_to_zero_set(f, Vec3(l.heel.x(), 0.0, -g.rh), dh);
  l.ring1_point = 0.5 * (l.heel + l.toe);
  l.ring1_normal = (l.toe - l.heel).cross(Vec3::UnitY()).normalized();
  l.ring2_point = Vec3(g.toe_x + 4.0 * g.rh, 0.0, 0.0);
  l.ring2_normal = Vec3::UnitX();
  l.graft_direction = g.direction;
  return l;
}

}  // namespace

AnastomosisLandmarks anastomosis_landmarks(const AnastomosisOptions& o) { return landmarks_of(make_geometry(o)); }

TriMesh anastomosis(const AnastomosisOptions& o) {
  const Geometry g = make_geometry(o);
  const ImplicitFunction f = [&g](const Vec3& p) { return g.f(p); };
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Vec3& p : g.graft_axis(g.rg)) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  for (const Vec3& p : g.host) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double margin = std::max(g.rh, g.rg) + g.fillet + 2.0 * g.h;
  lo -= Vec3::Constant(margin);
  hi += Vec3::Constant(margin);
  const Vec3 box = hi - lo;
  if (box.prod() / (g.h * g.h * g.h) > 4e8)
    throw OptionError(fmt::format("--resolution {} needs a grid of {:.3g} points: choose a coarser one", g.h,
                                  box.prod() / (g.h * g.h * g.h)));
  std::vector<TubeEnd> ends;
  for (const NamedEnd& e : landmarks_of(g).ends) ends.push_back(e.end);
  return open_tube_surface(f, lo, hi, ends, {.resolution = g.h, .jitter = o.jitter, .seed = o.seed, .reach = kReach});
}

}  // namespace vesselmesh::synth
