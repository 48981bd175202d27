#include "study/chart.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace vesselmesh::study {
namespace {

constexpr std::array<const char*, 8> kColours = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                                 "#E69F00", "#56B4E9", "#000000", "#F0E442"};

}  // namespace

std::string xml_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {

const auto& escape = xml_escape;

double nice_step(double range, int count) {
  const double raw = range / std::max(1, count - 1);
  const double exponent = std::floor(std::log10(raw));
  const double fraction = raw / std::pow(10.0, exponent);
  const double nice = fraction < 1.5 ? 1.0 : fraction < 3.0 ? 2.0 : fraction < 7.0 ? 5.0 : 10.0;
  return nice * std::pow(10.0, exponent);
}

std::string tick_label(double value, double step) {
  if (std::abs(value) < 1e-12 * step) value = 0.0;
  const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
  if (std::abs(value) >= 1e5 || (value != 0.0 && std::abs(value) < 1e-4)) return fmt::format("{:.3g}", value);
  return fmt::format("{:.{}f}", value, decimals);
}

std::string document_start(int width, int height) {
  return fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
      "font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"13\">\n"
      "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
      width, height);
}

// The title, the frame, the y axis's grid and labels, the axis titles.
struct Frame {
  double left, right, top, bottom, y0, y1;
  double y(double value) const { return bottom - (value - y0) / (y1 - y0) * (bottom - top); }
};

std::string frame(const Frame& f, const std::vector<double>& yt, const std::string& title, const std::string& x_label,
                  const std::string& y_label) {
  std::string out = fmt::format("<text x=\"{:.1f}\" y=\"26\" text-anchor=\"middle\" font-size=\"16\">{}</text>\n",
                                0.5 * (f.left + f.right), escape(title));
  for (double t : yt) {
    out += fmt::format("<line x1=\"{1:.1f}\" y1=\"{0:.1f}\" x2=\"{2:.1f}\" y2=\"{0:.1f}\" stroke=\"#e0e0e0\"/>\n",
                       f.y(t), f.left, f.right);
    out += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"end\">{}</text>\n", f.left - 6, f.y(t) + 4,
                       tick_label(t, yt.size() > 1 ? yt[1] - yt[0] : 1.0));
  }
  out += fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"none\" "
                     "stroke=\"#444\"/>\n",
                     f.left, f.top, f.right - f.left, f.bottom - f.top);
  if (!x_label.empty())
    out += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\">{}</text>\n", 0.5 * (f.left + f.right),
                       f.bottom + 42, escape(x_label));
  out += fmt::format("<text transform=\"translate(18 {:.1f}) rotate(-90)\" text-anchor=\"middle\">{}</text>\n",
                     0.5 * (f.top + f.bottom), escape(y_label));
  return out;
}

std::string legend_entry(double x, double y, const char* colour, const std::string& name, bool dashed, bool box) {
  std::string out =
      box ? fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"20\" height=\"10\" fill=\"{}\"/>\n", x, y - 5, colour)
          : fmt::format("<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"{}\" "
                        "stroke-width=\"2\"{}/>\n",
                        x, y, x + 24, y, colour, dashed ? " stroke-dasharray=\"6 4\"" : "");
  return out + fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\">{}</text>\n", x + 30, y + 4, escape(name));
}

}  // namespace

std::vector<double> nice_ticks(double low, double high, int count) {
  if (!(high > low)) {
    const double pad = low == 0.0 ? 1.0 : 0.1 * std::abs(low);
    low -= pad;
    high += pad;
  }
  const double step = nice_step(high - low, count);
  const long first = static_cast<long>(std::floor(low / step + 1e-9));
  const long last = static_cast<long>(std::ceil(high / step - 1e-9));
  std::vector<double> ticks;
  for (long k = first; k <= last; ++k) ticks.push_back(static_cast<double>(k) * step);
  return ticks;
}

std::string svg(const LineChart& chart) {
  double x_low = std::numeric_limits<double>::infinity(), x_high = -x_low, y_low = x_low, y_high = -x_low;
  for (const Series& s : chart.series) {
    if (s.x.size() != s.y.size())
      throw InputError(fmt::format("chart \"{}\": series \"{}\" has {} x and {} y values", chart.title, s.name,
                                   s.x.size(), s.y.size()));
    for (size_t i = 0; i < s.x.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) {
        x_low = std::min(x_low, s.x[i]);
        x_high = std::max(x_high, s.x[i]);
        y_low = std::min(y_low, s.y[i]);
        y_high = std::max(y_high, s.y[i]);
      }
  }
  if (!std::isfinite(x_low)) x_low = 0.0, x_high = 1.0, y_low = 0.0, y_high = 1.0;
  if (chart.y_from_zero && y_low > 0.0) y_low = 0.0;
  const std::vector<double> xt = nice_ticks(x_low, x_high), yt = nice_ticks(y_low, y_high);
  const double x0 = xt.front(), x1 = xt.back(), y0 = yt.front(), y1 = yt.back();
  const double left = 78, right = chart.width - 170, top = 46, bottom = chart.height - 58;
  const auto px = [&](double x) { return left + (x - x0) / (x1 - x0) * (right - left); };
  const auto py = [&](double y) { return bottom - (y - y0) / (y1 - y0) * (bottom - top); };

  std::string out = document_start(chart.width, chart.height);
  out += frame({left, right, top, bottom, y0, y1}, yt, chart.title, chart.x_label, chart.y_label);
  for (double t : xt) {
    out += fmt::format("<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{0:.1f}\" y2=\"{2:.1f}\" stroke=\"#e0e0e0\"/>\n",
                       px(t), top, bottom);
    out += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\">{}</text>\n", px(t), bottom + 18,
                       tick_label(t, xt.size() > 1 ? xt[1] - xt[0] : 1.0));
  }
  for (size_t k = 0; k < chart.series.size(); ++k) {
    const Series& s = chart.series[k];
    const char* colour = kColours[k % kColours.size()];
    std::string points;
    const auto flush = [&]() {
      if (points.empty()) return;
      out += fmt::format("<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"1.8\"{} points=\"{}\"/>\n", colour,
                         s.dashed ? " stroke-dasharray=\"6 4\"" : "", points);
      points.clear();
    };
    for (size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
        flush();
        continue;
      }
      points += fmt::format("{}{:.2f},{:.2f}", points.empty() ? "" : " ", px(s.x[i]), py(s.y[i]));
    }
    flush();
    out += legend_entry(right + 12, top + 10 + 20 * static_cast<double>(k), colour, s.name, s.dashed, false);
  }
  for (const Marker& m : chart.markers) {
    if (!std::isfinite(m.x) || !std::isfinite(m.y)) continue;
    out += fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"4\" fill=\"none\" stroke=\"#000\" "
                       "stroke-width=\"1.5\"/>\n",
                       px(m.x), py(m.y));
    out += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" font-size=\"12\">{}</text>\n", px(m.x) + 6, py(m.y) - 6,
                       escape(m.label));
  }
  return out + "</svg>\n";
}

std::string svg(const BarChart& chart) {
  double low = 0.0, high = 0.0;
  for (const BarSeries& s : chart.series) {
    if (s.values.size() != chart.categories.size())
      throw InputError(fmt::format("chart \"{}\": series \"{}\" has {} values for {} categories", chart.title, s.name,
                                   s.values.size(), chart.categories.size()));
    for (double v : s.values)
      if (std::isfinite(v)) low = std::min(low, v), high = std::max(high, v);
  }
  const std::vector<double> yt = nice_ticks(low, high);
  const Frame f{78, chart.width - 170.0, 46, chart.height - 58.0, yt.front(), yt.back()};
  std::string out = document_start(chart.width, chart.height);
  out += frame(f, yt, chart.title, "", chart.y_label);
  const double group = (f.right - f.left) / std::max<size_t>(1, chart.categories.size());
  const double bar = 0.8 * group / std::max<size_t>(1, chart.series.size());
  for (size_t c = 0; c < chart.categories.size(); ++c) {
    const double x = f.left + group * (static_cast<double>(c) + 0.1);
    for (size_t k = 0; k < chart.series.size(); ++k) {
      const double v = chart.series[k].values[c];
      if (!std::isfinite(v)) continue;
      const double a = f.y(std::max(0.0, v)), b = f.y(std::min(0.0, v));
      out += fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"{}\"><title>{}: "
                         "{:.4g}</title></rect>\n",
                         x + bar * static_cast<double>(k), a, 0.92 * bar, std::max(0.5, b - a),
                         kColours[k % kColours.size()], escape(chart.series[k].name + ", " + chart.categories[c]), v);
    }
    out += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\">{}</text>\n",
                       f.left + group * (static_cast<double>(c) + 0.5), f.bottom + 18, escape(chart.categories[c]));
  }
  out += fmt::format("<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{2:.1f}\" y2=\"{1:.1f}\" stroke=\"#444\"/>\n", f.left,
                     f.y(0.0), f.right);
  for (size_t k = 0; k < chart.series.size(); ++k)
    out += legend_entry(f.right + 12, f.top + 10 + 20 * static_cast<double>(k), kColours[k % kColours.size()],
                        chart.series[k].name, false, true);
  return out + "</svg>\n";
}

}  // namespace vesselmesh::study
