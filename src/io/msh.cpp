#include "io/msh.h"

#include "io/atomic_file.h"
#include "io/gmsh_session.h"
#include "mesh/error.h"

#include <fmt/format.h>
#include <gmsh.h>

#include <algorithm>
#include <filesystem>
#include <unordered_map>

namespace vesselmesh::io {
namespace {
constexpr int kTriangle3 = 2;  // Gmsh element types
constexpr int kTetrahedron4 = 4, kPrism6 = 6;

// Node tags 1, 2, ... (our index + 1) and xyz coordinates of every point.
void gmsh_nodes(const std::vector<Vec3>& points, std::vector<std::size_t>& tags, std::vector<double>& coords) {
  tags.resize(points.size());
  coords.clear();
  coords.reserve(3 * points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    tags[i] = i + 1;
    coords.insert(coords.end(), {points[i].x(), points[i].y(), points[i].z()});
  }
}

void require_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(fmt::format("{}: cannot open: no such file", path));
}

// Opens an MSH file in the current Gmsh session; every node's tag and xyz.
void open_with_nodes(const std::string& path, std::vector<std::size_t>& tags, std::vector<double>& coords) {
  gmsh::open(path);
  std::vector<double> parametric;
  gmsh::model::mesh::getNodes(tags, coords, parametric, -1, -1, false, false);
}

// An entity's physical group (its first), else the entity's own tag, and the group's name.
struct EntityGroup {
  int tag = 0;
  bool grouped = false;
  std::string name;
};
EntityGroup entity_group(int dim, int entity) {
  std::vector<int> physicals;
  gmsh::model::getPhysicalGroupsForEntity(dim, entity, physicals);
  EntityGroup g{physicals.empty() ? entity : physicals.front(), !physicals.empty(), ""};
  if (g.grouped) gmsh::model::getPhysicalName(dim, g.tag, g.name);
  return g;
}

// The session's model as MSH 4.1 text (physical groups only), written atomically.
void write_model(const std::string& path) {
  gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
  gmsh::option::setNumber("Mesh.Binary", 0);
  gmsh::option::setNumber("Mesh.SaveAll", 0);
  write_atomically(path, [&](const std::string& temporary) { gmsh::write(temporary); });
}

}  // namespace

void write_msh(const std::string& path, const TriMesh& mesh,
               const std::map<int, std::string>& label_names) {
  // Distinct labels in order; each becomes one discrete surface entity.
  std::vector<int> labels = mesh.has_labels() ? mesh.labels : std::vector<int>(mesh.triangles.size(), 1);
  std::vector<int> distinct = labels;
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  const bool positive = distinct.empty() || distinct.front() > 0;

  GmshSession session;
  call_gmsh(path, [&] {
    gmsh::model::add("vesselmesh");
    std::vector<std::size_t> node_tags;
    std::vector<double> coords;
    gmsh_nodes(mesh.points, node_tags, coords);
    for (size_t k = 0; k < distinct.size(); ++k) {
      const int entity = static_cast<int>(k) + 1;
      gmsh::model::addDiscreteEntity(2, entity);
      if (k == 0) gmsh::model::mesh::addNodes(2, entity, node_tags, coords);
      std::vector<std::size_t> element_tags, element_nodes;
      for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        if (labels[t] != distinct[k]) continue;
        element_tags.push_back(t + 1);
        for (int v : mesh.triangles[t]) element_nodes.push_back(static_cast<std::size_t>(v) + 1);
      }
      gmsh::model::mesh::addElementsByType(entity, kTriangle3, element_tags, element_nodes);
      const int physical = positive ? distinct[k] : entity;
      gmsh::model::addPhysicalGroup(2, {entity}, physical);
      const auto name = label_names.find(distinct[k]);
      gmsh::model::setPhysicalName(
          2, physical,
          name != label_names.end() ? name->second
                                    : (mesh.has_labels() ? fmt::format("label_{}", distinct[k]) : "surface"));
    }
    write_model(path);
  });
}

TriMesh read_msh_surface(const std::string& path, std::map<int, std::string>* label_names) {
  require_file(path);
  GmshSession session;
  TriMesh mesh;
  call_gmsh(path, [&] {
    std::vector<std::size_t> node_tags;
    std::vector<double> coords;
    open_with_nodes(path, node_tags, coords);
    std::unordered_map<std::size_t, int> index_of;  // Gmsh node tag -> our point index
    gmsh::vectorpair entities;
    gmsh::model::getEntities(entities, 2);
    for (const auto& [dim, entity] : entities) {
      const EntityGroup group = entity_group(dim, entity);
      const int label = group.tag;
      if (label_names && !group.name.empty()) (*label_names)[label] = group.name;
      std::vector<std::size_t> element_tags, element_nodes;
      gmsh::model::mesh::getElementsByType(kTriangle3, element_tags, element_nodes, entity);
      for (size_t e = 0; e < element_tags.size(); ++e) {
        Triangle f;
        for (int c = 0; c < 3; ++c) {
          const std::size_t tag = element_nodes[3 * e + c];
          auto [it, inserted] = index_of.try_emplace(tag, mesh.num_points());
          if (inserted) mesh.points.emplace_back();  // coordinates filled below
          f[c] = it->second;
        }
        mesh.triangles.push_back(f);
        mesh.labels.push_back(label);
      }
    }
    std::unordered_map<std::size_t, size_t> position;
    for (size_t i = 0; i < node_tags.size(); ++i) position[node_tags[i]] = i;
    for (const auto& [tag, index] : index_of) {
      const auto found = position.find(tag);
      if (found == position.end())
        throw InputError(fmt::format("{}: a triangle uses node {}, which the file does not define", path, tag));
      const size_t i = found->second;
      mesh.points[index] = Vec3(coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]);
    }
  });
  if (mesh.triangles.empty())
    throw InputError(fmt::format("{}: the MSH file has no 3-node triangles (a surface is needed)", path));
  return mesh;
}

void write_msh(const std::string& path, const TetMesh& mesh) {
  GmshSession session;
  call_gmsh(path, [&] {
    gmsh::model::add("vesselmesh");
    std::vector<std::size_t> node_tags;
    std::vector<double> coords;
    gmsh_nodes(mesh.points, node_tags, coords);
    // Surfaces first (entity k + 1 for the k-th tag), then the volume bounded by them.
    std::vector<int> tags;
    for (int tag : mesh.boundary_tags) tags.push_back(tag);
    std::sort(tags.begin(), tags.end());
    tags.erase(std::unique(tags.begin(), tags.end()), tags.end());
    std::size_t element = 1;
    std::vector<int> surfaces;
    for (size_t k = 0; k < tags.size(); ++k) {
      const int entity = static_cast<int>(k) + 1;
      surfaces.push_back(entity);
      gmsh::model::addDiscreteEntity(2, entity);
      if (k == 0) gmsh::model::mesh::addNodes(2, entity, node_tags, coords);
      std::vector<std::size_t> element_tags, element_nodes;
      for (size_t t = 0; t < mesh.boundary.size(); ++t) {
        if (mesh.boundary_tags[t] != tags[k]) continue;
        element_tags.push_back(element++);
        for (int v : mesh.boundary[t]) element_nodes.push_back(static_cast<std::size_t>(v) + 1);
      }
      gmsh::model::mesh::addElementsByType(entity, kTriangle3, element_tags, element_nodes);
      gmsh::model::addPhysicalGroup(2, {entity}, tags[k]);
      const auto name = mesh.tag_names.find(tags[k]);
      gmsh::model::setPhysicalName(2, tags[k], name != mesh.tag_names.end() ? name->second : fmt::format("tag_{}", tags[k]));
    }
    gmsh::model::addDiscreteEntity(3, 1, surfaces);
    if (tags.empty()) gmsh::model::mesh::addNodes(3, 1, node_tags, coords);
    std::vector<std::size_t> element_tags, element_nodes;
    for (const Tet& t : mesh.tets) {
      element_tags.push_back(element++);
      for (int v : t) element_nodes.push_back(static_cast<std::size_t>(v) + 1);
    }
    if (!element_tags.empty()) gmsh::model::mesh::addElementsByType(1, kTetrahedron4, element_tags, element_nodes);
    element_tags.clear();
    element_nodes.clear();
    for (const Prism& p : mesh.prisms) {
      element_tags.push_back(element++);
      for (int v : mesh::flipped_prism(p)) element_nodes.push_back(static_cast<std::size_t>(v) + 1);
    }
    if (!element_tags.empty()) gmsh::model::mesh::addElementsByType(1, kPrism6, element_tags, element_nodes);
    gmsh::model::addPhysicalGroup(3, {1}, mesh.volume_tag);
    gmsh::model::setPhysicalName(3, mesh.volume_tag, mesh.volume_name);
    write_model(path);
  });
}

TetMesh read_msh_volume(const std::string& path) {
  require_file(path);
  GmshSession session;
  // A volume mesh is read once for a long run (the flow solver's first process): Gmsh's own
  // memory given back after it (6 MB of the first process's peak at 590k tetrahedra; Gmsh's
  // libraries stay mapped, 38 MB of shared pages).
  session.finalize_at_end();
  TetMesh mesh;
  call_gmsh(path, [&] {
    std::vector<std::size_t> node_tags;
    std::vector<double> coords;
    open_with_nodes(path, node_tags, coords);
    std::unordered_map<std::size_t, int> index_of;
    for (size_t i = 0; i < node_tags.size(); ++i) {
      index_of.emplace(node_tags[i], static_cast<int>(i));
      mesh.points.emplace_back(coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]);
    }
    auto corners = [&](const std::vector<std::size_t>& nodes, size_t e, int count, int* out) {
      for (int c = 0; c < count; ++c) {
        const auto it = index_of.find(nodes[count * e + c]);
        if (it == index_of.end())
          throw InputError(fmt::format("{}: an element uses node {}, which the file does not define", path, nodes[count * e + c]));
        out[c] = it->second;
      }
    };
    gmsh::vectorpair entities;
    gmsh::model::getEntities(entities, 3);
    for (const auto& [dim, entity] : entities) {
      const EntityGroup group = entity_group(dim, entity);
      if (group.grouped) {
        mesh.volume_tag = group.tag;
        mesh.volume_name = group.name;
      }
      std::vector<std::size_t> tags, nodes;
      gmsh::model::mesh::getElementsByType(kTetrahedron4, tags, nodes, entity);
      for (size_t e = 0; e < tags.size(); ++e) corners(nodes, e, 4, mesh.tets.emplace_back().data());
      tags.clear();  // Gmsh fills vectors that are not empty in place, without resizing them
      nodes.clear();
      gmsh::model::mesh::getElementsByType(kPrism6, tags, nodes, entity);
      for (size_t e = 0; e < tags.size(); ++e) {
        Prism p;
        corners(nodes, e, 6, p.data());
        mesh.prisms.push_back(mesh::flipped_prism(p));
      }
    }
    gmsh::model::getEntities(entities, 2);
    for (const auto& [dim, entity] : entities) {
      const EntityGroup group = entity_group(dim, entity);
      const int tag = group.tag;
      mesh.tag_names[tag] = group.name.empty() ? mesh::unnamed_tag(tag) : group.name;
      std::vector<std::size_t> tags, nodes;
      gmsh::model::mesh::getElementsByType(kTriangle3, tags, nodes, entity);
      for (size_t e = 0; e < tags.size(); ++e) {
        corners(nodes, e, 3, mesh.boundary.emplace_back().data());
        mesh.boundary_tags.push_back(tag);
      }
    }
  });
  if (mesh.tets.empty() && mesh.prisms.empty())
    throw InputError(fmt::format("{}: the MSH file has no tetrahedra or prisms (a volume mesh is needed)", path));
  return mesh;
}

}  // namespace vesselmesh::io
