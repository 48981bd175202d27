// Gmsh's C++ API keeps one global model and is not thread-safe. A GmshSession holds it for
// the current scope: it initializes Gmsh quietly (no terminal output, no configuration
// files, errors thrown as exceptions) and clears the model when it ends. One at a time.
#pragma once

#include "mesh/error.h"
#include "mesh/trimesh.h"

#include <array>
#include <cstddef>
#include <functional>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

namespace vesselmesh::io {

class GmshSession {
 public:
  GmshSession();
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
  // Gmsh finalized when the session ends (not only its model cleared): what it keeps between
  // sessions given back, the next session starting it afresh.
  void finalize_at_end() { finalize_ = true; }

 private:
  std::unique_lock<std::mutex> lock_;
  bool finalize_ = false;
};

// Gmsh's options and size callback outlive a session: the options set through this are put
// back and the callback (it refers to its caller's field) removed when the scope ends, error or
// not, so that later Gmsh work in the same process starts from what it expects. Inside a session.
class ScopedGmshOptions {
 public:
  ScopedGmshOptions() = default;
  ScopedGmshOptions(const ScopedGmshOptions&) = delete;
  ScopedGmshOptions& operator=(const ScopedGmshOptions&) = delete;
  ~ScopedGmshOptions();
  void set(const std::string& name, double value);
  void size_callback(std::function<double(int, int, double, double, double)> callback);

 private:
  bool callback_ = false;
  std::vector<std::pair<std::string, double>> saved_;
};

// Runs `what` and turns any exception Gmsh throws (it may throw non-std types) into an
// InputError "<context>: <Gmsh's last error>".
template <typename F>
void call_gmsh(const std::string& context, F&& what);

[[noreturn]] void rethrow_gmsh_error(const std::string& context);

// Adds `mesh` to the current model as discrete surface 1: point i is node i + 1, triangle t
// element t + 1. Then sets the model's size, which Gmsh's meshing tolerances follow and which
// reading a file sets but adding nodes does not (without it the aortic arch's patches came out
// with edges 0.46 of the size asked, whatever the size). Inside a session; Gmsh may throw.
void add_discrete_surface(const TriMesh& mesh);

// Gmsh's elements of N nodes (`nodes` flat, as getElementsByType gives them) in our numbering
// through `index_of` (Gmsh's node tag -> our point); InternalError naming `what` on a node the
// map lacks.
template <std::size_t N>
std::vector<std::array<int, N>> in_our_numbering(const std::vector<std::size_t>& nodes,
                                                 const std::unordered_map<std::size_t, int>& index_of,
                                                 const std::string& what) {
  std::vector<std::array<int, N>> elements(nodes.size() / N);
  for (std::size_t e = 0; e < elements.size(); ++e)
    for (std::size_t c = 0; c < N; ++c) {
      const auto it = index_of.find(nodes[N * e + c]);
      if (it == index_of.end()) throw InternalError("Gmsh returned a " + what + " on an unknown node");
      elements[e][c] = it->second;
    }
  return elements;
}

template <typename F>
void call_gmsh(const std::string& context, F&& what) {
  try {
    what();
  } catch (...) {
    rethrow_gmsh_error(context);
  }
}

}  // namespace vesselmesh::io
