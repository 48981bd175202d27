#include "io/ply.h"

#include "mesh/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

namespace vesselmesh::io {
namespace {

const std::string kHeader =
    "ply\nformat {}\ncomment made by hand\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "property uchar red\nelement face 1\nproperty list uchar int vertex_indices\nproperty int flags\nend_header\n";

std::string header(const std::string& format) {
  std::string h = kHeader;
  h.replace(h.find("{}"), 2, format);
  return h;
}

template <typename T>
void put(std::string& out, T value, bool big_endian) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if (big_endian) std::reverse(raw, raw + sizeof(T));
  out.append(raw, sizeof(T));
}

std::string binary_quad(bool big_endian) {
  std::string body = header(big_endian ? "binary_big_endian 1.0" : "binary_little_endian 1.0");
  const float xyz[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (const auto& p : xyz) {
    for (float c : p) put(body, c, big_endian);
    put(body, uint8_t{200}, big_endian);
  }
  put(body, uint8_t{4}, big_endian);
  for (int32_t i : {0, 1, 2, 3}) put(body, i, big_endian);
  put(body, int32_t{7}, big_endian);
  return body;
}

TEST(Ply, AsciiQuadBecomesTwoTriangles) {
  const TriMesh m = parse_ply(header("ascii 1.0") + "0 0 0 255\n1 0 0 255\n1 1 0 255\n0 1 0 255\n4 0 1 2 3 9\n", "q.ply");
  EXPECT_EQ(m.num_points(), 4);
  ASSERT_EQ(m.num_triangles(), 2);
  EXPECT_EQ(m.triangles[1], (Triangle{0, 2, 3}));
}

TEST(Ply, BinaryLittleAndBigEndianReadTheSame) {
  const TriMesh little = parse_ply(binary_quad(false), "l.ply");
  const TriMesh big = parse_ply(binary_quad(true), "b.ply");
  EXPECT_EQ(little.points, big.points);
  EXPECT_EQ(little.triangles, big.triangles);
  EXPECT_EQ(little.points[2], Vec3(1, 1, 0));
}

std::string error_of(const std::string& bytes) {
  try {
    parse_ply(bytes, "bad.ply");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Ply, DamagedFilesAreOneLineErrors) {
  EXPECT_NE(error_of("").find("empty"), std::string::npos);
  EXPECT_NE(error_of("plx\n").find("not a PLY file"), std::string::npos);
  EXPECT_NE(error_of("ply\nformat ascii 1.0\nelement vertex 2\n").find("without 'end_header'"), std::string::npos);
  EXPECT_NE(error_of("ply\nformat ascii 1.0\nelement vertex 99999999\nend_header\n").find("instances"),
            std::string::npos);
  std::string cut = binary_quad(false);
  cut.resize(cut.size() - 6);
  EXPECT_NE(error_of(cut).find("ends in the middle"), std::string::npos) << error_of(cut);
  EXPECT_NE(error_of(header("ascii 1.0") + "0 0 0 1\n1 0 0 1\n1 1 0 1\n0 1 0 1\n3 0 1 8 0\n").find("uses vertex 8"),
            std::string::npos);
  EXPECT_NE(error_of(header("ascii 1.0") + "0 0 0 1\n1 0 zero 1\n").find("bad.ply:14"), std::string::npos)
      << error_of(header("ascii 1.0") + "0 0 0 1\n1 0 zero 1\n");
  EXPECT_NE(error_of(header("ascii 1.0") + "0 0 0 1\n1 0 nan 1\n").find("non-finite"), std::string::npos);
}

}  // namespace
}  // namespace vesselmesh::io
