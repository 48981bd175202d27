#include "study/chart.h"
#include "study/raster.h"

#include "mesh/error.h"

#include <gtest/gtest.h>

namespace vesselmesh::study {
namespace {

TEST(Chart, TicksAreRoundAndCoverTheRange) {
  const std::vector<double> t = nice_ticks(0.0, 12.55);
  ASSERT_GE(t.size(), 3u);
  EXPECT_LE(t.front(), 0.0);
  EXPECT_GE(t.back(), 12.55);
  const double step = t[1] - t[0];
  EXPECT_TRUE(step == 2.0 || step == 5.0) << step;
  const std::vector<double> small = nice_ticks(0.5547, 0.5746);
  EXPECT_LE(small.front(), 0.5547);
  EXPECT_GE(small.back(), 0.5746);
  EXPECT_LE(small.size(), 8u);
  EXPECT_GE(nice_ticks(3.0, 3.0).size(), 2u);  // a flat series still gets an axis
}

TEST(Chart, SvgHasEverySeriesTheLegendAndEscapedText) {
  LineChart c;
  c.title = "WSS <ring 1> & more";
  c.x_label = "s (mm)";
  c.y_label = "Pa";
  c.series = {{"a", {0, 1, 2}, {1, 2, 3}}, {"b", {0, 1}, {0.5, 0.25}, true}};
  c.markers = {{"min", 1, 2}};
  const std::string s = svg(c);
  EXPECT_EQ(s.rfind("<?xml", 0), 0u);
  EXPECT_NE(s.find("WSS &lt;ring 1&gt; &amp; more"), std::string::npos);
  EXPECT_EQ(std::count(s.begin(), s.end(), '\n') > 10, true);
  size_t polylines = 0;
  for (size_t at = s.find("<polyline"); at != std::string::npos; at = s.find("<polyline", at + 1)) ++polylines;
  EXPECT_EQ(polylines, 2u);
  EXPECT_NE(s.find("stroke-dasharray"), std::string::npos);
  EXPECT_NE(s.find(">min</text>"), std::string::npos);
  EXPECT_NE(s.find("</svg>"), std::string::npos);
  c.series[0].y.pop_back();
  EXPECT_THROW(svg(c), InputError);
}

TEST(Chart, RendersToPng) {
  LineChart c;
  c.title = "t";
  c.series = {{"a", {0, 1}, {0, 1}}};
  c.width = 300;
  c.height = 200;
  const std::string png = png_from_svg(svg(c), 2.0);
  ASSERT_GT(png.size(), 100u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  // Width and height (big-endian, in the IHDR chunk): twice the SVG's.
  const auto word = [&](size_t at) {
    return (static_cast<unsigned char>(png[at]) << 24) | (static_cast<unsigned char>(png[at + 1]) << 16) |
           (static_cast<unsigned char>(png[at + 2]) << 8) | static_cast<unsigned char>(png[at + 3]);
  };
  EXPECT_EQ(word(16), 600);
  EXPECT_EQ(word(20), 400);
  EXPECT_THROW(png_from_svg("not svg"), InputError);
}

}  // namespace
}  // namespace vesselmesh::study
