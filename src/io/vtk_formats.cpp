#include "io/vtk_formats.h"

#include "io/atomic_file.h"
#include "io/vtk_internal.h"
#include "mesh/error.h"
#include "mesh/merge_points.h"

#include <fmt/format.h>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkCellType.h>
#include <vtkFieldData.h>
#include <vtkStringArray.h>
#include <vtkTypeInt32Array.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <mutex>

namespace vesselmesh::io {
namespace {

thread_local std::string t_vtk_error;  // the first error VTK reported on this thread

// VTK prints its errors to a window or stderr; the library never prints, so they are kept
// here and turned into exceptions by the code that called VTK.
class KeepErrorsWindow : public vtkOutputWindow {
 public:
  static KeepErrorsWindow* New();
  vtkTypeMacro(KeepErrorsWindow, vtkOutputWindow);
  void DisplayText(const char*) override {}
  void DisplayErrorText(const char* text) override {
    if (text && t_vtk_error.empty()) t_vtk_error = text;
  }
  void DisplayWarningText(const char*) override {}
  void DisplayGenericWarningText(const char*) override {}
  void DisplayDebugText(const char*) override {}
};
vtkStandardNewMacro(KeepErrorsWindow);

// One component of whole numbers (labels are sometimes stored as floating point).
bool holds_labels(const Field& field) {
  if (field.components != 1) return false;
  for (double v : field.values)
    if (!std::isfinite(v) || v != std::round(v) || std::abs(v) > 2e9) return false;
  return true;
}

vtkSmartPointer<vtkDataArray> to_vtk_array(const Field& field, int count, const std::string& path) {
  if (field.components <= 0 || field.values.size() != static_cast<size_t>(count) * field.components)
    throw InternalError(fmt::format("{}: field '{}' has {} values, expected {} x {}", path, field.name,
                                    field.values.size(), count, field.components));
  if (!field.integer) {
    // The field's own values, not a copy (VTK only reads them while the writer runs; save = 1:
    // VTK does not free them): a fluid frame's velocity is 2.4 MB at 100k points.
    auto array = vtkSmartPointer<vtkDoubleArray>::New();
    array->SetName(field.name.c_str());
    array->SetNumberOfComponents(field.components);
    array->SetArray(const_cast<double*>(field.values.data()), static_cast<vtkIdType>(field.values.size()), 1);
    return array;
  }
  auto array = vtkSmartPointer<vtkIntArray>::New();
  array->SetName(field.name.c_str());
  array->SetNumberOfComponents(field.components);
  array->SetNumberOfTuples(count);
  for (int t = 0; t < count; ++t)
    for (int c = 0; c < field.components; ++c)
      array->SetComponent(t, c, field.values[static_cast<size_t>(t) * field.components + c]);
  return array;
}

}  // namespace

void keep_vtk_errors() {
  static std::once_flag once;
  std::call_once(once, [] {
    vtkNew<KeepErrorsWindow> window;
    vtkOutputWindow::SetInstance(window);
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  });
  t_vtk_error.clear();
}

bool vtk_failed() { return !t_vtk_error.empty(); }

// VTK's messages span lines and start with the source location; keep the last line.
std::string vtk_error_text() {
  std::string text = t_vtk_error;
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  const size_t cut = text.rfind('\n');
  if (cut != std::string::npos) text = text.substr(cut + 1);
  return text.empty() ? std::string("not a valid file") : text;
}

const char* vtk_format_name(VtkFormat format) {
  switch (format) {
    case VtkFormat::vtp: return "VTK XML PolyData (.vtp)";
    case VtkFormat::vtu: return "VTK XML UnstructuredGrid (.vtu)";
  }
  return "VTK";
}

void append_piece_fields(std::vector<Field>& fields, std::vector<Field>& piece, bool first) {
  if (first) {
    fields = std::move(piece);
    return;
  }
  std::vector<Field> kept;
  for (Field& f : fields)
    for (Field& g : piece)
      if (g.name == f.name && g.components == f.components) {
        f.values.insert(f.values.end(), g.values.begin(), g.values.end());
        kept.push_back(std::move(f));
        break;
      }
  fields = std::move(kept);
}

SurfaceData finish_surface(SurfaceData out, std::vector<Field> cell_fields, const std::string& label_array,
                           const std::string& name) {
  // Labels.
  auto chosen = cell_fields.end();
  if (!label_array.empty()) {
    chosen = std::find_if(cell_fields.begin(), cell_fields.end(), [&](const Field& f) { return f.name == label_array; });
    if (chosen == cell_fields.end() || !holds_labels(*chosen))
      throw InputError(fmt::format("{}: has no integer cell array '{}' to take labels from", name, label_array));
  } else {
    for (const char* candidate : {"ModelFaceID", "tag", "CellEntityIds", "gmsh:physical"}) {
      chosen = std::find_if(cell_fields.begin(), cell_fields.end(),
                            [&](const Field& f) { return f.name == candidate && holds_labels(f); });
      if (chosen != cell_fields.end()) break;
    }
  }
  if (chosen != cell_fields.end()) {
    out.label_array = chosen->name;
    out.mesh.labels.assign(chosen->values.begin(), chosen->values.end());
    cell_fields.erase(chosen);
  }
  out.cell_data = std::move(cell_fields);

  // Points with identical coordinates become one; their data is the first one's.
  const int before = out.mesh.num_points();
  const std::vector<int> remap = mesh::merge_identical_points(out.mesh.points);
  mesh::remap_triangles(out.mesh.triangles, remap);
  for (std::vector<int>& line : out.lines)
    for (int& v : line) v = remap[v];
  if (out.mesh.num_points() != before) merge_point_fields(out.point_data, remap, out.mesh.num_points());
  return out;
}

void merge_point_fields(std::vector<Field>& fields, const std::vector<int>& remap, int points) {
  for (Field& field : fields) {
    std::vector<double> merged(static_cast<size_t>(points) * field.components);
    for (int i = static_cast<int>(remap.size()) - 1; i >= 0; --i)  // backwards: the first occurrence writes last
      for (int c = 0; c < field.components; ++c)
        merged[static_cast<size_t>(remap[i]) * field.components + c] =
            field.values[static_cast<size_t>(i) * field.components + c];
    field.values = std::move(merged);
  }
}

SurfaceData read_vtk_surface(const std::string& path, VtkFormat format, const std::string& label_array) {
  if (!path.ends_with(".pvtp")) return parse_vtk_xml_surface(read_file(path), format, path, label_array);
  // The pieces joined as they are, then labelled and merged as one surface.
  SurfaceData all;
  std::vector<Field> cells;
  std::string labels = label_array;
  bool first = true;
  for (const std::string& source : parallel_pieces(path)) {
    SurfaceData piece = read_vtk_surface(source, VtkFormat::vtp, label_array);
    const int offset = all.mesh.num_points();
    all.mesh.points.insert(all.mesh.points.end(), piece.mesh.points.begin(), piece.mesh.points.end());
    for (Triangle t : piece.mesh.triangles) {
      for (int& v : t) v += offset;
      all.mesh.triangles.push_back(t);
    }
    if (!piece.label_array.empty()) {
      labels = piece.label_array;
      piece.cell_data.push_back(Field::labels(piece.label_array, piece.mesh.labels));
    }
    append_piece_fields(all.point_data, piece.point_data, first);
    append_piece_fields(cells, piece.cell_data, first);
    first = false;
  }
  return finish_surface(std::move(all), std::move(cells), labels, path);
}

std::vector<std::string> parallel_pieces(const std::string& path) {
  const std::string text = read_file(path);
  if (text.find("<PUnstructuredGrid") == std::string::npos && text.find("<PPolyData") == std::string::npos)
    throw InputError(fmt::format("{}: not a VTK parallel file (.pvtu or .pvtp: no <PUnstructuredGrid> or <PPolyData>)",
                                 path));
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  std::vector<std::string> sources;
  for (size_t at = text.find("<Piece"); at != std::string::npos; at = text.find("<Piece", at + 1)) {
    const size_t end = text.find('>', at);
    const size_t source = text.find("Source=\"", at);
    if (source == std::string::npos || source > end)
      throw InputError(fmt::format("{}: a <Piece> without a Source", path));
    const size_t close = text.find('"', source + 8);
    sources.push_back((folder / text.substr(source + 8, close - source - 8)).string());
  }
  if (sources.empty()) throw InputError(fmt::format("{}: names no piece", path));
  return sources;
}

void write_parallel_file(const std::string& path, VtkFormat format, const std::vector<std::string>& sources,
                         const std::vector<Field>& point_data, bool labels) {
  const char* kind = format == VtkFormat::vtu ? "PUnstructuredGrid" : "PPolyData";
  std::string text = fmt::format("<?xml version=\"1.0\"?>\n<VTKFile type=\"{}\" version=\"0.1\" "
                                 "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <{} GhostLevel=\"0\">\n",
                                 kind, kind);
  text += "    <PPointData>\n";
  for (const Field& f : point_data)
    text += fmt::format("      <PDataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\"/>\n",
                        f.integer ? "Int32" : "Float64", f.name, f.components);
  text += "    </PPointData>\n";
  if (format == VtkFormat::vtu || labels)
    text += "    <PCellData>\n      <PDataArray type=\"Int32\" Name=\"tag\" NumberOfComponents=\"1\"/>\n    </PCellData>\n";
  text += "    <PPoints>\n      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n    </PPoints>\n";
  for (const std::string& source : sources) text += fmt::format("    <Piece Source=\"{}\"/>\n", source);
  text += fmt::format("  </{}>\n</VTKFile>\n", kind);
  write_text(path, text);
}

namespace {

template <typename Writer>
void write_dataset(const std::string& path, vtkDataObject* data) {
  write_atomically(path, [&](const std::string& temporary) {
    vtkNew<Writer> writer;
    writer->SetFileName(temporary.c_str());
    writer->SetInputData(data);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetCompressorTypeToZLib();
    if (writer->Write() != 1 || vtk_failed())
      throw InputError(fmt::format("{}: cannot write: {}", path, vtk_error_text()));
  });
}

vtkSmartPointer<vtkPoints> to_vtk_points(const std::vector<Vec3>& points) {
  auto out = vtkSmartPointer<vtkPoints>::New();
  out->SetDataTypeToDouble();
  out->SetNumberOfPoints(static_cast<vtkIdType>(points.size()));
  for (size_t i = 0; i < points.size(); ++i) out->SetPoint(static_cast<vtkIdType>(i), points[i].x(), points[i].y(), points[i].z());
  return out;
}

}  // namespace

void write_vtp(const std::string& path, const TriMesh& mesh, const std::vector<Field>& point_data,
               const std::vector<Field>& cell_data) {
  keep_vtk_errors();
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(mesh.num_triangles(), 3 * mesh.num_triangles());
  for (const Triangle& f : mesh.triangles) {
    const vtkIdType ids[3] = {f[0], f[1], f[2]};
    polys->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(to_vtk_points(mesh.points));
  poly->SetPolys(polys);
  for (const Field& field : point_data) poly->GetPointData()->AddArray(to_vtk_array(field, mesh.num_points(), path));
  if (mesh.has_labels())
    poly->GetCellData()->AddArray(to_vtk_array(Field::labels("tag", mesh.labels), mesh.num_triangles(), path));
  for (const Field& field : cell_data) poly->GetCellData()->AddArray(to_vtk_array(field, mesh.num_triangles(), path));
  write_dataset<vtkXMLPolyDataWriter>(path, poly);
}

void write_vtp_polylines(const std::string& path, const std::vector<std::vector<Vec3>>& lines,
                         const std::vector<Field>& point_data, const std::vector<Field>& cell_data) {
  keep_vtk_errors();
  std::vector<Vec3> points;
  vtkNew<vtkCellArray> cells;
  for (const auto& line : lines) {
    std::vector<vtkIdType> ids;
    for (const Vec3& p : line) ids.push_back(static_cast<vtkIdType>(points.size())), points.push_back(p);
    cells->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(to_vtk_points(points));
  poly->SetLines(cells);
  for (const Field& field : point_data)
    poly->GetPointData()->AddArray(to_vtk_array(field, static_cast<int>(points.size()), path));
  for (const Field& field : cell_data)
    poly->GetCellData()->AddArray(to_vtk_array(field, static_cast<int>(lines.size()), path));
  write_dataset<vtkXMLPolyDataWriter>(path, poly);
}

namespace {

// Points handed to VTK without a copy (VTK reads them while the writer runs; save = 1: it does
// not free them).
vtkSmartPointer<vtkPoints> borrowed_points(const std::vector<Vec3>& points) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "points as a packed array");
  vtkNew<vtkDoubleArray> coordinates;
  coordinates->SetNumberOfComponents(3);
  coordinates->SetArray(const_cast<double*>(points.empty() ? nullptr : points.front().data()),
                        3 * static_cast<vtkIdType>(points.size()), 1);
  auto out = vtkSmartPointer<vtkPoints>::New();
  out->SetData(coordinates);
  return out;
}

// Tetrahedra as a VTK cell array over our own connectivity (32-bit point numbers, no copy); only
// the offsets are made.
vtkSmartPointer<vtkCellArray> borrowed_tetrahedra(const std::vector<Tet>& tets) {
  static_assert(sizeof(Tet) == 4 * sizeof(vtkTypeInt32), "tetrahedra as a packed array");
  const vtkIdType cells = static_cast<vtkIdType>(tets.size());
  vtkNew<vtkTypeInt32Array> connectivity, offsets;
  connectivity->SetArray(const_cast<vtkTypeInt32*>(tets.empty() ? nullptr : tets.front().data()), 4 * cells, 1);
  offsets->SetNumberOfValues(cells + 1);
  for (vtkIdType c = 0; c <= cells; ++c) offsets->SetValue(c, static_cast<vtkTypeInt32>(4 * c));
  auto out = vtkSmartPointer<vtkCellArray>::New();
  out->SetData(offsets, connectivity);
  return out;
}

}  // namespace

// Built cell by cell, VTK's 64-bit connectivity and offsets were a copy of 40 bytes a tetrahedron
// (23 MB at 580k) on top of a run's memory at every fluid frame; the XML writer itself adds
// nothing (VTK 9.1, measured).
void write_vtu_tetrahedra(const std::string& path, const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                          const std::vector<Field>& point_data, const std::vector<Field>& cell_data) {
  keep_vtk_errors();
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(borrowed_points(points));
  const int cells = static_cast<int>(tets.size());
  grid->SetCells(VTK_TETRA, borrowed_tetrahedra(tets));
  for (const Field& field : point_data)
    grid->GetPointData()->AddArray(to_vtk_array(field, static_cast<int>(points.size()), path));
  for (const Field& field : cell_data) grid->GetCellData()->AddArray(to_vtk_array(field, cells, path));
  write_dataset<vtkXMLUnstructuredGridWriter>(path, grid);
}

void write_vtu(const std::string& path, const TetMesh& mesh, const std::vector<Field>& point_data, bool boundary) {
  keep_vtk_errors();
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(borrowed_points(mesh.points));
  const int volume_cells = mesh.num_tets() + mesh.num_prisms();
  const int faces = boundary ? static_cast<int>(mesh.boundary.size()) : 0;
  const int cells = volume_cells + faces;
  const bool layers = mesh.has_layers();
  if (faces == 0 && mesh.num_prisms() == 0) {
    grid->SetCells(VTK_TETRA, borrowed_tetrahedra(mesh.tets));
  } else {
    // Exactly the cells' connectivity, in 32 bits.
    vtkNew<vtkTypeInt32Array> connectivity, offsets;
    vtkNew<vtkUnsignedCharArray> types;
    connectivity->SetNumberOfValues(4 * static_cast<vtkIdType>(mesh.num_tets()) + 6 * mesh.num_prisms() + 3 * faces);
    offsets->SetNumberOfValues(cells + 1);
    types->SetNumberOfValues(cells);
    vtkIdType at = 0, cell = 0;
    const auto add = [&](const int* ids, int n, unsigned char type) {
      offsets->SetValue(cell, static_cast<vtkTypeInt32>(at));
      types->SetValue(cell++, type);
      for (int k = 0; k < n; ++k) connectivity->SetValue(at++, ids[k]);
    };
    for (const Tet& t : mesh.tets) add(t.data(), 4, VTK_TETRA);
    for (const auto& prism : mesh.prisms) add(prism.data(), 6, VTK_WEDGE);
    for (int f = 0; f < faces; ++f) add(mesh.boundary[f].data(), 3, VTK_TRIANGLE);
    offsets->SetValue(cell, static_cast<vtkTypeInt32>(at));
    vtkNew<vtkCellArray> cell_array;
    cell_array->SetData(offsets, connectivity);
    grid->SetCells(types, cell_array);
  }
  for (const Field& field : point_data) grid->GetPointData()->AddArray(to_vtk_array(field, mesh.num_points(), path));
  const auto int_array = [&](const char* name, const std::function<int(int)>& value) {
    vtkNew<vtkIntArray> array;
    array->SetName(name);
    array->SetNumberOfValues(cells);
    for (int c = 0; c < cells; ++c) array->SetValue(c, value(c));
    grid->GetCellData()->AddArray(array);
  };
  int_array("tag", [&](int c) { return c < volume_cells ? mesh.volume_tag : mesh.boundary_tags[c - volume_cells]; });
  if (layers) {
    const int tets = mesh.num_tets();
    int_array("layer", [&](int c) {
      if (c < tets) return mesh.tet_layer.empty() ? 0 : mesh.tet_layer[c];
      if (c < volume_cells) return mesh.prism_layer.empty() ? 1 : mesh.prism_layer[c - tets];
      return -1;
    });
    int_array("column", [&](int c) {
      if (c < tets) return mesh.tet_column.empty() ? -1 : mesh.tet_column[c];
      if (c < volume_cells) return mesh.prism_column.empty() ? -1 : mesh.prism_column[c - tets];
      return -1;
    });
  }
  vtkNew<vtkStringArray> names;
  names->SetName("tag_names");
  names->InsertNextValue(fmt::format("{} {}", mesh.volume_tag, mesh.volume_name));
  for (const auto& [t, name] : mesh.tag_names) names->InsertNextValue(fmt::format("{} {}", t, name));
  grid->GetFieldData()->AddArray(names);
  write_dataset<vtkXMLUnstructuredGridWriter>(path, grid);
}

}  // namespace vesselmesh::io
