#include "io/stl.h"

#include "mesh/error.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cstring>

namespace vesselmesh::io {
namespace {

std::string binary_stl(const std::vector<std::array<float, 9>>& facets, uint32_t declared,
                       const std::string& header = "test") {
  std::string bytes(80, '\0');
  std::memcpy(bytes.data(), header.data(), std::min<size_t>(header.size(), 80));
  bytes.append(reinterpret_cast<const char*>(&declared), 4);
  for (const auto& f : facets) {
    const float normal[3] = {0, 0, 0};
    bytes.append(reinterpret_cast<const char*>(normal), 12);
    bytes.append(reinterpret_cast<const char*>(f.data()), 36);
    bytes.append(2, '\0');
  }
  return bytes;
}

const std::vector<std::array<float, 9>> kTwoFacets = {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}};

std::string error_of(std::string_view bytes) {
  try {
    parse_stl(bytes, "f.stl");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Stl, BinaryCornersAreMergedExactly) {
  StlInfo info;
  const TriMesh m = parse_stl(binary_stl(kTwoFacets, 2), "f.stl", &info);
  EXPECT_TRUE(info.binary);
  EXPECT_EQ(info.raw_triangles, 2);
  EXPECT_EQ(info.header, "test");
  ASSERT_EQ(m.num_points(), 4);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (Triangle{1, 3, 2}));
  EXPECT_EQ(m.points[3], Vec3(1, 1, 0));
}

TEST(Stl, BinaryWhoseHeaderSaysSolidIsStillBinary) {
  const TriMesh m = parse_stl(binary_stl(kTwoFacets, 2, "solid exported-by-some-tool"), "f.stl");
  EXPECT_EQ(m.num_triangles(), 2);
}

TEST(Stl, AsciiWithSeveralSolids) {
  const std::string text =
      "solid first\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n"
      "  endloop\n endfacet\nendsolid first\nsolid second\nfacet normal 0 0 0\nouter loop\nvertex 1 0 0\n"
      "vertex 1.0 1e0 0\nvertex 0 1 -0\nendloop\nendfacet\nendsolid\n";
  StlInfo info;
  const TriMesh m = parse_stl(text, "a.stl", &info);
  EXPECT_FALSE(info.binary);
  EXPECT_EQ(info.header, "first");
  EXPECT_EQ(m.num_triangles(), 2);
  EXPECT_EQ(m.num_points(), 4);  // 1e0 == 1.0 and -0 == 0 merge
}

TEST(Stl, WriteThenReadGivesTheSameMesh) {
  test::TemporaryFolder tmp;
  const TriMesh sphere = synth::sphere({.radius = 3.0, .resolution = 0.6});
  write_stl(tmp.path("s.stl"), sphere);
  EXPECT_EQ(tmp.files(), std::vector<std::string>{"s.stl"});
  const TriMesh back = read_stl(tmp.path("s.stl"));
  ASSERT_EQ(back.num_triangles(), sphere.num_triangles());
  ASSERT_EQ(back.num_points(), sphere.num_points());
  for (int t = 0; t < back.num_triangles(); ++t)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR((back.points[back.triangles[t][c]] - sphere.points[sphere.triangles[t][c]]).norm(), 0.0, 1e-6);
}

TEST(Stl, EmptyFile) { EXPECT_NE(error_of("").find("empty"), std::string::npos); }

TEST(Stl, TruncatedBinary) {
  std::string bytes = binary_stl(kTwoFacets, 2);
  bytes.resize(bytes.size() - 10);
  const std::string e = error_of(bytes);
  EXPECT_NE(e.find("f.stl"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
}

TEST(Stl, CountThatDisagreesWithTheSize) {
  const std::string e = error_of(binary_stl(kTwoFacets, 1));
  EXPECT_NE(e.find("disagrees"), std::string::npos) << e;
  EXPECT_NE(e.find("declares 1 triangles"), std::string::npos) << e;
}

TEST(Stl, ZeroTrianglesIsAnError) {
  EXPECT_NE(error_of(binary_stl({}, 0)).find("no triangles"), std::string::npos);
}

TEST(Stl, NonFiniteBinaryCoordinateNamesTheTriangle) {
  auto facets = kTwoFacets;
  facets[1][4] = std::nanf("");
  const std::string e = error_of(binary_stl(facets, 2));
  EXPECT_NE(e.find("triangle 1 corner 1"), std::string::npos) << e;
}

TEST(Stl, NonFiniteAsciiCoordinateNamesTheLine) {
  const std::string text = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex nan 0 0\nvertex 0 1 0\n";
  const std::string e = error_of(text);
  EXPECT_NE(e.find("f.stl:5"), std::string::npos) << e;
  EXPECT_NE(e.find("non-finite"), std::string::npos) << e;
}

TEST(Stl, MalformedAsciiNamesTheLine) {
  const std::string text = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0\nvertex 0 1 0\nendloop\n";
  const std::string e = error_of(text);
  EXPECT_NE(e.find("f.stl:6"), std::string::npos) << e;
  EXPECT_NE(e.find("expected a number"), std::string::npos) << e;
  EXPECT_NE(error_of("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n").find("end of the"),
            std::string::npos);
}

TEST(Stl, BytesThatAreNoStl) {
  const std::string png = "\x89PNG\r\n\x1a\n" + std::string(200, 'x');
  EXPECT_NE(error_of(png).find("not an STL file"), std::string::npos) << error_of(png);
  EXPECT_NE(error_of("hello").find("not an STL file"), std::string::npos);
}

TEST(Stl, MissingFileNamesIt) {
  try {
    read_stl("/nonexistent/x.stl");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/x.stl"), std::string::npos);
  }
}

TEST(Stl, RealVesselReadsWithTheCountsOfItsReadme) {
  VESSELMESH_REQUIRE_SHARED(path, "vessels/vmtk_aorta_iliac_bifurcation_open_mm.stl");
  const TriMesh m = read_stl(path);
  EXPECT_EQ(m.num_triangles(), 11887);
  EXPECT_EQ(m.num_points(), 6068);
}

}  // namespace
}  // namespace vesselmesh::io
