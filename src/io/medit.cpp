#include "io/medit.h"

#include "io/atomic_file.h"
#include "io/text_cursor.h"
#include "mesh/error.h"

#include <fmt/format.h>
#include <fmt/os.h>

#include <map>
#include <set>

namespace vesselmesh::io {
namespace {

// Numbers per entry of the sections a surface file may hold besides Vertices and Triangles.
const std::map<std::string_view, int> kSkipped = {
    {"Edges", 3},       {"Corners", 1},           {"Ridges", 1},    {"RequiredVertices", 1}, {"RequiredEdges", 1},
    {"RequiredTriangles", 1}, {"Normals", 3},     {"NormalAtVertices", 2}, {"Tangents", 3}, {"TangentAtVertices", 2},
    {"Quadrilaterals", 5}, {"Tetrahedra", 5},     {"Prisms", 7}};

}  // namespace

TriMesh parse_medit(std::string_view text, const std::string& name) {
  if (text.empty()) throw InputError(fmt::format("{}: the file is empty", name));
  TextCursor in(text, name, "Medit");
  TriMesh mesh;
  std::vector<int> references;
  bool version = false;
  for (std::string_view keyword = in.word(); !keyword.empty(); keyword = in.word()) {
    if (keyword.front() == '#') {
      in.rest_of_line();
    } else if (keyword == "MeshVersionFormatted") {
      in.integer();
      version = true;
    } else if (keyword == "Dimension") {
      if (in.integer() != 3) in.fail("only 3-dimensional meshes are read");
    } else if (keyword == "Vertices") {
      const long long n = in.integer();
      if (n < 0 || n > 500'000'000) in.fail(fmt::format("{} vertices is not a count", n));
      mesh.points.reserve(static_cast<size_t>(n));
      for (long long i = 0; i < n; ++i) {
        const double x = in.number(), y = in.number(), z = in.number();
        in.integer();
        mesh.points.emplace_back(x, y, z);
      }
    } else if (keyword == "Triangles") {
      const long long n = in.integer();
      if (n < 0 || n > 1'000'000'000) in.fail(fmt::format("{} triangles is not a count", n));
      for (long long i = 0; i < n; ++i) {
        Triangle t;
        for (int& v : t) {
          const long long k = in.integer();
          if (k < 1 || k > mesh.num_points())
            in.fail(fmt::format("triangle {} uses vertex {}, but {} vertices are defined before it", i + 1, k,
                                mesh.num_points()));
          v = static_cast<int>(k - 1);
        }
        mesh.triangles.push_back(t);
        references.push_back(static_cast<int>(in.integer()));
      }
    } else if (keyword == "End") {
      break;
    } else if (auto skipped = kSkipped.find(keyword); skipped != kSkipped.end()) {
      const long long n = in.integer();
      if (n < 0) in.fail(fmt::format("{} {} is not a count", n, keyword));
      for (long long i = 0; i < n * skipped->second; ++i) in.number();
    } else {
      in.fail(fmt::format("unknown section {}", TextCursor::quoted(keyword)));
    }
  }
  if (!version) throw InputError(fmt::format("{}: Medit: no MeshVersionFormatted: not a .mesh file", name));
  if (mesh.triangles.empty()) throw InputError(fmt::format("{}: Medit: no triangles (a surface is needed)", name));
  if (std::set<int>(references.begin(), references.end()).size() > 1) mesh.labels = std::move(references);
  return mesh;
}

TriMesh read_medit(const std::string& path) { return parse_medit(read_file(path), path); }

void write_medit(const std::string& path, const TriMesh& mesh) {
  write_atomically(path, [&](const std::string& temporary) {
    auto out = fmt::output_file(temporary);
    out.print("MeshVersionFormatted 2\nDimension 3\n\nVertices\n{}\n", mesh.num_points());
    for (const Vec3& p : mesh.points) out.print("{} {} {} 0\n", p.x(), p.y(), p.z());
    out.print("\nTriangles\n{}\n", mesh.num_triangles());
    for (int t = 0; t < mesh.num_triangles(); ++t) {
      const Triangle& f = mesh.triangles[t];
      out.print("{} {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1, mesh.has_labels() ? mesh.labels[t] : 0);
    }
    out.print("\nEnd\n");
  });
}

void write_medit_metric(const std::string& path, const std::vector<Sym3>& metric) {
  write_atomically(path, [&](const std::string& temporary) {
    auto out = fmt::output_file(temporary);
    out.print("MeshVersionFormatted 2\nDimension 3\n\nSolAtVertices\n{}\n1 3\n", metric.size());
    for (const Sym3& m : metric) out.print("{} {} {} {} {} {}\n", m.v[0], m.v[1], m.v[3], m.v[2], m.v[4], m.v[5]);
    out.print("\nEnd\n");
  });
}

}  // namespace vesselmesh::io
