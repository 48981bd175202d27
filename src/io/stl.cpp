#include "io/stl.h"

#include "io/atomic_file.h"
#include "io/text_cursor.h"
#include "mesh/error.h"
#include "mesh/merge_points.h"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>

namespace vesselmesh::io {
namespace {

constexpr size_t kHeaderBytes = 80;
constexpr size_t kFacetBytes = 50;  // normal, 3 corners (12 float32), attribute (uint16)

bool starts_with_solid(std::string_view bytes) {
  size_t i = 0;
  while (i < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[i]))) ++i;
  return bytes.substr(i, 5) == "solid";
}

uint32_t read_u32(const char* p) {
  uint32_t v;
  std::memcpy(&v, p, 4);
  return v;  // STL is little-endian, as is every platform we build for
}

TriMesh parse_binary(std::string_view bytes, const std::string& name, StlInfo* info) {
  if (bytes.size() < kHeaderBytes + 4)
    throw InputError(fmt::format(
        "{}: not an STL file: {} bytes is too short for a binary STL (84-byte header) and it "
        "does not start with 'solid' as an ASCII STL does",
        name, bytes.size()));
  const uint64_t count = read_u32(bytes.data() + kHeaderBytes);
  const uint64_t expected = kHeaderBytes + 4 + kFacetBytes * count;
  if (bytes.size() != expected) {
    // A count far beyond the file's size is no STL at all; a little beyond, a cut-off file.
    const bool truncated = bytes.size() < expected;
    const bool plausible = expected <= 50 * bytes.size();
    const char* what = !plausible ? "not an STL file (it does not start with 'solid' as an ASCII STL does, and as a "
                                    "binary STL"
                       : truncated ? "truncated binary STL"
                                   : "the triangle count disagrees with the file size";
    throw InputError(fmt::format("{}: {}: the header declares {} triangles, which take {} bytes, but the file has {} "
                                 "bytes{}",
                                 name, what, count, expected, bytes.size(),
                                 !plausible  ? ")"
                                 : truncated ? " (an interrupted copy or export? export it again)"
                                             : ""));
  }
  if (count == 0) throw InputError(fmt::format("{}: the STL file has no triangles", name));
  if (count > static_cast<uint64_t>(std::numeric_limits<int>::max() / 3))
    throw InputError(fmt::format("{}: {} triangles is more than vesselmesh handles", name, count));
  if (info) {
    info->binary = true;
    info->header.assign(bytes.data(), kHeaderBytes);
    info->header.erase(info->header.find_last_not_of(std::string_view("\0 ", 2)) + 1);
    info->raw_triangles = static_cast<long long>(count);
  }
  TriMesh mesh;
  mesh.triangles.resize(count);
  mesh::IdenticalPointSet points(count / 2 + 16);  // a closed surface has about half as many points
  const char* facet = bytes.data() + kHeaderBytes + 4;
  for (uint64_t t = 0; t < count; ++t, facet += kFacetBytes) {
    float xyz[9];
    std::memcpy(xyz, facet + 12, sizeof xyz);
    for (int c = 0; c < 3; ++c) {
      const Vec3 p(xyz[3 * c], xyz[3 * c + 1], xyz[3 * c + 2]);
      if (!p.allFinite())
        throw InputError(fmt::format("{}: triangle {} corner {} has a non-finite coordinate ({}, {}, {})",
                                     name, t, c, p.x(), p.y(), p.z()));
      mesh.triangles[t][c] = points.insert(p);
    }
  }
  mesh.points = points.release();
  return mesh;
}

TriMesh parse_ascii(std::string_view text, const std::string& name, StlInfo* info) {
  TextCursor in(text, name, "malformed ASCII STL");
  TriMesh mesh;
  mesh::IdenticalPointSet points(text.size() / 200);
  in.expect("solid");
  std::string solid_name(in.rest_of_line());
  for (std::string_view w = in.word(); !w.empty(); w = in.word()) {
    if (w == "endsolid") {
      in.rest_of_line();
      continue;
    }
    if (w == "solid") {  // several solids in one file
      in.rest_of_line();
      continue;
    }
    if (w != "facet") in.fail(fmt::format("expected 'facet' or 'endsolid', found '{}'", w.substr(0, 40)));
    in.expect("normal");
    for (int i = 0; i < 3; ++i) in.number();
    in.expect("outer");
    in.expect("loop");
    Triangle f;
    for (int c = 0; c < 3; ++c) {
      in.expect("vertex");
      const double x = in.number(), y = in.number(), z = in.number();
      f[c] = points.insert(Vec3(x, y, z));
    }
    in.expect("endloop");
    in.expect("endfacet");
    mesh.triangles.push_back(f);
  }
  if (mesh.triangles.empty()) throw InputError(fmt::format("{}: the ASCII STL file has no facets", name));
  if (info) {
    info->binary = false;
    info->header = solid_name;
    info->raw_triangles = static_cast<long long>(mesh.triangles.size());
  }
  mesh.points = points.release();
  return mesh;
}

}  // namespace

TriMesh parse_stl(std::string_view bytes, const std::string& name, StlInfo* info) {
  if (bytes.empty()) throw InputError(fmt::format("{}: the file is empty", name));
  // A binary file whose size matches its count is binary even if its header says "solid".
  if (bytes.size() >= kHeaderBytes + 4) {
    const uint64_t count = read_u32(bytes.data() + kHeaderBytes);
    if (count > 0 && bytes.size() == kHeaderBytes + 4 + kFacetBytes * count)
      return parse_binary(bytes, name, info);
  }
  if (starts_with_solid(bytes)) return parse_ascii(bytes, name, info);
  return parse_binary(bytes, name, info);
}

TriMesh read_stl(const std::string& path, StlInfo* info) { return parse_stl(read_file(path), path, info); }

void write_stl(const std::string& path, const TriMesh& mesh) {
  write_atomically(path, [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary);
    if (!out) throw InputError(fmt::format("{}: cannot open for writing", path));
    char header[kHeaderBytes] = {};
    std::snprintf(header, sizeof header, "binary STL written by vesselmesh");
    out.write(header, sizeof header);
    const uint32_t count = static_cast<uint32_t>(mesh.triangles.size());
    out.write(reinterpret_cast<const char*>(&count), 4);
    std::vector<char> buffer(kFacetBytes * mesh.triangles.size());
    char* facet = buffer.data();
    for (const Triangle& f : mesh.triangles) {
      const Vec3 &a = mesh.points[f[0]], &b = mesh.points[f[1]], &c = mesh.points[f[2]];
      Vec3 n = (b - a).cross(c - a);
      if (n.norm() > 0.0) n.normalize();
      const float values[12] = {float(n.x()), float(n.y()), float(n.z()), float(a.x()), float(a.y()),
                                float(a.z()), float(b.x()), float(b.y()), float(b.z()), float(c.x()),
                                float(c.y()), float(c.z())};
      std::memcpy(facet, values, sizeof values);
      std::memset(facet + 48, 0, 2);
      facet += kFacetBytes;
    }
    out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    if (!out.flush()) throw InputError(fmt::format("{}: write failed (disk full?)", path));
  });
}

}  // namespace vesselmesh::io
