// Helpers shared by the test suites: temporary folders, the shared real-vessel data (tests
// skip with a message where ../shared is absent), and small meshes built by hand.
#pragma once

#include "mesh/tetmesh.h"
#include "mesh/reporter.h"
#include "mesh/trimesh.h"
#include "study/raster.h"

#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace vesselmesh::test {

// A fresh empty folder under the system's temporary folder, removed at the end of the test.
class TemporaryFolder {
 public:
  TemporaryFolder();
  ~TemporaryFolder();
  std::string path(const std::string& name) const { return (folder_ / name).string(); }
  const std::filesystem::path& folder() const { return folder_; }
  // Names of the files in it (to check that nothing half-written is left behind).
  std::vector<std::string> files() const;

 private:
  std::filesystem::path folder_;
};

// Path of a file of ../shared/data, or "" when the shared folder is absent.
std::string shared_data(const std::string& relative);

// Skips the current test with a message when the shared data is absent.
#define VESSELMESH_REQUIRE_SHARED(path_variable, relative)                                  \
  const std::string path_variable = ::vesselmesh::test::shared_data(relative);             \
  if (path_variable.empty()) GTEST_SKIP() << "shared data absent (" << (relative)          \
                                          << "): this test runs beside ../shared/data only"

// A test-name-safe version of a file name: letters and digits, the rest '_'.
std::string test_name(const std::string& text);

// Writes bytes to a file.
void write_bytes(const std::string& path, const std::string& bytes);

// The message of the InputError `read` throws on a file holding `text` (written at `path` first), or
// "no error" when it throws none.
std::string input_error(const std::string& path, const std::string& text,
                        const std::function<void(const std::string&)>& read);

// The volume a closed, outward triangle surface encloses (divergence theorem).
double enclosed_volume(const std::vector<Vec3>& points, const std::vector<Triangle>& faces);

// A regular tetrahedron, outward, 4 points and 4 triangles.
TriMesh tetrahedron(const Vec3& offset = Vec3::Zero(), double size = 1.0);

// The unit square in the plane z = 0 as n x n cells, each cut into two triangles along one diagonal
// (`flip`: the other).
TriMesh unit_square(int n, bool flip = false);

// The box [0, size] cut into cells[0] x cells[1] x cells[2] cuboids, each into the six tetrahedra of
// its main diagonal (Kuhn's subdivision: neighbours share their faces' diagonals), positive; no
// boundary triangles.
TetMesh kuhn_box(const std::array<int, 3>& cells, const Vec3& size);

// Triangles per unit area of a surface between two axial positions (z of the triangles' centroids),
// as a nozzle's throat or pipe has them.
double triangle_density_between(const TriMesh& mesh, double z_low, double z_high);

// A study report's interactive 3D view (study/view3d.h) as headless Chromium draws it, the network
// off (every host unresolvable, a dead proxy): the page opened with `query` (e.g. "?view3d"), its
// status element read back from the DOM and a screenshot of the whole view taken. Nothing when
// Chromium is not installed (/usr/bin/chromium, or $VESSELMESH_CHROMIUM).
struct DrawnViews {
  bool status_read = false;             // the page filled its status element
  int drawn = 0;                        // views the page drew
  std::vector<std::string> errors;      // the page's script errors
  std::vector<std::array<int, 4>> rects;  // per view: x, y, width, height in CSS pixels (the screenshot's)
  study::Image screenshot;
  std::string log;                      // what Chromium printed on its error stream
};
std::optional<DrawnViews> draw_in_chromium(const std::string& html_file, const std::string& query);

// The share of the pixels inside `rect` (inset by 3 pixels) that `test` accepts (a 0xAARRGGBB pixel).
double share_of_pixels(const study::Image& image, const std::array<int, 4>& rect, bool (*test)(uint32_t));

// The report's views as the browser draws them (issue 53), opened with "?view3d" and
// "?view3d=difference": the page's status read, `views` views drawn without a script error, and in
// each view's rectangle of the screenshot over 3 % of the pixels drawn (not the white background),
// 85 % of those explained by the view's scale (viridis for |WSS|, lit; blue-white-red for the compared views' differences, the
// reference (the last view) keeping its |WSS|). Skips the test where Chromium is not installed.
void expect_views_drawn(const std::string& html_file, int views);

// A reporter that keeps the warnings it is given, one a line.
struct Warnings : Reporter {
  mutable std::string text;
  void warning(std::string_view message) const override { text += std::string(message) + "\n"; }
};

}  // namespace vesselmesh::test
