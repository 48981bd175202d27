// Surfaces in VTK's XML formats: read VTP and VTU, write VTP with point and cell data arrays.
// VTK's XML parser, decoder and writer work behind this small header.
//
// Polygons and strips are split into triangles; vertices, lines and volume cells are not part
// of a surface. Points with identical coordinates are merged, their point data taken from the
// first. Every count, offset and index of the file is checked: a damaged file is an
// InputError naming it, never a crash.
// Labels: the integer cell array named by `label_array`, else the first present of
// ModelFaceID, tag, CellEntityIds, gmsh:physical, becomes TriMesh::labels.
#pragma once

#include "mesh/tetmesh.h"
#include "mesh/trimesh.h"

#include <string>
#include <string_view>
#include <vector>

namespace vesselmesh::io {

enum class VtkFormat { vtp, vtu };

struct SurfaceData {
  TriMesh mesh;
  std::vector<Field> point_data;  // one value tuple per mesh point
  std::vector<Field> cell_data;   // one value tuple per mesh triangle (labels excluded)
  std::string label_array;        // the cell array the labels came from, or empty
  std::vector<std::vector<int>> lines;  // VTP polylines (indices into mesh.points), if any
};

// A .pvtp (VTP pieces, as `vesselmesh simulate` writes under MPI) is read whole: its pieces
// joined, the points they share merged.
SurfaceData read_vtk_surface(const std::string& path, VtkFormat format,
                             const std::string& label_array = "");

// The same for a VTP or VTU held in memory (`name` appears in error messages).
SurfaceData parse_vtk_xml_surface(std::string_view bytes, VtkFormat format, const std::string& name,
                                  const std::string& label_array = "");

// The polylines of a VTP (e.g. centerlines): `lines` index `mesh.points`; point data kept.
SurfaceData read_vtp_polylines(const std::string& path);

// Polylines as VTK XML PolyData (each line one cell), with point and cell data, atomically.
void write_vtp_polylines(const std::string& path, const std::vector<std::vector<Vec3>>& lines,
                         const std::vector<Field>& point_data = {}, const std::vector<Field>& cell_data = {});

// VTK XML PolyData, binary and compressed, Float64 points, written atomically. The mesh's
// labels (if any) are written as the Int32 cell array `tag`. Field sizes must match.
void write_vtp(const std::string& path, const TriMesh& mesh,
               const std::vector<Field>& point_data = {}, const std::vector<Field>& cell_data = {});

// A volume mesh as VTK XML UnstructuredGrid, binary and compressed, atomically: tetrahedra,
// prisms (VTK wedges, TetMesh order) and the boundary triangles, in that order. Cell data
// `tag` (the volume's tag for volume cells, the boundary tag for triangles), and with layer
// data `layer` (1..N, 0 interior, -1 boundary) and `column` (the wall triangle's index among
// the boundary triangles, -1 elsewhere); field data `tag_names` ("<tag> <name>" strings).
// Without `boundary`, the volume's cells alone (a flow result's frame: its boundary is the mesh's).
// The points and a tetrahedral mesh's cells are handed to VTK without copies.
void write_vtu(const std::string& path, const TetMesh& mesh, const std::vector<Field>& point_data = {},
               bool boundary = true);

// Tetrahedra alone as VTK XML UnstructuredGrid (binary, compressed, atomically), with point and
// cell data (sizes must match): for solvers that read one element type (io/export.h).
void write_vtu_tetrahedra(const std::string& path, const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                          const std::vector<Field>& point_data, const std::vector<Field>& cell_data);

// A volume mesh written by write_vtu (or any VTU of tetrahedra, wedges and boundary triangles
// with the integer cell data `tag`): tags named from the field data `tag_names` when present,
// "tag_<number>" otherwise; `layer` and `column` kept when present. Points are not merged.
// Checked like the surface readers: a bad file is an InputError naming it. `point_data`, when
// given, receives the file's numeric point arrays (e.g. the solver's velocity and pressure).
// A .pvtu (VTU pieces) is read whole: its pieces one after the other, the points they share (a
// process's ghost points) merged into one, its data the first piece's, as one process wrote it up to
// the points' order (fluid_metric's Hessians and the flow mesh's point count need the pieces joined).
TetMesh read_vtu_volume(const std::string& path, std::vector<Field>* point_data = nullptr);

// A dataset in pieces (one per MPI process): ParaView's .pvtu / .pvtp file naming the pieces
// (`sources`, relative to its folder) and the arrays they hold (the fields' names, components
// and types; their values are in the pieces, written by write_vtu / write_vtp: a vtu piece has
// the cell array `tag`, a vtp piece has it when `labels`), written atomically.
void write_parallel_file(const std::string& path, VtkFormat format, const std::vector<std::string>& sources,
                         const std::vector<Field>& point_data, bool labels = true);
// The pieces a .pvtu / .pvtp names, as paths from the current folder. InputError when it is not
// one (naming it) or names none.
std::vector<std::string> parallel_pieces(const std::string& path);

}  // namespace vesselmesh::io
