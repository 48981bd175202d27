#include "test_support.h"

#include "io/atomic_file.h"
#include "mesh/error.h"
#include "study/picture.h"
#include "study/view3d.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <iostream>

#include <atomic>
#include <cctype>
#include <fstream>
#include <unistd.h>

#include <fmt/format.h>

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

std::string input_error(const std::string& path, const std::string& text,
                        const std::function<void(const std::string&)>& read) {
  write_bytes(path, text);
  try {
    read(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
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

double triangle_density_between(const TriMesh& mesh, double z_low, double z_high) {
  double area = 0.0;
  int count = 0;
  for (const Triangle& t : mesh.triangles) {
    const Vec3 &a = mesh.points[t[0]], &b = mesh.points[t[1]], &c = mesh.points[t[2]];
    if (const double z = (a.z() + b.z() + c.z()) / 3.0; z >= z_low && z <= z_high) {
      area += 0.5 * (b - a).cross(c - a).norm();
      ++count;
    }
  }
  return count / area;
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

std::optional<DrawnViews> draw_in_chromium(const std::string& html_file, const std::string& query) {
  const char* given = std::getenv("VESSELMESH_CHROMIUM");
  const std::string chromium = given && *given ? given : "/usr/bin/chromium";
  if (!fs::exists(chromium)) return std::nullopt;
  TemporaryFolder tmp;
  const std::string url = "file://" + fs::absolute(html_file).string() + query;
  // Headless, software WebGL, no network: the report must need none.
  const auto command = [&](int height, const std::string& action, const std::string& out) {
    return fmt::format("'{}' --headless --no-sandbox --disable-gpu --enable-unsafe-swiftshader --disable-quic "
                       "--no-first-run --disable-background-networking --disable-component-update --disable-sync "
                       "--proxy-server=http://127.0.0.1:9 --host-resolver-rules='MAP * ~NOTFOUND' "
                       "--user-data-dir='{}' --window-size=1000,{} --virtual-time-budget=30000 {} '{}' {} 2>>'{}'",
                       chromium, tmp.path("profile"), height, action, url, out, tmp.path("log.txt"));
  };
  DrawnViews d;
  const int dom = std::system(command(1200, "--dump-dom", "> '" + tmp.path("dom.html") + "'").c_str());
  const std::string page = fs::exists(tmp.path("dom.html")) ? io::read_file(tmp.path("dom.html")) : "";
  const size_t open = page.find("id=\"view3d-status\"");
  const size_t from = open == std::string::npos ? open : page.find('>', open);
  const size_t to = from == std::string::npos ? from : page.find("</pre>", from);
  if (dom == 0 && to != std::string::npos) {
    const std::string text = page.substr(from + 1, to - from - 1);
    if (text != "pending") {
      const nlohmann::json j = nlohmann::json::parse(text);
      d.status_read = true;
      d.drawn = j["drawn"].get<int>();
      d.errors = j["errors"].get<std::vector<std::string>>();
      d.rects = j["rects"].get<std::vector<std::array<int, 4>>>();
    }
  }
  int bottom = 600;
  for (const auto& r : d.rects) bottom = std::max(bottom, r[1] + r[3] + 10);
  const std::string shot = tmp.path("shot.png");
  if (std::system(command(bottom, "--screenshot='" + shot + "'", "> /dev/null").c_str()) == 0 && fs::exists(shot))
    d.screenshot = study::read_png(shot);
  d.log = fs::exists(tmp.path("log.txt")) ? io::read_file(tmp.path("log.txt")) : "";
  return d;
}

namespace {

// A pixel that the viridis scale, lit between 0.3 and 1.3 of its colour, explains (within 8 % a
// channel); or the blue-white-red difference scale, so lit.
bool in_scale(uint32_t pixel, bool difference) {
  const Vec3 p(static_cast<double>((pixel >> 16) & 255), static_cast<double>((pixel >> 8) & 255),
               static_cast<double>(pixel & 255));
  for (int k = 0; k <= 64; ++k) {
    const std::array<double, 3> v = difference ? study::diverging(k / 32.0 - 1.0) : study::viridis(k / 64.0);
    const Vec3 c = 255.0 * Vec3(v[0], v[1], v[2]);
    const double s = std::clamp(p.dot(c) / c.dot(c), 0.3, 1.3);
    if ((p - s * c).cwiseAbs().maxCoeff() < 0.08 * 255.0) return true;
  }
  return false;
}
bool drawn(uint32_t pixel) {  // not the views' white background
  return std::min({(pixel >> 16) & 255u, (pixel >> 8) & 255u, pixel & 255u}) < 250u;
}
bool wss_coloured(uint32_t pixel) { return drawn(pixel) && in_scale(pixel, false); }
bool difference_coloured(uint32_t pixel) { return drawn(pixel) && in_scale(pixel, true); }

}  // namespace

double share_of_pixels(const study::Image& image, const std::array<int, 4>& rect, bool (*test)(uint32_t)) {
  const int x0 = std::max(0, rect[0] + 3), y0 = std::max(0, rect[1] + 3);
  const int x1 = std::min(image.width, rect[0] + rect[2] - 3), y1 = std::min(image.height, rect[1] + rect[3] - 3);
  long all = 0, accepted = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      ++all;
      accepted += test(image.at(x, y)) ? 1 : 0;
    }
  return all > 0 ? static_cast<double>(accepted) / static_cast<double>(all) : 0.0;
}

void expect_views_drawn(const std::string& html, int views) {
  for (const std::string mode : {"", "=difference"}) {
    const std::optional<DrawnViews> d = draw_in_chromium(html, "?view3d" + mode);
    if (!d) GTEST_SKIP() << "Chromium is not installed (apt-get install chromium)";
    ASSERT_TRUE(d->status_read) << d->log.substr(0, 3000);
    EXPECT_TRUE(d->errors.empty()) << d->errors.front();
    ASSERT_EQ(d->drawn, views);
    ASSERT_EQ(static_cast<int>(d->rects.size()), views);
    ASSERT_GT(d->screenshot.width, 0) << d->log.substr(0, 3000);
    for (int k = 0; k < views; ++k) {
      const bool difference = !mode.empty() && k + 1 < views;  // the reference (last) keeps its |WSS|
      const double all = share_of_pixels(d->screenshot, d->rects[k], drawn);
      const double scaled =
          share_of_pixels(d->screenshot, d->rects[k], difference ? difference_coloured : wss_coloured);
      EXPECT_GT(all, 0.03) << "view " << k << mode << ": no wall drawn";
      EXPECT_GT(scaled, 0.85 * all) << "view " << k << mode << ": colours not of the scale (" << scaled << " of "
                                    << all << " of the view)";
      if (difference) {  // the toggle turned the view from the |WSS| scale
        EXPECT_LT(share_of_pixels(d->screenshot, d->rects[k], wss_coloured), 0.5 * all) << "view " << k << mode;
      }
      std::cout << "view " << k << mode << ": drawn " << all << " of the view, in the scale " << scaled << "\n";
    }
  }
}


}  // namespace vesselmesh::test
