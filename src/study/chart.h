// Charts as SVG text, for reports and ring plots: line charts of one or more series, with
// axis ticks at round numbers, grid, legend and marked points. The colours are the Okabe-Ito
// palette (told apart with colour-vision deficiencies); series may also be dashed.
#pragma once

#include <string>
#include <vector>

namespace vesselmesh::study {

struct Series {
  std::string name;
  std::vector<double> x, y;  // the same length; non-finite values break the line
  bool dashed = false;
};

struct Marker {
  std::string label;
  double x = 0.0, y = 0.0;
};

struct LineChart {
  std::string title, x_label, y_label;
  std::vector<Series> series;
  std::vector<Marker> markers;
  int width = 760, height = 440;
  bool y_from_zero = false;  // the y axis starts at 0 when every value is positive
};

// Grouped bars: one group per category, one bar per series in each (values may be negative).
struct BarSeries {
  std::string name;
  std::vector<double> values;  // one per category; NaN leaves a gap
};

struct BarChart {
  std::string title, y_label;
  std::vector<std::string> categories;
  std::vector<BarSeries> series;
  int width = 760, height = 440;
};

// A standalone SVG document. Throws InputError when a series' x and y differ in length (or a
// bar series' values and the categories).
std::string svg(const LineChart& chart);
std::string svg(const BarChart& chart);

// Text made safe inside XML (SVG, HTML): & < > " escaped.
std::string xml_escape(const std::string& text);

// Round tick positions covering [low, high], about `count` of them.
std::vector<double> nice_ticks(double low, double high, int count = 6);

}  // namespace vesselmesh::study
