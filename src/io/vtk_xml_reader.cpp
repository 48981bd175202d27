// VTP and VTU surfaces read with VTK's XML parser and data decoder (vtkXMLDataParser: ascii,
// base64 and raw appended data, zlib/lz4/lzma compression) but not with vtkXMLPolyDataReader,
// which crashes on some malformed files (duplicate array names, short ascii arrays): every
// count, offset and index here is checked before it is used, so a bad file is an InputError.
#include "io/vtk_formats.h"
#include "io/vtk_internal.h"

#include "io/atomic_file.h"
#include "io/base64.h"

#include "mesh/error.h"
#include "mesh/merge_points.h"

#include <fmt/format.h>

#include <vtkLZ4DataCompressor.h>
#include <vtkLZMADataCompressor.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkType.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkZLibDataCompressor.h>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <limits>
#include <set>
#include <sstream>

namespace vesselmesh::io {
namespace {

// VTK cell types this reader takes from a VTU.
constexpr int kVtkTriangle = 5, kVtkTriangleStrip = 6, kVtkPolygon = 7, kVtkQuad = 9, kVtkTetra = 10,
              kVtkWedge = 13;

class XmlSurfaceReader {
 public:
  XmlSurfaceReader(std::string_view bytes, VtkFormat format, const std::string& name)
      : bytes_(bytes), stream_(std::string(bytes)), format_(format), name_(name), input_size_(bytes.size()) {}

  SurfaceData read(const std::string& label_array, bool lines_only);
  // A volume mesh: tetrahedra, wedges and boundary triangles, with cell data `tag` (and
  // `layer`, `column` when present) and field data `tag_names`, as write_vtu writes them.
  TetMesh read_volume(std::vector<Field>* point_data);

 private:
  [[noreturn]] void fail(const std::string& what) const { throw InputError(fmt::format("{}: {}", name_, what)); }

  std::string attribute(vtkXMLDataElement* e, const char* key) const {
    const char* value = e->GetAttribute(key);
    return value ? value : "";
  }

  long long count_attribute(vtkXMLDataElement* e, const char* key, bool required) const;
  void parse_root();
  // Reads a DataArray of `tuples` tuples into doubles; `components` is taken from the file
  // and checked against `expected_components` when that is positive.
  std::vector<double> read_array(vtkXMLDataElement* array, long long tuples, int expected_components,
                                 int* components = nullptr);
  std::vector<long long> read_index_array(vtkXMLDataElement* parent, const char* array_name, long long count,
                                          const char* what);
  void read_piece(vtkXMLDataElement* piece, SurfaceData& out, std::vector<Field>& cell_fields);
  template <typename Visit>
  void read_cell_section(vtkXMLDataElement* piece, const char* section, Visit visit);
  void read_polydata_cells(vtkXMLDataElement* piece, int point_base, long long cell_base, SurfaceData& out,
                           std::vector<long long>& cell_of_triangle);
  void read_grid_cells(vtkXMLDataElement* piece, long long cells, int point_base, long long cell_base,
                       TriMesh& mesh, std::vector<long long>& cell_of_triangle);
  void add_polygon(const long long* ids, long long n, long long points, int point_base, long long cell,
                   TriMesh& mesh, std::vector<long long>& cell_of_triangle, bool strip);
  std::vector<Field> read_fields(vtkXMLDataElement* data, long long tuples, const char* where);
  void read_points(vtkXMLDataElement* piece, long long points, std::vector<Vec3>& out);
  std::vector<std::string> read_strings(vtkXMLDataElement* array);
  std::string stored_bytes(vtkXMLDataElement* array, bool appended, long long offset, size_t count) const;
  // Token i of a binary header (UInt32 or UInt64, the file's byte order).
  uint64_t header_token(const std::string& bytes, size_t i) const {
    unsigned char raw[8] = {};
    std::memcpy(raw, bytes.data() + i * header_size_, header_size_);
    if (big_endian_) std::reverse(raw, raw + header_size_);
    uint64_t v = 0;
    for (int k = header_size_ - 1; k >= 0; --k) v = (v << 8) | raw[k];
    return v;
  }
  void check_compression_header(vtkXMLDataElement* array, const std::string& label, bool appended, long long offset,
                                size_t expected_bytes) const;

  std::string_view bytes_;
  std::istringstream stream_;
  VtkFormat format_;
  std::string name_;
  size_t input_size_;
  vtkNew<vtkXMLDataParser> parser_;
  vtkXMLDataElement* dataset_ = nullptr;
  bool compressed_ = false;
  int header_size_ = 4;        // bytes of a header token: UInt32 or UInt64
  bool big_endian_ = false;
  bool appended_base64_ = false;
  TetMesh* volume_ = nullptr;  // set while reading a volume: its cells go there
  std::vector<long long> cell_of_tet_, cell_of_prism_;
};

int word_type(const std::string& type) {
  static const std::pair<const char*, int> types[] = {
      {"Int8", VTK_TYPE_INT8},       {"UInt8", VTK_TYPE_UINT8},     {"Int16", VTK_TYPE_INT16},
      {"UInt16", VTK_TYPE_UINT16},   {"Int32", VTK_TYPE_INT32},     {"UInt32", VTK_TYPE_UINT32},
      {"Int64", VTK_TYPE_INT64},     {"UInt64", VTK_TYPE_UINT64},   {"Float32", VTK_TYPE_FLOAT32},
      {"Float64", VTK_TYPE_FLOAT64}};
  for (const auto& [text, value] : types)
    if (type == text) return value;
  return -1;
}

double word_value(const unsigned char* p, int type) {
  auto get = [p](auto v) {
    std::memcpy(&v, p, sizeof v);
    return static_cast<double>(v);
  };
  switch (type) {
    case VTK_TYPE_INT8: return get(int8_t{});
    case VTK_TYPE_UINT8: return get(uint8_t{});
    case VTK_TYPE_INT16: return get(int16_t{});
    case VTK_TYPE_UINT16: return get(uint16_t{});
    case VTK_TYPE_INT32: return get(int32_t{});
    case VTK_TYPE_UINT32: return get(uint32_t{});
    case VTK_TYPE_INT64: return get(int64_t{});
    case VTK_TYPE_UINT64: return get(uint64_t{});
    case VTK_TYPE_FLOAT32: return get(float{});
    default: return get(double{});
  }
}

bool integral(int type) { return type != VTK_TYPE_FLOAT32 && type != VTK_TYPE_FLOAT64; }

long long XmlSurfaceReader::count_attribute(vtkXMLDataElement* e, const char* key, bool required) const {
  const std::string text = attribute(e, key);
  if (text.empty()) {
    if (required) fail(fmt::format("<{}> has no {}", e->GetName(), key));
    return 0;
  }
  long long value = -1;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value < 0)
    fail(fmt::format("<{}> {}=\"{}\" is not a count", e->GetName(), key, text.substr(0, 30)));
  return value;
}

void XmlSurfaceReader::parse_root() {
  parser_->SetStream(&stream_);
  if (!parser_->Parse()) fail(fmt::format("cannot read it as {}: {}", vtk_format_name(format_), vtk_error_text()));
  vtkXMLDataElement* root = parser_->GetRootElement();
  if (!root || std::strcmp(root->GetName(), "VTKFile") != 0) fail("not a VTK XML file (no <VTKFile> element)");
  const char* type = format_ == VtkFormat::vtp ? "PolyData" : "UnstructuredGrid";
  if (attribute(root, "type") != type)
    fail(fmt::format("a VTK XML file of type '{}', not {}", attribute(root, "type"), type));
  const std::string compressor = attribute(root, "compressor");
  if (compressor == "vtkZLibDataCompressor") parser_->SetCompressor(vtkSmartPointer<vtkZLibDataCompressor>::New());
  else if (compressor == "vtkLZ4DataCompressor") parser_->SetCompressor(vtkSmartPointer<vtkLZ4DataCompressor>::New());
  else if (compressor == "vtkLZMADataCompressor") parser_->SetCompressor(vtkSmartPointer<vtkLZMADataCompressor>::New());
  else if (!compressor.empty()) fail(fmt::format("unknown compressor '{}'", compressor.substr(0, 40)));
  compressed_ = !compressor.empty();
  header_size_ = attribute(root, "header_type") == "UInt64" ? 8 : 4;
  big_endian_ = attribute(root, "byte_order") == "BigEndian";
  if (vtkXMLDataElement* appended = root->FindNestedElementWithName("AppendedData"))
    appended_base64_ = attribute(appended, "encoding") == "base64";
  dataset_ = root->FindNestedElementWithName(type);
  if (!dataset_) fail(fmt::format("no <{}> element", type));
}

std::vector<double> XmlSurfaceReader::read_array(vtkXMLDataElement* array, long long tuples, int expected_components,
                                                 int* components_out) {
  const std::string name = attribute(array, "Name");
  const std::string label = name.empty() ? std::string("an unnamed array") : fmt::format("array '{}'", name.substr(0, 40));
  const int type = word_type(attribute(array, "type"));
  if (type < 0) fail(fmt::format("{} has type '{}', not a number type", label, attribute(array, "type").substr(0, 20)));
  const long long components = attribute(array, "NumberOfComponents").empty()
                                   ? 1
                                   : count_attribute(array, "NumberOfComponents", true);
  if (components < 1 || components > 64) fail(fmt::format("{} has {} components", label, components));
  if (expected_components > 0 && components != expected_components)
    fail(fmt::format("{} has {} components, {} expected", label, components, expected_components));
  const size_t word = parser_->GetWordTypeSize(type);
  // Compressed data can be about a thousand times smaller than what it holds, no more.
  const double bytes = static_cast<double>(tuples) * components * word;
  if (bytes > 1100.0 * static_cast<double>(input_size_) + 1e6 || bytes > 8e9)
    fail(fmt::format("{} declares {} values, more than a file of {} bytes can hold", label, tuples * components,
                     input_size_));
  const size_t count = static_cast<size_t>(tuples * components);
  std::vector<unsigned char> raw(count * word + 1);
  size_t read = 0;
  const std::string format = attribute(array, "format");
  if (count > 0) {
    if (format == "appended") {
      const long long offset = count_attribute(array, "offset", true);
      check_compression_header(array, label, true, offset, count * word);
      read = parser_->ReadAppendedData(offset, raw.data(), 0, count, type);
    } else if (format == "ascii" || format == "binary") {
      if (format == "binary") check_compression_header(array, label, false, 0, count * word);
      read = parser_->ReadInlineData(array, format == "ascii", raw.data(), 0, count, type);
    } else {
      fail(fmt::format("{} has format '{}' (ascii, binary or appended expected)", label, format.substr(0, 20)));
    }
  }
  if (read != count) fail(fmt::format("{}: {} values expected, {} could be read", label, count, read));
  std::vector<double> values(count);
  for (size_t i = 0; i < count; ++i) values[i] = word_value(raw.data() + i * word, type);
  if (components_out) *components_out = static_cast<int>(components);
  return values;
}

std::string XmlSurfaceReader::stored_bytes(vtkXMLDataElement* array, bool appended, long long offset,
                                           size_t count) const {
  if (appended) {
    const long long start = parser_->GetAppendedDataPosition() + offset;
    if (parser_->GetAppendedDataPosition() <= 0 || start < 0 || static_cast<size_t>(start) >= bytes_.size()) return {};
    if (appended_base64_) return decode_base64(bytes_, static_cast<size_t>(start), count);
    return std::string(bytes_.substr(static_cast<size_t>(start), count));
  }
  const long long at = array->GetXMLByteIndex();  // the element's '<'
  if (at < 0 || static_cast<size_t>(at) >= bytes_.size()) return {};
  const size_t close = bytes_.find('>', static_cast<size_t>(at));
  if (close == std::string_view::npos) return {};
  return decode_base64(bytes_, close + 1, count);
}

// vtkXMLDataParser trusts the block table of compressed data and allocates what it says (a
// damaged file asked for 16 GB). The table is checked here first: it must describe exactly
// the array's bytes, in blocks that fit in the file.
void XmlSurfaceReader::check_compression_header(vtkXMLDataElement* array, const std::string& label, bool appended,
                                                long long offset, size_t expected_bytes) const {
  if (!compressed_) return;
  auto token = [&](const std::string& bytes, size_t i) { return header_token(bytes, i); };
  const std::string head = stored_bytes(array, appended, offset, 3 * static_cast<size_t>(header_size_));
  if (head.size() < 3 * static_cast<size_t>(header_size_)) fail(fmt::format("{}: its compressed data is cut short", label));
  const uint64_t blocks = token(head, 0), block_size = token(head, 1), last_size = token(head, 2);
  const uint64_t total = blocks == 0 ? 0 : (last_size == 0 ? blocks * block_size : (blocks - 1) * block_size + last_size);
  if (blocks > input_size_ || block_size > (1ull << 31) || last_size > block_size || total != expected_bytes)
    fail(fmt::format("{}: its compression header describes {} blocks of {} bytes, not the {} bytes the array holds",
                     label, blocks, block_size, expected_bytes));
  const std::string table = stored_bytes(array, appended, offset, (3 + blocks) * header_size_);
  if (table.size() < (3 + blocks) * header_size_) fail(fmt::format("{}: its compressed data is cut short", label));
  uint64_t compressed = 0;
  for (uint64_t b = 0; b < blocks; ++b) compressed += std::min<uint64_t>(token(table, 3 + b), 1ull << 40);
  if (compressed > input_size_)
    fail(fmt::format("{}: its compressed blocks add up to {} bytes, more than the file has", label, compressed));
}

std::vector<long long> XmlSurfaceReader::read_index_array(vtkXMLDataElement* parent, const char* array_name,
                                                          long long count, const char* what) {
  vtkXMLDataElement* array = nullptr;
  for (int i = 0; i < parent->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* e = parent->GetNestedElement(i);
    if (std::strcmp(e->GetName(), "DataArray") == 0 && attribute(e, "Name") == array_name) array = e;
  }
  if (!array) fail(fmt::format("<{}> has no '{}' array", parent->GetName(), array_name));
  const std::vector<double> values = read_array(array, count, 1);
  std::vector<long long> out(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    if (!(values[i] >= 0.0 && values[i] < 9e15) || values[i] != std::floor(values[i]))
      fail(fmt::format("{} '{}' value {} is {}, not an index", what, array_name, i, values[i]));
    out[i] = static_cast<long long>(values[i]);
  }
  return out;
}

void XmlSurfaceReader::add_polygon(const long long* ids, long long n, long long points, int point_base,
                                   long long cell, TriMesh& mesh, std::vector<long long>& cell_of_triangle,
                                   bool strip) {
  for (long long i = 0; i < n; ++i)
    if (ids[i] >= points)
      fail(fmt::format("cell {} uses point {}, but the piece has {} points", cell, ids[i], points));
  for (long long k = 0; k + 2 < n; ++k) {  // fan for polygons, alternating for strips
    Triangle f = strip ? Triangle{int(ids[k]), int(ids[k + 1]), int(ids[k + 2])}
                       : Triangle{int(ids[0]), int(ids[k + 1]), int(ids[k + 2])};
    if (strip && k % 2 == 1) std::swap(f[0], f[1]);
    for (int& v : f) v += point_base;
    mesh.triangles.push_back(f);
    cell_of_triangle.push_back(cell);
  }
}

template <typename Visit>
void XmlSurfaceReader::read_cell_section(vtkXMLDataElement* piece, const char* section, Visit visit) {
  const long long n = count_attribute(piece, (std::string("NumberOf") + section).c_str(), false);
  if (n == 0) return;
  vtkXMLDataElement* element = piece->FindNestedElementWithName(section);
  if (!element) fail(fmt::format("the piece declares {} {} but has no <{}>", n, section, section));
  const std::vector<long long> offsets = read_index_array(element, "offsets", n, section);
  const long long total = offsets.back();
  if (static_cast<double>(total) > 4.0 * static_cast<double>(input_size_) * 1100.0 + 1e6)
    fail(fmt::format("<{}> offsets declare {} indices, more than the file can hold", section, total));
  const std::vector<long long> ids = read_index_array(element, "connectivity", total, section);
  long long start = 0;
  for (long long c = 0; c < n; ++c) {
    if (offsets[c] < start || offsets[c] > total)
      fail(fmt::format("<{}> offsets are not increasing up to {} at cell {}", section, total, c));
    visit(ids.data() + start, offsets[c] - start, c);
    start = offsets[c];
  }
}

void XmlSurfaceReader::read_polydata_cells(vtkXMLDataElement* piece, int point_base, long long cell_base,
                                           SurfaceData& out, std::vector<long long>& cell_of_triangle) {
  const long long points = count_attribute(piece, "NumberOfPoints", true);
  // Cells are numbered verts, lines, polys, strips (cell data follows that order).
  const long long lines = count_attribute(piece, "NumberOfLines", false);
  read_cell_section(piece, "Lines", [&](const long long* ids, long long n, long long) {
    std::vector<int> line;
    for (long long i = 0; i < n; ++i) {
      if (ids[i] >= points) fail(fmt::format("a line uses point {}, but the piece has {} points", ids[i], points));
      line.push_back(static_cast<int>(ids[i]) + point_base);
    }
    out.lines.push_back(std::move(line));
  });
  const long long polys_start = cell_base + count_attribute(piece, "NumberOfVerts", false) + lines;
  read_cell_section(piece, "Polys", [&](const long long* ids, long long n, long long c) {
    add_polygon(ids, n, points, point_base, polys_start + c, out.mesh, cell_of_triangle, false);
  });
  const long long strips_start = polys_start + count_attribute(piece, "NumberOfPolys", false);
  read_cell_section(piece, "Strips", [&](const long long* ids, long long n, long long c) {
    add_polygon(ids, n, points, point_base, strips_start + c, out.mesh, cell_of_triangle, true);
  });
}

void XmlSurfaceReader::read_grid_cells(vtkXMLDataElement* piece, long long cells, int point_base,
                                       long long cell_base, TriMesh& mesh, std::vector<long long>& cell_of_triangle) {
  const long long points = count_attribute(piece, "NumberOfPoints", true);
  if (cells == 0) return;
  vtkXMLDataElement* element = piece->FindNestedElementWithName("Cells");
  if (!element) fail("the piece has cells but no <Cells>");
  const std::vector<long long> offsets = read_index_array(element, "offsets", cells, "Cells");
  const std::vector<long long> types = read_index_array(element, "types", cells, "Cells");
  const long long total = offsets.back();
  if (static_cast<double>(total) > 4.0 * static_cast<double>(input_size_) * 1100.0 + 1e6)
    fail(fmt::format("<Cells> offsets declare {} indices, more than the file can hold", total));
  const std::vector<long long> ids = read_index_array(element, "connectivity", total, "Cells");
  long long start = 0, volume_cells = 0;
  for (long long c = 0; c < cells; ++c) {
    if (offsets[c] < start || offsets[c] > total)
      fail(fmt::format("<Cells> offsets are not increasing up to {} at cell {}", total, c));
    const long long n = offsets[c] - start;
    const long long t = types[c];
    if (t == kVtkTriangle || t == kVtkQuad || t == kVtkPolygon || t == kVtkTriangleStrip) {
      if ((t == kVtkTriangle && n != 3) || (t == kVtkQuad && n != 4))
        fail(fmt::format("cell {} of type {} has {} points", c, t, n));
      add_polygon(ids.data() + start, n, points, point_base, cell_base + c, mesh, cell_of_triangle,
                  t == kVtkTriangleStrip);
    } else if (volume_ && (t == kVtkTetra || t == kVtkWedge)) {
      const long long expected = t == kVtkTetra ? 4 : 6;
      if (n != expected) fail(fmt::format("cell {} of type {} has {} points, not {}", c, t, n, expected));
      int v[6];
      for (long long i = 0; i < n; ++i) {
        if (ids[start + i] >= points)
          fail(fmt::format("cell {} uses point {}, but the piece has {} points", c, ids[start + i], points));
        v[i] = static_cast<int>(ids[start + i]) + point_base;
      }
      if (t == kVtkTetra) {
        volume_->tets.push_back({v[0], v[1], v[2], v[3]});
        cell_of_tet_.push_back(cell_base + c);
      } else {
        volume_->prisms.push_back({v[0], v[1], v[2], v[3], v[4], v[5]});
        cell_of_prism_.push_back(cell_base + c);
      }
    } else if (volume_ && t >= 10) {
      fail(fmt::format("cell {} has VTK type {}: volume meshes of tetrahedra (10) and wedges (13) are read", c, t));
    } else if (volume_ && t != 1 && t != 2 && t != 3 && t != 4) {
      fail(fmt::format("cell {} has VTK type {}, not a tetrahedron, wedge or boundary triangle", c, t));
    } else if (t >= 10) {
      ++volume_cells;
    }
    start = offsets[c];
  }
  if (!volume_ && mesh.triangles.empty() && volume_cells > 0)
    fail(fmt::format("holds {} volume cells and no surface triangles: vesselmesh reads lumen surfaces here", volume_cells));
}

std::vector<Field> XmlSurfaceReader::read_fields(vtkXMLDataElement* data, long long tuples, const char* where) {
  std::vector<Field> fields;
  if (!data) return fields;
  std::set<std::string> names;
  for (int i = 0; i < data->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* array = data->GetNestedElement(i);
    if (std::strcmp(array->GetName(), "DataArray") != 0) continue;
    const std::string name = attribute(array, "Name");
    if (name.empty()) fail(fmt::format("{} array {} has no name", where, i));
    if (!names.insert(name).second) fail(fmt::format("two {} arrays are named '{}'", where, name.substr(0, 40)));
    if (word_type(attribute(array, "type")) < 0) continue;  // strings and the like: not used
    Field field{.name = name, .components = 1, .values = {}, .integer = integral(word_type(attribute(array, "type")))};
    field.values = read_array(array, tuples, 0, &field.components);
    fields.push_back(std::move(field));
  }
  return fields;
}

void XmlSurfaceReader::read_points(vtkXMLDataElement* piece, long long points, std::vector<Vec3>& out) {
  if (points == 0) return;
  vtkXMLDataElement* element = piece->FindNestedElementWithName("Points");
  vtkXMLDataElement* array = element ? element->FindNestedElementWithName("DataArray") : nullptr;
  if (!array) fail("the piece has points but no <Points> array");
  const std::vector<double> xyz = read_array(array, points, 3);
  for (long long i = 0; i < points; ++i) {
    const Vec3 p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    if (!p.allFinite()) fail(fmt::format("point {} has a non-finite coordinate ({}, {}, {})", i, p.x(), p.y(), p.z()));
    out.push_back(p);
  }
}

// A String DataArray: the strings one after another, each ended by a zero byte (binary or
// appended, compressed or not), or their character codes (ascii).
std::vector<std::string> XmlSurfaceReader::read_strings(vtkXMLDataElement* array) {
  const std::string label = fmt::format("string array '{}'", attribute(array, "Name").substr(0, 40));
  const std::string format = attribute(array, "format");
  const bool appended = format == "appended";
  const long long offset = appended ? count_attribute(array, "offset", true) : 0;
  std::string text;
  if (format == "ascii") {
    std::istringstream in(array->GetCharacterData() ? array->GetCharacterData() : "");
    for (int code = 0; in >> code;) {
      if (code < 0 || code > 255) fail(fmt::format("{}: character code {} out of range", label, code));
      text.push_back(static_cast<char>(code));
    }
  } else if (appended || format == "binary") {
    // The byte count: a compressed array's block table, else the one header token.
    const std::string head = stored_bytes(array, appended, offset, 3 * static_cast<size_t>(header_size_));
    if (head.size() < static_cast<size_t>(header_size_)) fail(fmt::format("{}: its data is cut short", label));
    auto token = [&](size_t i) { return header_token(head, i); };
    uint64_t total = token(0);
    if (compressed_) {
      if (head.size() < 3 * static_cast<size_t>(header_size_)) fail(fmt::format("{}: its data is cut short", label));
      const uint64_t blocks = token(0), block_size = token(1), last = token(2);
      total = blocks == 0 ? 0 : (last == 0 ? blocks * block_size : (blocks - 1) * block_size + last);
    }
    if (total > 1100.0 * static_cast<double>(input_size_) + 1e6)
      fail(fmt::format("{} declares {} bytes, more than the file can hold", label, total));
    check_compression_header(array, label, appended, offset, total);
    std::vector<unsigned char> raw(total + 1);
    const size_t read = total == 0 ? 0
                        : appended ? parser_->ReadAppendedData(offset, raw.data(), 0, total, VTK_TYPE_UINT8)
                                   : parser_->ReadInlineData(array, false, raw.data(), 0, total, VTK_TYPE_UINT8);
    if (read != total) fail(fmt::format("{}: {} bytes expected, {} could be read", label, total, read));
    text.assign(raw.begin(), raw.begin() + static_cast<long>(total));
  } else {
    fail(fmt::format("{} has format '{}'", label, format.substr(0, 20)));
  }
  std::vector<std::string> strings;
  std::string current;
  for (char c : text) {
    if (c == '\0') {
      strings.push_back(current);
      current.clear();
    } else {
      current.push_back(c);
    }
  }
  if (!current.empty()) strings.push_back(current);
  return strings;
}

TetMesh XmlSurfaceReader::read_volume(std::vector<Field>* point_data) {
  parse_root();
  TetMesh mesh;
  volume_ = &mesh;
  vtkXMLDataElement* piece = nullptr;
  for (int i = 0; i < dataset_->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* e = dataset_->GetNestedElement(i);
    if (std::strcmp(e->GetName(), "Piece") != 0) continue;
    if (piece) fail("has more than one <Piece>: a volume mesh is read from one piece");
    piece = e;
  }
  if (!piece) fail("no <Piece> element");
  const long long points = count_attribute(piece, "NumberOfPoints", true);
  if (points > std::numeric_limits<int>::max() / 2) fail(fmt::format("{} points is more than vesselmesh handles", points));
  const long long cells = count_attribute(piece, "NumberOfCells", true);
  read_points(piece, points, mesh.points);
  if (point_data) *point_data = read_fields(piece->FindNestedElementWithName("PointData"), points, "point data");
  TriMesh triangles;
  std::vector<long long> cell_of_triangle;
  read_grid_cells(piece, cells, 0, 0, triangles, cell_of_triangle);
  if (mesh.tets.empty() && mesh.prisms.empty()) fail("holds no tetrahedra or wedges: not a volume mesh");
  mesh.boundary = std::move(triangles.triangles);

  const std::vector<Field> fields = read_fields(piece->FindNestedElementWithName("CellData"), cells, "cell data");
  const auto find = [&](const char* name) -> const Field* {
    for (const Field& f : fields)
      if (f.name == name && f.components == 1) return &f;
    return nullptr;
  };
  const Field* tag = find("tag");
  if (!tag)
    fail("has no cell data 'tag' (the boundary triangles' tags): write the volume with vesselmesh volume, or as .msh "
         "with physical groups");
  const auto integer = [&](const Field& f, long long c) {
    const double v = f.values[static_cast<size_t>(c)];
    if (v != std::floor(v) || std::abs(v) > 1e9) fail(fmt::format("cell data '{}' of cell {} is {}, not an integer", f.name, c, v));
    return static_cast<int>(v);
  };
  for (long long c : cell_of_triangle) mesh.boundary_tags.push_back(integer(*tag, c));
  if (!cell_of_tet_.empty()) mesh.volume_tag = integer(*tag, cell_of_tet_[0]);
  else mesh.volume_tag = integer(*tag, cell_of_prism_[0]);
  const Field* layer = find("layer");
  const Field* column = find("column");
  if (layer && column) {
    for (long long c : cell_of_tet_) {
      mesh.tet_layer.push_back(integer(*layer, c));
      mesh.tet_column.push_back(integer(*column, c));
    }
    for (long long c : cell_of_prism_) {
      mesh.prism_layer.push_back(integer(*layer, c));
      mesh.prism_column.push_back(integer(*column, c));
    }
  }

  // Names: "<tag> <name>" strings, the volume's first (its tag may also be a boundary's: they
  // are cells of another dimension); a tag without one is named unnamed_tag().
  if (vtkXMLDataElement* data = dataset_->FindNestedElementWithName("FieldData"))
    for (int i = 0; i < data->GetNumberOfNestedElements(); ++i) {
      vtkXMLDataElement* array = data->GetNestedElement(i);
      if (attribute(array, "Name") != "tag_names") continue;
      bool first = true;
      for (const std::string& entry : read_strings(array)) {
        std::istringstream in(entry);
        int t = 0;
        std::string name;
        if (!(in >> t >> name)) fail(fmt::format("tag_names entry '{}' is not '<tag> <name>'", entry.substr(0, 60)));
        if (first && t == mesh.volume_tag) mesh.volume_name = name;
        else mesh.tag_names[t] = name;
        first = false;
      }
    }
  mesh.tag_names = mesh::boundary_tag_names(mesh);
  volume_ = nullptr;
  return mesh;
}

void XmlSurfaceReader::read_piece(vtkXMLDataElement* piece, SurfaceData& out, std::vector<Field>& cell_fields) {
  const long long points = count_attribute(piece, "NumberOfPoints", true);
  if (points > std::numeric_limits<int>::max() / 2) fail(fmt::format("{} points is more than vesselmesh handles", points));
  const long long cells = format_ == VtkFormat::vtp
                              ? count_attribute(piece, "NumberOfVerts", false) + count_attribute(piece, "NumberOfLines", false) +
                                    count_attribute(piece, "NumberOfPolys", false) + count_attribute(piece, "NumberOfStrips", false)
                              : count_attribute(piece, "NumberOfCells", true);
  const int point_base = out.mesh.num_points();
  read_points(piece, points, out.mesh.points);
  std::vector<long long> cell_of_triangle;
  const size_t first_triangle = out.mesh.triangles.size();
  if (format_ == VtkFormat::vtp) read_polydata_cells(piece, point_base, 0, out, cell_of_triangle);
  else read_grid_cells(piece, cells, point_base, 0, out.mesh, cell_of_triangle);

  std::vector<Field> point_fields = read_fields(piece->FindNestedElementWithName("PointData"), points, "point data");
  std::vector<Field> piece_cells = read_fields(piece->FindNestedElementWithName("CellData"), cells, "cell data");
  // Pieces must agree on their arrays to be joined; keep those all pieces have.
  append_piece_fields(out.point_data, point_fields, point_base == 0);
  for (Field& f : piece_cells) {  // cell data per triangle, from the cell it came from
    Field per_triangle{.name = f.name, .components = f.components, .values = {}, .integer = f.integer};
    for (long long c : cell_of_triangle)
      for (int k = 0; k < f.components; ++k) per_triangle.values.push_back(f.values[c * f.components + k]);
    f = std::move(per_triangle);
  }
  append_piece_fields(cell_fields, piece_cells, first_triangle == 0);
}

SurfaceData XmlSurfaceReader::read(const std::string& label_array, bool lines_only) {
  parse_root();
  SurfaceData out;
  std::vector<Field> cell_fields;
  int pieces = 0;
  for (int i = 0; i < dataset_->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* piece = dataset_->GetNestedElement(i);
    if (std::strcmp(piece->GetName(), "Piece") != 0) continue;
    read_piece(piece, out, cell_fields);
    ++pieces;
  }
  if (pieces == 0) fail("no <Piece> element");
  if (!lines_only && out.mesh.triangles.empty()) fail("contains no triangles or polygons (a surface is needed)");
  if (lines_only && out.lines.empty()) fail("contains no lines (polylines are needed)");
  return finish_surface(std::move(out), std::move(cell_fields), label_array, name_);
}

}  // namespace

SurfaceData parse_vtk_xml_surface(std::string_view bytes, VtkFormat format, const std::string& name,
                                  const std::string& label_array) {
  VM_CHECK(format == VtkFormat::vtp || format == VtkFormat::vtu, "parse_vtk_xml_surface takes VTP or VTU");
  keep_vtk_errors();
  if (bytes.empty()) throw InputError(fmt::format("{}: the file is empty", name));
  if (bytes.find("<VTKFile") == std::string_view::npos)
    throw InputError(fmt::format("{}: not a VTK XML file (no <VTKFile> element)", name));
  try {
    return XmlSurfaceReader(bytes, format, name).read(label_array, false);
  } catch (const std::bad_alloc&) {
    throw InputError(fmt::format("{}: the file declares more data than fits in memory (a damaged file?)", name));
  }
}

TetMesh read_vtu_volume(const std::string& path, std::vector<Field>* point_data) {
  if (path.ends_with(".pvtu")) {  // the pieces one after the other, their shared points merged
    TetMesh all;
    std::vector<Field> fields;
    bool first = true;
    for (const std::string& source : parallel_pieces(path)) {
      std::vector<Field> piece_fields;
      TetMesh piece = read_vtu_volume(source, point_data ? &piece_fields : nullptr);
      const int offset = all.num_points();
      const auto shift = [&](auto cell) {
        for (int& v : cell) v += offset;
        return cell;
      };
      if (first) {
        all.volume_tag = piece.volume_tag;
        all.volume_name = piece.volume_name;
      }
      all.points.insert(all.points.end(), piece.points.begin(), piece.points.end());
      for (const Tet& t : piece.tets) all.tets.push_back(shift(t));
      for (const Prism& p : piece.prisms) all.prisms.push_back(shift(p));
      for (const Triangle& t : piece.boundary) all.boundary.push_back(shift(t));
      all.boundary_tags.insert(all.boundary_tags.end(), piece.boundary_tags.begin(), piece.boundary_tags.end());
      all.tag_names.insert(piece.tag_names.begin(), piece.tag_names.end());
      append_piece_fields(fields, piece_fields, first);
      first = false;
    }
    // A point two pieces share (each writes the ghost points of its cells) is one point, its data
    // the first piece's: the mesh as one process wrote it, up to the points' order.
    const std::vector<int> remap = mesh::merge_identical_points(all.points);
    for (Tet& t : all.tets)
      for (int& v : t) v = remap[v];
    for (Prism& p : all.prisms)
      for (int& v : p) v = remap[v];
    for (Triangle& t : all.boundary)
      for (int& v : t) v = remap[v];
    if (static_cast<int>(remap.size()) != all.num_points()) merge_point_fields(fields, remap, all.num_points());
    if (point_data) *point_data = std::move(fields);
    return all;
  }
  keep_vtk_errors();
  const std::string bytes = read_file(path);
  if (bytes.empty()) throw InputError(fmt::format("{}: the file is empty", path));
  if (bytes.find("<VTKFile") == std::string::npos)
    throw InputError(fmt::format("{}: not a VTK XML file (no <VTKFile> element)", path));
  try {
    return XmlSurfaceReader(bytes, VtkFormat::vtu, path).read_volume(point_data);
  } catch (const std::bad_alloc&) {
    throw InputError(fmt::format("{}: the file declares more data than fits in memory (a damaged file?)", path));
  }
}

SurfaceData read_vtp_polylines(const std::string& path) {
  keep_vtk_errors();
  const std::string bytes = read_file(path);
  if (bytes.empty()) throw InputError(fmt::format("{}: the file is empty", path));
  try {
    return XmlSurfaceReader(bytes, VtkFormat::vtp, path).read("", true);
  } catch (const std::bad_alloc&) {
    throw InputError(fmt::format("{}: the file declares more data than fits in memory (a damaged file?)", path));
  }
}

}  // namespace vesselmesh::io
