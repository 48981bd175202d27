#include "io/msh_stream.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <compare>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <numeric>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

namespace vesselmesh::io {
namespace {

constexpr int kTriangle3 = 2, kTetrahedron4 = 4, kPrism6 = 6;  // Gmsh element types

// Whitespace-separated words of a file read in blocks; a word is valid until the next call.
// (io/text_cursor.h reads a text held whole in memory: for a 2 M-tetrahedron mesh that is the
// 90 MB file on top of the mesh, which this reader exists to avoid.)
class Words {
 public:
  explicit Words(const std::string& path) : path_(path), file_(std::fopen(path.c_str(), "rb"), &std::fclose) {
    if (!file_) throw InputError(fmt::format("{}: cannot open: {}", path, std::strerror(errno)));
    buffer_.resize(kBlock);
  }

  // The next word, or empty at the end of the file.
  std::string_view word() {
    if (!skip_space()) return {};
    size_t end = pos_;
    while (true) {
      while (end < size_ && !is_space(buffer_[end])) ++end;
      if (end < size_ || eof_) break;
      if (end - pos_ >= kLongest) fail("a word longer than 256 characters");
      end -= pos_;
      refill();
      end += pos_;
    }
    const std::string_view w(buffer_.data() + pos_, end - pos_);
    pos_ = end;
    return w;
  }
  // The next word, which must be there.
  std::string_view next(std::string_view what) {
    const std::string_view w = word();
    if (w.empty()) fail(fmt::format("the file ends where {} was expected", what));
    return w;
  }
  long long integer(std::string_view what) {
    const std::string_view w = next(what);
    long long value = 0;
    const auto [end, error] = std::from_chars(w.data(), w.data() + w.size(), value);
    if (error != std::errc() || end != w.data() + w.size())
      fail(fmt::format("expected {} (a whole number), found \"{}\"", what, w));
    return value;
  }
  int count(std::string_view what) {
    const long long value = integer(what);
    if (value < 0 || value > 2'000'000'000) fail(fmt::format("{} {} is out of range", what, value));
    return static_cast<int>(value);
  }
  double number(std::string_view what) {
    const std::string_view w = next(what);
    double value = 0.0;
    const auto [end, error] = std::from_chars(w.data(), w.data() + w.size(), value);
    if (error != std::errc() || end != w.data() + w.size() || !std::isfinite(value))
      fail(fmt::format("expected {} (a finite number), found \"{}\"", what, w));
    return value;
  }
  // A name in double quotes (spaces kept).
  std::string quoted() {
    if (!skip_space() || buffer_[pos_] != '"') fail("expected a name in double quotes");
    ++pos_;
    std::string name;
    while (true) {
      if (pos_ == size_ && (eof_ || (refill(), pos_ == size_))) fail("a quoted name is not closed");
      const char c = buffer_[pos_++];
      if (c == '"') return name;
      if (c == '\n') fail("a quoted name is not closed on its line");
      name += c;
    }
  }
  // Skips the rest of the current line.
  void skip_line() {
    while (true) {
      while (pos_ < size_ && buffer_[pos_] != '\n') ++pos_;
      if (pos_ < size_) {
        ++pos_;
        ++line_;
        return;
      }
      if (eof_) return;
      refill();
    }
  }
  void expect(std::string_view keyword) {
    const std::string_view w = word();
    if (w != keyword) fail(fmt::format("expected {}, found \"{}\"", keyword, w));
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(fmt::format("{}:{}: MSH: {}", path_, line_, what));
  }

 private:
  static constexpr size_t kBlock = 1 << 20, kLongest = 256;
  static bool is_space(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }
  // Moves to the next word's start (counting lines); false at the end of the file.
  bool skip_space() {
    while (true) {
      while (pos_ < size_ && is_space(buffer_[pos_])) line_ += buffer_[pos_++] == '\n';
      if (pos_ < size_) return true;
      if (eof_) return false;
      refill();
    }
  }
  // Keeps the unread bytes and reads more after them.
  void refill() {
    std::memmove(buffer_.data(), buffer_.data() + pos_, size_ - pos_);
    size_ -= pos_;
    pos_ = 0;
    const size_t got = std::fread(buffer_.data() + size_, 1, buffer_.size() - size_, file_.get());
    size_ += got;
    if (got == 0) eof_ = true;
  }

  std::string path_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  std::vector<char> buffer_;
  size_t pos_ = 0, size_ = 0;
  bool eof_ = false;
  int line_ = 1;
};

// A block of nodes or elements: its entity and where it was in the file.
struct EntityKey {
  int dim, tag;
  auto operator<=>(const EntityKey&) const = default;
};

struct Reader {
  explicit Reader(Words& words) : in(words) {}
  Words& in;
  std::map<std::pair<int, int>, std::string> physical_names;  // (dim, tag) -> name
  std::map<EntityKey, int> entity_group;                      // (dim, entity) -> its first physical tag
  std::vector<int> surfaces;                                  // the surface entities
  // Nodes: the tags of each block and their coordinates, in the file's order, then placed.
  std::vector<EntityKey> node_blocks;
  std::vector<size_t> node_block_start;
  std::vector<long long> node_tags;
  std::vector<Vec3> coordinates;
  // Node tag -> point index, once the nodes are placed: an array over the tags' range (-1: none),
  // or a map where the tags are sparse (a range over 4 times the nodes).
  std::vector<int> index_of_tag;
  std::unordered_map<long long, int> sparse_index;
  bool sparse = false;
  long long least_tag = 0;
  bool nodes_read = false;
  // Elements by entity: tetrahedra and prisms of the volumes, triangles of the surfaces.
  std::map<int, std::vector<Tet>> tets;
  std::map<int, std::vector<Prism>> prisms;
  std::map<int, std::vector<Triangle>> triangles;

  void physical_names_section() {
    const int n = in.count("the number of physical names");
    for (int k = 0; k < n; ++k) {
      const int dim = in.count("a physical name's dimension");
      const int tag = static_cast<int>(in.integer("a physical name's tag"));
      physical_names[{dim, tag}] = in.quoted();
    }
    in.expect("$EndPhysicalNames");
  }

  void entities_section() {
    int counts[4];
    for (int& c : counts) c = in.count("the number of entities");
    for (int dim = 0; dim < 4; ++dim)
      for (int k = 0; k < counts[dim]; ++k) {
        const int tag = static_cast<int>(in.integer("an entity's tag"));
        for (int c = 0; c < (dim == 0 ? 3 : 6); ++c) in.number("an entity's coordinates");
        const int physicals = in.count("an entity's number of physical tags");
        for (int p = 0; p < physicals; ++p) {
          const int physical = static_cast<int>(in.integer("a physical tag"));
          if (p == 0) entity_group[{dim, tag}] = physical;
        }
        if (dim > 0) {
          const int bounding = in.count("an entity's number of bounding entities");
          for (int b = 0; b < bounding; ++b) in.integer("a bounding entity");
        }
        if (dim == 2) surfaces.push_back(tag);
      }
    in.expect("$EndEntities");
  }

  void nodes_section() {
    const int blocks = in.count("the number of node blocks");
    const long long total = in.integer("the number of nodes");
    least_tag = in.integer("the least node tag");
    const long long most_tag = in.integer("the largest node tag");
    if (total < 0 || total > 2'000'000'000 || (total > 0 && most_tag < least_tag))
      in.fail(fmt::format("node counts out of range ({} nodes, tags {} to {})", total, least_tag, most_tag));
    sparse = most_tag - least_tag >= 4 * total + 1024;
    node_tags.reserve(static_cast<size_t>(total));
    coordinates.reserve(static_cast<size_t>(total));
    for (int b = 0; b < blocks; ++b) {
      const int dim = in.count("a node block's dimension");
      const int tag = static_cast<int>(in.integer("a node block's entity"));
      const long long parametric = in.integer("a node block's parametric flag");
      const int n = in.count("a node block's number of nodes");
      node_blocks.push_back({dim, tag});
      node_block_start.push_back(node_tags.size());
      for (int k = 0; k < n; ++k) node_tags.push_back(in.integer("a node tag"));
      for (int k = 0; k < n; ++k) {
        Vec3& x = coordinates.emplace_back();
        for (int c = 0; c < 3; ++c) x[c] = in.number("a node's coordinate");
        if (parametric) for (int c = 0; c < dim; ++c) in.number("a node's parametric coordinate");
      }
    }
    node_block_start.push_back(node_tags.size());
    in.expect("$EndNodes");
    place_nodes(most_tag);
  }

  // The points in the order of their entities (by dimension, then tag; Gmsh's getNodes), and each
  // node tag's point.
  void place_nodes(long long most_tag) {
    std::vector<int> order(node_blocks.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return node_blocks[a] < node_blocks[b]; });
    if (!sparse) index_of_tag.assign(static_cast<size_t>(std::max(0LL, most_tag - least_tag + 1)), -1);
    std::vector<Vec3> points;
    points.reserve(coordinates.size());
    for (int b : order)
      for (size_t k = node_block_start[b]; k < node_block_start[b + 1]; ++k) {
        if (node_tags[k] < least_tag || node_tags[k] > most_tag)
          in.fail(fmt::format("node tag {} is outside the section's range {} to {}", node_tags[k], least_tag, most_tag));
        const int next = static_cast<int>(points.size());
        const bool fresh = sparse ? sparse_index.emplace(node_tags[k], next).second
                                  : std::exchange(index_of_tag[static_cast<size_t>(node_tags[k] - least_tag)], next) < 0;
        if (!fresh) in.fail(fmt::format("node {} is defined twice", node_tags[k]));
        points.push_back(coordinates[k]);
      }
    coordinates = std::move(points);
    std::vector<long long>().swap(node_tags);
    nodes_read = true;
  }

  int point(long long tag) {
    if (sparse) {
      const auto found = sparse_index.find(tag);
      if (found != sparse_index.end()) return found->second;
    } else {
      const long long k = tag - least_tag;
      if (k >= 0 && k < static_cast<long long>(index_of_tag.size()) && index_of_tag[static_cast<size_t>(k)] >= 0)
        return index_of_tag[static_cast<size_t>(k)];
    }
    in.fail(fmt::format("an element uses node {}, which the file does not define", tag));
  }

  template <size_t N>
  void read_elements(int n, std::vector<std::array<int, N>>& out) {
    out.reserve(out.size() + static_cast<size_t>(n));
    for (int k = 0; k < n; ++k) {
      in.integer("an element tag");
      std::array<int, N>& e = out.emplace_back();
      for (size_t c = 0; c < N; ++c) e[c] = point(in.integer("an element's node"));
    }
  }

  void elements_section() {
    if (!nodes_read) in.fail("$Elements before $Nodes");
    const int blocks = in.count("the number of element blocks");
    for (int c = 0; c < 3; ++c) in.integer("the element counts");
    for (int b = 0; b < blocks; ++b) {
      const int dim = in.count("an element block's dimension");
      const int tag = static_cast<int>(in.integer("an element block's entity"));
      const int type = in.count("an element block's type");
      const int n = in.count("an element block's number of elements");
      if (dim == 3 && type == kTetrahedron4) read_elements(n, tets[tag]);
      else if (dim == 3 && type == kPrism6) read_elements(n, prisms[tag]);
      else if (dim == 2 && type == kTriangle3) read_elements(n, triangles[tag]);
      else {
        in.skip_line();  // the block's header line
        for (int k = 0; k < n; ++k) in.skip_line();
        continue;
      }
    }
    in.expect("$EndElements");
  }

  // What is left after a section this reader does not use.
  void skip_section(std::string_view name) {
    const std::string end = "$End" + std::string(name.substr(1));
    while (true) {
      const std::string_view w = in.word();
      if (w.empty()) in.fail(fmt::format("{} is not closed by {}", name, end));
      if (w == end) return;
    }
  }
};

}  // namespace

std::optional<TetMesh> read_msh41_volume(const std::string& path) {
  Words in(path);
  if (in.word() != "$MeshFormat") return std::nullopt;
  const std::string version(in.next("the MSH version")), type(in.next("the MSH file type"));
  if (version != "4.1" || type != "0") return std::nullopt;
  in.next("the MSH data size");
  in.expect("$EndMeshFormat");
  Reader r(in);
  while (true) {
    const std::string section(in.word());
    if (section.empty()) break;
    if (section == "$PhysicalNames") r.physical_names_section();
    else if (section == "$Entities") r.entities_section();
    else if (section == "$Nodes") r.nodes_section();
    else if (section == "$Elements") r.elements_section();
    else if (section.size() > 1 && section[0] == '$') r.skip_section(section);
    else in.fail(fmt::format("expected a section ($Name), found \"{}\"", section));
  }

  TetMesh mesh;
  mesh.points = std::move(r.coordinates);
  const auto group = [&](int dim, int entity, bool& grouped, std::string& name) {
    const auto found = r.entity_group.find({dim, entity});
    grouped = found != r.entity_group.end();
    const int tag = grouped ? found->second : entity;
    const auto named = r.physical_names.find({dim, tag});
    name = grouped && named != r.physical_names.end() ? named->second : "";
    return tag;
  };
  // The volume entities by tag: each one's tetrahedra, then its prisms.
  std::vector<int> volumes;
  for (const auto& [entity, list] : r.tets) volumes.push_back(entity);
  for (const auto& [entity, list] : r.prisms) volumes.push_back(entity);
  for (const auto& [key, physical] : r.entity_group)
    if (key.dim == 3) volumes.push_back(key.tag);
  const auto sorted = [](std::vector<int>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  };
  sorted(volumes);
  for (int entity : volumes) {
    bool grouped = false;
    std::string name;
    const int tag = group(3, entity, grouped, name);
    if (grouped) {
      mesh.volume_tag = tag;
      mesh.volume_name = name;
    }
    std::vector<Tet>& t = r.tets[entity];
    if (mesh.tets.empty()) mesh.tets = std::move(t);
    else mesh.tets.insert(mesh.tets.end(), t.begin(), t.end());
    std::vector<Tet>().swap(t);
    for (const Prism& p : r.prisms[entity]) mesh.prisms.push_back(mesh::flipped_prism(p));
  }
  // The surface entities by tag, those without triangles named too.
  std::vector<int> surfaces = r.surfaces;
  for (const auto& [entity, list] : r.triangles) surfaces.push_back(entity);
  sorted(surfaces);
  for (int entity : surfaces) {
    bool grouped = false;
    std::string name;
    const int tag = group(2, entity, grouped, name);
    mesh.tag_names[tag] = name.empty() ? mesh::unnamed_tag(tag) : name;
    for (const Triangle& f : r.triangles[entity]) {
      mesh.boundary.push_back(f);
      mesh.boundary_tags.push_back(tag);
    }
  }
  if (mesh.tets.empty() && mesh.prisms.empty())
    throw InputError(fmt::format("{}: the MSH file has no tetrahedra or prisms (a volume mesh is needed)", path));
  return mesh;
}

}  // namespace vesselmesh::io
