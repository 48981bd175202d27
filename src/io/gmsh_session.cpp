#include "io/gmsh_session.h"

#include "mesh/error.h"

#include <gmsh.h>

#include <exception>
#include <vector>

namespace vesselmesh::io {
namespace {
std::mutex& gmsh_mutex() {
  static std::mutex mutex;
  return mutex;
}
// Guarded by the mutex. After an error Gmsh can keep a broken model (a failed open leaves
// later opens empty), so an error finalizes it and the next session starts afresh.
bool g_initialized = false;
bool g_failed = false;
}  // namespace

GmshSession::GmshSession() : lock_(gmsh_mutex()) {
  if (g_initialized && g_failed) {
    gmsh::finalize();
    g_initialized = false;
  }
  g_failed = false;
  if (!g_initialized) {
    gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
    g_initialized = true;
  }
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::option::setNumber("General.Verbosity", 2);  // errors and warnings, kept by the logger
  gmsh::option::setNumber("General.AbortOnError", 2);  // throw instead of exiting
  gmsh::logger::start();
  gmsh::clear();
}

GmshSession::~GmshSession() {
  try {
    gmsh::logger::stop();
    gmsh::clear();
    if (finalize_) {
      gmsh::finalize();
      g_initialized = false;
    }
  } catch (...) {
  }
}

ScopedGmshOptions::~ScopedGmshOptions() {
  if (callback_) {
    try {
      gmsh::model::mesh::removeSizeCallback();
    } catch (...) {
    }
  }
  for (auto it = saved_.rbegin(); it != saved_.rend(); ++it) {
    try {
      gmsh::option::setNumber(it->first, it->second);
    } catch (...) {  // a destructor must not throw; the option keeps its value
    }
  }
}

void ScopedGmshOptions::set(const std::string& name, double value) {
  double old = 0.0;
  gmsh::option::getNumber(name, old);
  saved_.emplace_back(name, old);
  gmsh::option::setNumber(name, value);
}

void ScopedGmshOptions::size_callback(std::function<double(int, int, double, double, double)> callback) {
  gmsh::model::mesh::setSizeCallback(std::move(callback));
  callback_ = true;
}

void add_discrete_surface(const TriMesh& mesh) {
  constexpr int kTriangle3 = 2;  // Gmsh's element type of a 3-node triangle
  gmsh::model::addDiscreteEntity(2, 1);
  std::vector<std::size_t> node_tags(mesh.points.size());
  std::vector<double> coords;
  coords.reserve(3 * mesh.points.size());
  for (size_t i = 0; i < mesh.points.size(); ++i) {
    node_tags[i] = i + 1;
    coords.insert(coords.end(), {mesh.points[i].x(), mesh.points[i].y(), mesh.points[i].z()});
  }
  std::vector<std::size_t> element_tags, element_nodes;
  element_tags.reserve(mesh.triangles.size());
  element_nodes.reserve(3 * mesh.triangles.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    element_tags.push_back(t + 1);
    for (int v : mesh.triangles[t]) element_nodes.push_back(static_cast<std::size_t>(v) + 1);
  }
  gmsh::model::mesh::addNodes(2, 1, node_tags, coords);
  gmsh::model::mesh::addElementsByType(1, kTriangle3, element_tags, element_nodes);
  gmsh::model::geo::synchronize();
}

void rethrow_gmsh_error(const std::string& context) {
  g_failed = true;  // called inside a session, under the mutex
  std::string message;
  try {
    throw;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    message = e.what();
  } catch (const std::string& s) {
    message = s;
  } catch (const char* s) {
    message = s;
  } catch (...) {
  }
  try {
    std::string last;
    gmsh::logger::getLastError(last);
    if (!last.empty()) message = last;
  } catch (...) {
  }
  throw InputError(context + ": " + (message.empty() ? "Gmsh failed" : message));
}

}  // namespace vesselmesh::io
