#include "io/obj.h"

#include "io/atomic_file.h"
#include "io/text_cursor.h"
#include "mesh/error.h"
#include "mesh/merge_points.h"

#include <fmt/format.h>

#include <charconv>
#include <map>

namespace vesselmesh::io {

TriMesh parse_obj(std::string_view text, const std::string& name) {
  if (text.empty()) throw InputError(fmt::format("{}: the file is empty", name));
  TextCursor in(text, name, "OBJ");
  TriMesh mesh;
  std::map<std::string, int> groups;
  int group = 0;
  std::vector<int> polygon;
  while (!in.at_end()) {
    const std::string_view keyword = in.word_on_line();
    if (keyword == "v") {
      const double x = in.number_on_line(), y = in.number_on_line(), z = in.number_on_line();
      mesh.points.emplace_back(x, y, z);
    } else if (keyword == "f") {
      polygon.clear();
      for (std::string_view w = in.word_on_line(); !w.empty(); w = in.word_on_line()) {
        const std::string_view index = w.substr(0, w.find('/'));
        long long i = 0;
        const auto [end, ec] = std::from_chars(index.data(), index.data() + index.size(), i);
        if (index.empty() || ec != std::errc() || end != index.data() + index.size() || i == 0)
          in.fail(fmt::format("a face corner must be a point number, found {}", TextCursor::quoted(w)));
        const long long point = i > 0 ? i - 1 : mesh.num_points() + i;  // negative: from the end
        if (point < 0 || point >= mesh.num_points())
          in.fail(fmt::format("a face uses point {}, but {} points are defined before it", i, mesh.num_points()));
        polygon.push_back(static_cast<int>(point));
      }
      if (polygon.size() < 3) in.fail(fmt::format("a face needs three corners, it has {}", polygon.size()));
      for (size_t k = 1; k + 1 < polygon.size(); ++k) {
        mesh.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
        mesh.labels.push_back(group);
      }
    } else if (keyword == "g" || keyword == "o") {
      const std::string group_name(in.word_on_line());
      group = groups.emplace(group_name, static_cast<int>(groups.size()) + 1).first->second;
    }
    in.rest_of_line();  // comments, normals, texture coordinates, materials: not used
  }
  if (mesh.triangles.empty()) throw InputError(fmt::format("{}: OBJ: no faces (a surface is needed)", name));
  if (groups.size() < 2) mesh.labels.clear();
  mesh::remap_triangles(mesh.triangles, mesh::merge_identical_points(mesh.points));
  return mesh;
}

TriMesh read_obj(const std::string& path) { return parse_obj(read_file(path), path); }

}  // namespace vesselmesh::io
