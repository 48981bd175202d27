#include "io/ply.h"

#include "io/atomic_file.h"
#include "io/text_cursor.h"
#include "mesh/error.h"
#include "mesh/merge_points.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

namespace vesselmesh::io {
namespace {

enum class Encoding { ascii, little_endian, big_endian };

struct Property {
  std::string name;
  int size = 0;          // bytes of a scalar (or of each list item)
  bool floating = false;
  bool is_signed = false;
  int count_size = 0;    // list properties: bytes of the count; 0 for scalars
};

struct Element {
  std::string name;
  long long count = 0;
  std::vector<Property> properties;
};

// PLY's scalar types: size, floating, signed.
bool scalar_type(std::string_view type, Property& p) {
  static const struct {
    const char* names[2];
    int size;
    bool floating, is_signed;
  } types[] = {{{"char", "int8"}, 1, false, true},    {{"uchar", "uint8"}, 1, false, false},
               {{"short", "int16"}, 2, false, true},  {{"ushort", "uint16"}, 2, false, false},
               {{"int", "int32"}, 4, false, true},    {{"uint", "uint32"}, 4, false, false},
               {{"float", "float32"}, 4, true, true}, {{"double", "float64"}, 8, true, true}};
  for (const auto& t : types)
    if (type == t.names[0] || type == t.names[1]) {
      p.size = t.size, p.floating = t.floating, p.is_signed = t.is_signed;
      return true;
    }
  return false;
}

class PlyReader {
 public:
  PlyReader(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name), text_(bytes, name, "PLY") {}
  TriMesh read();

 private:
  [[noreturn]] void fail(const std::string& what) const { throw InputError(fmt::format("{}: PLY: {}", name_, what)); }
  void read_header();
  double binary_value(int size, bool floating, bool is_signed);
  double value(int size, bool floating, bool is_signed);
  void read_element(const Element& element, TriMesh& mesh);

  std::string_view bytes_;
  std::string name_;
  TextCursor text_;
  Encoding encoding_ = Encoding::ascii;
  std::vector<Element> elements_;
  size_t pos_ = 0;  // binary body position
};

void PlyReader::read_header() {
  if (text_.word() != "ply") fail("not a PLY file (it does not start with 'ply')");
  for (;;) {
    const std::string_view keyword = text_.word();
    if (keyword.empty()) fail("the header ends without 'end_header'");
    if (keyword == "end_header") break;
    if (keyword == "comment" || keyword == "obj_info") {
      text_.rest_of_line();
    } else if (keyword == "format") {
      const std::string_view format = text_.word();
      if (format == "ascii") encoding_ = Encoding::ascii;
      else if (format == "binary_little_endian") encoding_ = Encoding::little_endian;
      else if (format == "binary_big_endian") encoding_ = Encoding::big_endian;
      else text_.fail(fmt::format("unknown format {}", TextCursor::quoted(format)));
      text_.rest_of_line();
    } else if (keyword == "element") {
      Element e;
      e.name = std::string(text_.word());
      e.count = text_.integer();
      // Every instance takes at least a byte: a count beyond the file's size is damage.
      if (e.count < 0 || static_cast<unsigned long long>(e.count) > bytes_.size())
        text_.fail(fmt::format("element '{}' declares {} instances in a file of {} bytes", e.name, e.count, bytes_.size()));
      elements_.push_back(std::move(e));
    } else if (keyword == "property") {
      if (elements_.empty()) text_.fail("a property before any element");
      Property p;
      std::string_view type = text_.word();
      if (type == "list") {
        Property count;
        if (!scalar_type(text_.word(), count) || count.floating) text_.fail("a list count must be an integer type");
        p.count_size = count.size;
        type = text_.word();
      }
      if (!scalar_type(type, p)) text_.fail(fmt::format("unknown property type {}", TextCursor::quoted(type)));
      p.name = std::string(text_.word());
      elements_.back().properties.push_back(std::move(p));
    } else {
      text_.fail(fmt::format("unknown header keyword {}", TextCursor::quoted(keyword)));
    }
  }
  // The binary body starts after the newline that ends "end_header".
  pos_ = bytes_.find('\n', text_.position());
  pos_ = pos_ == std::string_view::npos ? bytes_.size() : pos_ + 1;
}

double PlyReader::binary_value(int size, bool floating, bool is_signed) {
  if (pos_ + size > bytes_.size()) fail(fmt::format("the file ends in the middle of the data (byte {})", bytes_.size()));
  unsigned char raw[8];
  std::memcpy(raw, bytes_.data() + pos_, size);
  pos_ += size;
  if ((encoding_ == Encoding::big_endian) == (std::endian::native == std::endian::little))
    std::reverse(raw, raw + size);
  auto get = [&raw](auto v) {
    std::memcpy(&v, raw, sizeof v);
    return static_cast<double>(v);
  };
  if (floating) return size == 4 ? get(float{}) : get(double{});
  switch (size) {
    case 1: return is_signed ? get(int8_t{}) : get(uint8_t{});
    case 2: return is_signed ? get(int16_t{}) : get(uint16_t{});
    default: return is_signed ? get(int32_t{}) : get(uint32_t{});
  }
}

double PlyReader::value(int size, bool floating, bool is_signed) {
  if (encoding_ != Encoding::ascii) return binary_value(size, floating, is_signed);
  if (floating) return text_.number();
  return static_cast<double>(text_.integer());
}

void PlyReader::read_element(const Element& element, TriMesh& mesh) {
  const bool vertex = element.name == "vertex", face = element.name == "face";
  int axis[3] = {-1, -1, -1}, indices = -1;
  for (size_t i = 0; i < element.properties.size(); ++i) {
    const Property& p = element.properties[i];
    for (int k = 0; k < 3; ++k)
      if (vertex && p.name == std::string(1, char('x' + k)) && p.count_size == 0) axis[k] = static_cast<int>(i);
    if (face && (p.name == "vertex_indices" || p.name == "vertex_index") && p.count_size > 0) indices = static_cast<int>(i);
  }
  if (vertex && (axis[0] < 0 || axis[1] < 0 || axis[2] < 0)) fail("the vertex element has no x, y and z properties");
  if (face && indices < 0) fail("the face element has no vertex_indices list");
  std::vector<double> polygon;  // as read: an index list may be stored as floating point
  for (long long n = 0; n < element.count; ++n) {
    Vec3 p = Vec3::Zero();
    for (size_t i = 0; i < element.properties.size(); ++i) {
      const Property& prop = element.properties[i];
      if (prop.count_size == 0) {
        const double v = value(prop.size, prop.floating, prop.is_signed);
        for (int k = 0; k < 3; ++k)
          if (axis[k] == static_cast<int>(i)) p[k] = v;
        continue;
      }
      const double items = value(prop.count_size, false, false);
      if (!(items >= 0 && items <= 1e6)) fail(fmt::format("{} {} has a list of {} items", element.name, n, items));
      polygon.clear();
      for (int k = 0; k < static_cast<int>(items); ++k) polygon.push_back(value(prop.size, prop.floating, prop.is_signed));
      if (static_cast<int>(i) != indices) continue;
      for (double id : polygon)
        if (!(id >= 0 && id < mesh.num_points()) || id != std::floor(id))
          fail(fmt::format("face {} uses vertex {}, but there are {} vertices before it", n, id, mesh.num_points()));
      for (size_t k = 1; k + 1 < polygon.size(); ++k)  // fan
        mesh.triangles.push_back({int(polygon[0]), int(polygon[k]), int(polygon[k + 1])});
    }
    if (vertex) {
      if (!p.allFinite()) fail(fmt::format("vertex {} has a non-finite coordinate ({}, {}, {})", n, p.x(), p.y(), p.z()));
      mesh.points.push_back(p);
    }
  }
}

TriMesh PlyReader::read() {
  read_header();
  TriMesh mesh;
  for (const Element& e : elements_) read_element(e, mesh);
  if (mesh.triangles.empty()) fail("no faces (a surface is needed)");
  mesh::remap_triangles(mesh.triangles, mesh::merge_identical_points(mesh.points));
  return mesh;
}

}  // namespace

TriMesh parse_ply(std::string_view bytes, const std::string& name) {
  if (bytes.empty()) throw InputError(fmt::format("{}: the file is empty", name));
  return PlyReader(bytes, name).read();
}

TriMesh read_ply(const std::string& path) { return parse_ply(read_file(path), path); }

}  // namespace vesselmesh::io
