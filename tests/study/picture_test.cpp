#include "study/picture.h"

#include "mesh/error.h"
#include "synth/shapes.h"

#include <gtest/gtest.h>

namespace vesselmesh::study {
namespace {

TEST(Picture, LooksAtAPipeBroadside) {
  const TriMesh pipe = synth::cylinder({.radius = 1.0, .length = 10.0, .resolution = 0.5});
  const Vec3 view = broadside_view(pipe);
  EXPECT_NEAR(view.z(), 0.0, 1e-6);  // across the axis, not along it
  EXPECT_NEAR(view.norm(), 1.0, 1e-12);
}

TEST(Picture, DrawsEveryTriangleAndAColourBar) {
  const TriMesh pipe = synth::cylinder({.radius = 1.0, .length = 4.0, .resolution = 0.5});
  PictureOptions o;
  o.title = "pipe <1>";
  const std::string grey = surface_svg(pipe, nullptr, o);
  size_t paths = 0;
  for (size_t at = grey.find("<path"); at != std::string::npos; at = grey.find("<path", at + 1)) ++paths;
  EXPECT_EQ(paths, pipe.triangles.size());
  EXPECT_NE(grey.find("pipe &lt;1&gt;"), std::string::npos);
  std::vector<double> z;
  for (const Vec3& p : pipe.points) z.push_back(p.z());
  o.scalar_label = "z (mm)";
  const std::string coloured = surface_svg(pipe, &z, o);
  EXPECT_NE(coloured.find("z (mm)"), std::string::npos);
  EXPECT_NE(coloured.find(">4</text>"), std::string::npos);  // the bar's top label: the largest z
  // The same picture run after run.
  EXPECT_EQ(coloured, surface_svg(pipe, &z, o));
  z.pop_back();
  EXPECT_THROW(surface_svg(pipe, &z, o), InputError);
}

}  // namespace
}  // namespace vesselmesh::study
