#include "study/picture.h"

#include "mesh/error.h"
#include "study/chart.h"

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace vesselmesh::study {
namespace {

// Viridis at nine stops.
constexpr std::array<std::array<double, 3>, 9> kViridis = {{{0.267, 0.005, 0.329},
                                                            {0.283, 0.141, 0.458},
                                                            {0.254, 0.265, 0.530},
                                                            {0.207, 0.372, 0.553},
                                                            {0.164, 0.471, 0.558},
                                                            {0.128, 0.567, 0.551},
                                                            {0.135, 0.659, 0.518},
                                                            {0.267, 0.749, 0.441},
                                                            {0.478, 0.821, 0.318}}};
constexpr std::array<double, 3> kViridisTop = {0.993, 0.906, 0.144};


std::string rgb(const std::array<double, 3>& c, double shade) {
  const auto channel = [&](double v) { return static_cast<int>(std::lround(std::clamp(v * shade, 0.0, 1.0) * 255)); };
  return fmt::format("#{:02x}{:02x}{:02x}", channel(c[0]), channel(c[1]), channel(c[2]));
}

}  // namespace

std::array<double, 3> viridis(double t) {
  t = std::clamp(t, 0.0, 1.0) * 9.0;
  const int k = std::min(8, static_cast<int>(t));
  const std::array<double, 3>& a = kViridis[k];
  const std::array<double, 3>& b = k + 1 < 9 ? kViridis[k + 1] : kViridisTop;
  const double f = t - k;
  return {a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])};
}

Vec3 screen_up(const Vec3& view) {
  // "Up" is the coordinate axis least along the view, made orthogonal to it.
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(view[k]) < std::abs(view[axis])) axis = k;
  return (Vec3::Unit(axis) - view.dot(Vec3::Unit(axis)) * view).normalized();
}

Vec3 broadside_view(const TriMesh& mesh) {
  if (mesh.points.empty()) return Vec3::UnitZ();
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : mesh.points) mean += p;
  mean /= static_cast<double>(mesh.points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Vec3& p : mesh.points) covariance += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Vec3 view = solver.eigenvectors().col(0);  // the least eigenvalue comes first
  // A fixed sign, so that the picture does not flip between runs of similar shapes.
  int largest = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(view[k]) > std::abs(view[largest])) largest = k;
  return view[largest] < 0.0 ? Vec3(-view) : view;
}

std::string surface_svg(const TriMesh& mesh, const std::vector<double>* scalar, const PictureOptions& o) {
  if (scalar && scalar->size() != mesh.points.size())
    throw InputError(fmt::format("picture \"{}\": {} values for {} points", o.title, scalar->size(), mesh.points.size()));
  const Vec3 view = o.view.value_or(broadside_view(mesh)).normalized();
  const Vec3 up = screen_up(view);
  const Vec3 right = up.cross(view);
  // Fit the drawing into the picture (room left for the title and the colour bar).
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const Vec3& p : mesh.points) {
    x0 = std::min(x0, p.dot(right)), x1 = std::max(x1, p.dot(right));
    y0 = std::min(y0, p.dot(up)), y1 = std::max(y1, p.dot(up));
  }
  const double bar = scalar ? 110.0 : 0.0;
  const double area_w = o.width - 40.0 - bar, area_h = o.height - 70.0;
  const double scale = std::min(area_w / std::max(x1 - x0, 1e-12), area_h / std::max(y1 - y0, 1e-12));
  const double cx = 20.0 + 0.5 * area_w, cy = 50.0 + 0.5 * area_h;
  const auto sx = [&](const Vec3& p) { return cx + (p.dot(right) - 0.5 * (x0 + x1)) * scale; };
  const auto sy = [&](const Vec3& p) { return cy - (p.dot(up) - 0.5 * (y0 + y1)) * scale; };

  double low = o.low, high = o.high;
  if (scalar && !(high > low)) {
    low = 1e300, high = -1e300;
    for (double v : *scalar)
      if (std::isfinite(v)) low = std::min(low, v), high = std::max(high, v);
    if (!(high > low)) high = low + 1.0;
  }
  // Back to front: the farthest along the view first.
  std::vector<int> order(mesh.triangles.size());
  std::iota(order.begin(), order.end(), 0);
  std::vector<double> depth(mesh.triangles.size());
  for (size_t f = 0; f < depth.size(); ++f) {
    const Triangle& t = mesh.triangles[f];
    depth[f] = (mesh.points[t[0]] + mesh.points[t[1]] + mesh.points[t[2]]).dot(view);
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return depth[a] > depth[b]; });

  std::string out = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
      "font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"13\">\n"
      "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      "<text x=\"{2:.1f}\" y=\"28\" text-anchor=\"middle\" font-size=\"16\">{3}</text>\n<g stroke-linejoin=\"round\"{4}>\n",
      o.width, o.height, 0.5 * o.width, xml_escape(o.title), o.edges ? " stroke=\"#303030\" stroke-width=\"0.35\"" : "");
  out.reserve(out.size() + 90 * order.size());
  for (int f : order) {
    const Triangle& t = mesh.triangles[f];
    const Vec3 &a = mesh.points[t[0]], &b = mesh.points[t[1]], &c = mesh.points[t[2]];
    const Vec3 n = (b - a).cross(c - a);
    const double facing = n.norm() > 0.0 ? std::abs(n.normalized().dot(view)) : 1.0;
    const double shade = 0.45 + 0.55 * facing;
    std::array<double, 3> colour = {0.82, 0.84, 0.88};
    if (scalar) colour = viridis((((*scalar)[t[0]] + (*scalar)[t[1]] + (*scalar)[t[2]]) / 3.0 - low) / (high - low));
    const std::string fill = rgb(colour, shade);
    out += fmt::format("<path d=\"M{:.1f} {:.1f}L{:.1f} {:.1f}L{:.1f} {:.1f}Z\" fill=\"{}\"{}/>\n", sx(a), sy(a), sx(b),
                       sy(b), sx(c), sy(c), fill, o.edges ? "" : fmt::format(" stroke=\"{}\" stroke-width=\"0.3\"", fill));
  }
  out += "</g>\n";
  if (scalar) {  // the colour bar
    const double bx = o.width - bar + 20.0, top = 60.0, bottom = o.height - 40.0;
    const int steps = 64;
    for (int k = 0; k < steps; ++k) {
      const double y = bottom - (bottom - top) * (k + 1) / steps;
      out += fmt::format("<rect x=\"{:.1f}\" y=\"{:.2f}\" width=\"18\" height=\"{:.2f}\" fill=\"{}\"/>\n", bx, y,
                         (bottom - top) / steps + 0.5, rgb(viridis((k + 0.5) / steps), 1.0));
    }
    for (int k = 0; k <= 4; ++k) {
      const double v = low + (high - low) * k / 4.0, y = bottom - (bottom - top) * k / 4.0;
      out += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\">{:.3g}</text>\n", bx + 24, y + 4, v);
    }
    out += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\">{}</text>\n", bx - 10, top - 14, xml_escape(o.scalar_label));
  }
  return out + "</svg>\n";
}

}  // namespace vesselmesh::study
