#include "flow/mesh_part.h"

#include "io/bytes.h"
#include "mesh/error.h"
#include "mesh/point_graph.h"
#include "mesh/reorder.h"
#include "parallel/processes.h"

#include <fmt/format.h>

#include <algorithm>
#include <new>

namespace vesselmesh::flow {

struct MeshSplitter::Impl {
  int parts = 1;
  int total_points = 0;
  std::vector<int> process_begin;
  std::vector<int> order;   // order[global] = mesh point
  std::vector<Vec3> points;  // per global point
  std::vector<Tet> cells;    // the whole mesh's tetrahedra (prisms cut), global numbers
  // Per process the cells with a point it owns (CSR), per global point its boundary triangles.
  std::vector<int> cell_start, cell_list;
  std::vector<int> face_start, face_list;
  std::vector<Triangle> boundary;  // global numbers, the mesh's order
  std::vector<int> boundary_tags;
  std::map<int, std::string> tag_names;
  // The wall: its tags, per global point its cells (CSR).
  std::vector<int> wall_tags;
  std::vector<int> point_cell_start, point_cell_list;
  bool is_wall(int f) const {
    return std::find(wall_tags.begin(), wall_tags.end(), boundary_tags[f]) != wall_tags.end();
  }

  int owner(int g) const {
    const auto after = std::upper_bound(process_begin.begin(), process_begin.end(), g);
    return static_cast<int>(after - process_begin.begin()) - 1;
  }
};

namespace {

// Every tetrahedron's orientation (a bad cell stops the run, named).
void check_orientation(const TetMesh& mesh, const std::vector<Tet>& tets, const std::string& path) {
  for (const Tet& t4 : tets) {
    const double v6 = mesh::tet_volume6(mesh.points[t4[0]], mesh.points[t4[1]], mesh.points[t4[2]], mesh.points[t4[3]]);
    if (!(v6 > 0.0))
      throw InputError(fmt::format("{}: the tetrahedron of points {}, {}, {}, {} is inverted or flat (six times its "
                                   "volume {:.3g} in mesh units, at ({:.4g}, {:.4g}, {:.4g})): mend the mesh first",
                                   path, t4[0], t4[1], t4[2], t4[3], v6, mesh.points[t4[0]].x(),
                                   mesh.points[t4[0]].y(), mesh.points[t4[0]].z()));
  }
}

// Compressed rows: `rows` lists of `key(item)` -> items (by increasing item).
template <class Keys>
void bucket(int rows, int items, const Keys& keys, std::vector<int>& start, std::vector<int>& list) {
  start.assign(rows + 1, 0);
  for (int i = 0; i < items; ++i) keys(i, [&](int row) { ++start[row + 1]; });
  for (int r = 0; r < rows; ++r) start[r + 1] += start[r];
  list.resize(start[rows]);
  std::vector<int> next(start.begin(), start.end() - 1);
  for (int i = 0; i < items; ++i) keys(i, [&](int row) { list[next[row]++] = i; });
}

}  // namespace

MeshSplitter::MeshSplitter(const TetMesh& mesh, const std::string& path, int parts, const Partitioner& partition,
                           const std::vector<std::string>& wall_names)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.parts = parts;
  s.total_points = mesh.num_points();
  // The global numbering: RCM, then the points grouped by the process the partitioner gives them.
  std::vector<int> rcm, part(s.total_points, 0);
  {
    const std::vector<Tet> whole = mesh::all_tetrahedra(mesh);
    if (whole.empty()) throw InputError(fmt::format("{}: the mesh has no tetrahedra", path));
    check_orientation(mesh, whole, path);
    rcm = mesh::cuthill_mckee_order(mesh);
    if (parts > 1) {  // the point graph (of the tetrahedra the solver assembles) in RCM numbering
      const mesh::PointGraph graph = mesh::renumbered(mesh::point_graph(s.total_points, whole), rcm);
      part = partition(graph.start, graph.next, parts);
      VM_CHECK(static_cast<int>(part.size()) == s.total_points, "the partitioner's answer has a part per point");
    }
  }
  s.process_begin.assign(parts + 1, 0);
  for (int k = 0; k < s.total_points; ++k) ++s.process_begin[part[k] + 1];
  for (int r = 0; r < parts; ++r) s.process_begin[r + 1] += s.process_begin[r];
  for (int r = 0; r < parts; ++r)
    if (s.process_begin[r + 1] == s.process_begin[r])
      throw InputError(fmt::format("{}: {} processes for a mesh of {} points: process {} would own none; run it on "
                                   "fewer processes",
                                   path, parts, s.total_points, r));
  s.order.resize(s.total_points);
  {
    std::vector<int> next(s.process_begin.begin(), s.process_begin.end() - 1);
    for (int k = 0; k < s.total_points; ++k) s.order[next[part[k]]++] = rcm[k];
  }
  std::vector<int>().swap(part);
  std::vector<int>().swap(rcm);

  // The mesh in the global numbering (its cells sorted by it), cut into tetrahedra.
  {
    TetMesh ordered = mesh::renumbered(mesh, s.order);
    s.cells = mesh::all_tetrahedra(ordered);
    s.points = std::move(ordered.points);
    s.boundary = std::move(ordered.boundary);
    s.boundary_tags = std::move(ordered.boundary_tags);
  }
  s.tag_names = mesh::boundary_tag_names(mesh);
  const int cells = static_cast<int>(s.cells.size());
  bucket(parts, cells,
         [&](int e, auto&& add) {
           int seen[4], count = 0;
           for (int g : s.cells[e]) {
             const int r = s.owner(g);
             if (std::find(seen, seen + count, r) == seen + count) {
               seen[count++] = r;
               add(r);
             }
           }
         },
         s.cell_start, s.cell_list);
  bucket(s.total_points, static_cast<int>(s.boundary.size()),
         [&](int f, auto&& add) {
           for (int g : s.boundary[f]) add(g);
         },
         s.face_start, s.face_list);
  for (const auto& [tag, name] : s.tag_names)
    if (std::find(wall_names.begin(), wall_names.end(), name) != wall_names.end()) s.wall_tags.push_back(tag);
  if (!s.wall_tags.empty())
    bucket(s.total_points, cells,
           [&](int e, auto&& add) {
             for (int g : s.cells[e]) add(g);
           },
           s.point_cell_start, s.point_cell_list);
}

MeshSplitter::~MeshSplitter() = default;

int MeshSplitter::parts() const { return impl_->parts; }

MeshPart MeshSplitter::part(int rank) const {
  const Impl& s = *impl_;
  VM_CHECK(rank >= 0 && rank < s.parts, "a part of the split");
  MeshPart p;
  p.total_points = s.total_points;
  p.process_begin = s.process_begin;
  p.tag_names = s.tag_names;
  p.mesh_tetrahedra = static_cast<int>(s.cells.size());
  const int begin = s.process_begin[rank], end = s.process_begin[rank + 1];
  p.owned = end - begin;
  p.local_global.resize(p.owned);
  for (int a = 0; a < p.owned; ++a) p.local_global[a] = begin + a;
  // The wall: this process's triangles (their least point its own), the points whose stress it
  // computes (theirs and its own wall points), every wall triangle through those, and the cells
  // with a point within one edge of them (global numbers until the local ones are known).
  std::vector<int> wall_faces, wall_points, band;
  if (!s.wall_tags.empty()) {
    const auto mine = [&](int g) { return g >= begin && g < end; };
    for (int g = begin; g < end; ++g)
      for (int k = s.face_start[g]; k < s.face_start[g + 1]; ++k) {
        const int f = s.face_list[k];
        if (!s.is_wall(f)) continue;
        wall_points.push_back(g);
        const Triangle& t3 = s.boundary[f];
        if (mine(*std::min_element(t3.begin(), t3.end()))) wall_points.insert(wall_points.end(), t3.begin(), t3.end());
      }
    std::sort(wall_points.begin(), wall_points.end());
    wall_points.erase(std::unique(wall_points.begin(), wall_points.end()), wall_points.end());
    for (int g : wall_points)
      for (int k = s.face_start[g]; k < s.face_start[g + 1]; ++k)
        if (s.is_wall(s.face_list[k])) wall_faces.push_back(s.face_list[k]);
    std::sort(wall_faces.begin(), wall_faces.end());
    wall_faces.erase(std::unique(wall_faces.begin(), wall_faces.end()), wall_faces.end());
    const auto cells_of = [&](const std::vector<int>& points) {
      std::vector<int> out;
      for (int g : points)
        out.insert(out.end(), s.point_cell_list.begin() + s.point_cell_start[g],
                   s.point_cell_list.begin() + s.point_cell_start[g + 1]);
      std::sort(out.begin(), out.end());
      out.erase(std::unique(out.begin(), out.end()), out.end());
      return out;
    };
    std::vector<int> near;  // the points within one edge of the wall points
    for (int e : cells_of(wall_points)) near.insert(near.end(), s.cells[e].begin(), s.cells[e].end());
    std::sort(near.begin(), near.end());
    near.erase(std::unique(near.begin(), near.end()), near.end());
    band = cells_of(near);
  }
  std::vector<int> ghosts;
  for (int k = s.cell_start[rank]; k < s.cell_start[rank + 1]; ++k)
    for (int g : s.cells[s.cell_list[k]])
      if (g < begin || g >= end) ghosts.push_back(g);
  for (int e : band)
    for (int g : s.cells[e])
      if (g < begin || g >= end) ghosts.push_back(g);
  std::sort(ghosts.begin(), ghosts.end());
  ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());
  p.local_global.insert(p.local_global.end(), ghosts.begin(), ghosts.end());
  const auto local = [&](int g) {
    if (g >= begin && g < end) return g - begin;
    const auto it = std::lower_bound(ghosts.begin(), ghosts.end(), g);
    return it != ghosts.end() && *it == g ? p.owned + static_cast<int>(it - ghosts.begin()) : -1;
  };
  p.tets.reserve(s.cell_start[rank + 1] - s.cell_start[rank]);
  for (int k = s.cell_start[rank]; k < s.cell_start[rank + 1]; ++k) {
    const Tet& t4 = s.cells[s.cell_list[k]];
    p.tets.push_back({local(t4[0]), local(t4[1]), local(t4[2]), local(t4[3])});
  }
  p.points.resize(p.local_global.size());
  p.mesh_point.resize(p.local_global.size());
  for (size_t a = 0; a < p.points.size(); ++a) {
    p.points[a] = s.points[p.local_global[a]];
    p.mesh_point[a] = s.order[p.local_global[a]];
  }
  // Boundary triangles through a local point: their tags on the local points, and those whose
  // points are all local with one owned.
  std::vector<int> faces;
  for (int g : p.local_global)
    for (int k = s.face_start[g]; k < s.face_start[g + 1]; ++k) faces.push_back(s.face_list[k]);
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  for (int f : faces) {
    const Triangle& t3 = s.boundary[f];
    const Triangle tri{local(t3[0]), local(t3[1]), local(t3[2])};
    bool all = true, mine = false;
    for (int a : tri) {
      all = all && a >= 0;
      mine = mine || (a >= 0 && a < p.owned);
      if (a >= 0) p.point_tags.push_back({a, s.boundary_tags[f]});
    }
    if (all && mine) {
      p.boundary.push_back(tri);
      p.boundary_tags.push_back(s.boundary_tags[f]);
    }
  }
  for (int e : band) {
    const Tet& t4 = s.cells[e];
    p.wall.cells.push_back({local(t4[0]), local(t4[1]), local(t4[2]), local(t4[3])});
  }
  for (int f : wall_faces) {
    const Triangle& t3 = s.boundary[f];
    p.wall.triangles.push_back({local(t3[0]), local(t3[1]), local(t3[2])});
    p.wall.tags.push_back(s.boundary_tags[f]);
    const int least = *std::min_element(t3.begin(), t3.end());
    p.wall.written.push_back(least >= begin && least < end ? 1 : 0);
  }
  for (int g : wall_points) p.wall.points.push_back(local(g));
  std::sort(p.wall.points.begin(), p.wall.points.end());
  std::sort(p.point_tags.begin(), p.point_tags.end());
  p.point_tags.erase(std::unique(p.point_tags.begin(), p.point_tags.end()), p.point_tags.end());
  if (rank == 0) p.global_mesh_point = s.order;
  return p;
}

namespace {

constexpr char kPart = 'P';
// A failure on the first process, sent in place of a part: its kind and message.
constexpr char kInput = 'I', kOption = 'O', kComputation = 'C', kInternal = 'X';

}  // namespace

std::string pack(const MeshPart& p) {
  io::ByteWriter out;
  out.value(kPart);
  out.value(p.total_points);
  out.vector(p.process_begin);
  out.value(p.owned);
  out.vector(p.local_global);
  out.vector(p.mesh_point);
  out.vector(p.points);
  out.vector(p.tets);
  out.vector(p.boundary);
  out.vector(p.boundary_tags);
  out.vector(p.point_tags);
  out.value(static_cast<uint64_t>(p.tag_names.size()));
  for (const auto& [tag, name] : p.tag_names) {
    out.value(tag);
    out.string(name);
  }
  out.value(p.mesh_tetrahedra);
  out.vector(p.global_mesh_point);
  out.vector(p.wall.cells);
  out.vector(p.wall.triangles);
  out.vector(p.wall.tags);
  out.vector(p.wall.written);
  out.vector(p.wall.points);
  return out.take();
}

namespace {

io::ByteReader part_reader(std::string bytes) {
  return io::ByteReader(std::move(bytes), [](size_t at, size_t size) {
    throw InternalError(fmt::format("a mesh part's bytes end early (at byte {} of {})", at, size));
  });
}

}  // namespace

MeshPart unpack(std::string bytes) {
  io::ByteReader in = part_reader(std::move(bytes));
  VM_CHECK(in.value<char>() == kPart, "the bytes are a mesh part");
  MeshPart p;
  p.total_points = in.value<int>();
  p.process_begin = in.vector<int>();
  p.owned = in.value<int>();
  p.local_global = in.vector<int>();
  p.mesh_point = in.vector<int>();
  p.points = in.vector<Vec3>();
  p.tets = in.vector<Tet>();
  p.boundary = in.vector<Triangle>();
  p.boundary_tags = in.vector<int>();
  p.point_tags = in.vector<std::array<int, 2>>();
  const auto names = in.value<uint64_t>();
  for (uint64_t k = 0; k < names; ++k) {
    const int tag = in.value<int>();
    p.tag_names[tag] = in.string();
  }
  p.mesh_tetrahedra = in.value<int>();
  p.global_mesh_point = in.vector<int>();
  p.wall.cells = in.vector<Tet>();
  p.wall.triangles = in.vector<Triangle>();
  p.wall.tags = in.vector<int>();
  p.wall.written = in.vector<char>();
  p.wall.points = in.vector<int>();
  VM_CHECK(in.done(), "a mesh part's bytes end with it");
  return p;
}

MeshPart distribute_mesh(const TetMesh* mesh, const std::string& path, std::exception_ptr failure,
                         const std::vector<std::string>& wall_names) {
  const int ranks = parallel::process_count(), rank = parallel::process_rank();
  std::unique_ptr<MeshSplitter> splitter;
  std::string error;  // the first process's failure as the others receive it
  if (rank == 0) {
    try {
      if (failure) std::rethrow_exception(failure);
      VM_CHECK(mesh != nullptr, "the first process holds the mesh");
      splitter = std::make_unique<MeshSplitter>(*mesh, path, ranks, parallel::partition_graph, wall_names);
    } catch (const std::exception& e) {
      failure = std::current_exception();
      const char kind = dynamic_cast<const InputError*>(&e)         ? kInput
                        : dynamic_cast<const OptionError*>(&e)      ? kOption
                        : dynamic_cast<const ComputationError*>(&e) ? kComputation
                                                                    : kInternal;
      io::ByteWriter out;
      out.value(kind);
      out.string(dynamic_cast<const std::bad_alloc*>(&e) ? std::string("out of memory on the first process")
                                                         : std::string(e.what()));
      error = out.take();
    }
  }
  // The others' parts, made and sent one at a time; the first keeps its own as it is.
  std::string mine =
      parallel::scatter_from_first([&](int r) { return splitter ? pack(splitter->part(r)) : error; });
  if (failure) std::rethrow_exception(failure);
  if (rank == 0) {
    return splitter->part(0);
  }
  VM_CHECK(!mine.empty(), "a process received its mesh part");
  if (mine[0] != kPart) {
    io::ByteReader in = part_reader(std::move(mine));
    const char kind = in.value<char>();
    const std::string message = in.string();
    if (kind == kInput) throw InputError(message);
    if (kind == kOption) throw OptionError(message);
    if (kind == kComputation) throw ComputationError(message);
    throw InternalError(message);
  }
  return unpack(std::move(mine));
}

}  // namespace vesselmesh::flow
