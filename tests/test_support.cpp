#include "test_support.h"

#include <atomic>
#include <cctype>
#include <fstream>
#include <unistd.h>

namespace vesselmesh::test {

namespace fs = std::filesystem;

TemporaryFolder::TemporaryFolder() {
  static std::atomic<int> counter{0};
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "vesselmesh";
  folder_ = fs::temp_directory_path() / ("vesselmesh-test-" + std::to_string(::getpid()) + "-" +
                                         std::to_string(counter++) + "-" + name);
  fs::remove_all(folder_);
  fs::create_directories(folder_);
}

TemporaryFolder::~TemporaryFolder() {
  std::error_code ec;
  fs::remove_all(folder_, ec);
}

std::vector<std::string> TemporaryFolder::files() const {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder_)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string shared_data(const std::string& relative) {
  const fs::path path = fs::path(VESSELMESH_SHARED_DATA) / relative;
  std::error_code ec;
  return fs::exists(path, ec) ? path.string() : std::string();
}

std::string test_name(const std::string& text) {
  std::string name;
  for (char c : text) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return name;
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

TriMesh tetrahedron(const Vec3& offset, double size) {
  TriMesh m;
  m.points = {offset + size * Vec3(1, 1, 1), offset + size * Vec3(1, -1, -1), offset + size * Vec3(-1, 1, -1),
              offset + size * Vec3(-1, -1, 1)};
  m.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  return m;
}

double enclosed_volume(const std::vector<Vec3>& points, const std::vector<Triangle>& faces) {
  double v = 0.0;
  for (const Triangle& f : faces) v += points[f[0]].dot(points[f[1]].cross(points[f[2]])) / 6.0;
  return v;
}

TriMesh unit_square(int n, bool flip) {
  TriMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.points.push_back(Vec3(i, j, 0) / n);
  const auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (!flip) {
        m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        m.triangles.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        m.triangles.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  return m;
}

TetMesh kuhn_box(const std::array<int, 3>& cells, const Vec3& size) {
  TetMesh mesh;
  const auto id = [&](int i, int j, int k) { return (k * (cells[1] + 1) + j) * (cells[0] + 1) + i; };
  for (int k = 0; k <= cells[2]; ++k)
    for (int j = 0; j <= cells[1]; ++j)
      for (int i = 0; i <= cells[0]; ++i)
        mesh.points.emplace_back(size.x() * i / cells[0], size.y() * j / cells[1], size.z() * k / cells[2]);
  const int paths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < cells[2]; ++k)
    for (int j = 0; j < cells[1]; ++j)
      for (int i = 0; i < cells[0]; ++i)
        for (const auto& path : paths) {
          std::array<int, 3> at = {i, j, k};
          Tet t{};
          t[0] = id(at[0], at[1], at[2]);
          for (int s = 0; s < 3; ++s) {
            ++at[path[s]];
            t[s + 1] = id(at[0], at[1], at[2]);
          }
          if (mesh::tet_volume6(mesh, t) < 0.0) std::swap(t[2], t[3]);
          mesh.tets.push_back(t);
        }
  return mesh;
}

}  // namespace vesselmesh::test
