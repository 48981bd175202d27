// Gmsh's C++ API keeps one global model and is not thread-safe. A GmshSession holds it for
// the current scope: it initializes Gmsh quietly (no terminal output, no configuration
// files, errors thrown as exceptions) and clears the model when it ends. One at a time.
#pragma once

#include <mutex>
#include <string>

namespace vesselmesh::io {

class GmshSession {
 public:
  GmshSession();
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

 private:
  std::unique_lock<std::mutex> lock_;
};

// Runs `what` and turns any exception Gmsh throws (it may throw non-std types) into an
// InputError "<context>: <Gmsh's last error>".
template <typename F>
void call_gmsh(const std::string& context, F&& what);

[[noreturn]] void rethrow_gmsh_error(const std::string& context);

template <typename F>
void call_gmsh(const std::string& context, F&& what) {
  try {
    what();
  } catch (...) {
    rethrow_gmsh_error(context);
  }
}

}  // namespace vesselmesh::io
