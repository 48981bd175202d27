// Running the program as a user does, for the command-line tests (tests/apps/*_test.cpp): its
// exit code, standard output and error; the last line of the error (the message); a file's text;
// the flow tests' example case and their arrays' relative difference.
#pragma once

#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>

namespace vesselmesh {

using Json = nlohmann::json;

struct RunResult {
  int code = -1;
  std::string out, err;
  Json json() const { return Json::parse(out); }
};

inline std::string quote(const std::string& s) {
  std::string q(1, '\'');
  for (char c : s) {
    if (c == '\'') q.append("'\\''");
    else q.push_back(c);
  }
  q.push_back('\'');
  return q;
}

inline RunResult run_program(const std::string& program, const std::vector<std::string>& args) {
  test::TemporaryFolder tmp;
  std::string command = quote(program);
  for (const std::string& a : args) command.append(" ").append(quote(a));
  command.append(" >").append(quote(tmp.path("out"))).append(" 2>").append(quote(tmp.path("err"))).append(" </dev/null");
  const int status = std::system(command.c_str());
  RunResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  auto slurp = [](const std::string& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  r.out = slurp(tmp.path("out"));
  r.err = slurp(tmp.path("err"));
  return r;
}

inline RunResult run(const std::vector<std::string>& args) { return run_program(VESSELMESH_PROGRAM, args); }

// The last line of stderr: the error message.
inline std::string last_line(const std::string& text) {
  std::string t = text;
  while (!t.empty() && t.back() == '\n') t.pop_back();
  const size_t cut = t.rfind('\n');
  return cut == std::string::npos ? t : t.substr(cut + 1);
}

// A copy of the program in `folder`, without the modules (Gmsh's, PETSc's) beside it.
inline std::string program_alone(const test::TemporaryFolder& folder) {
  const std::string alone = folder.path("vesselmesh");
  std::filesystem::copy_file(VESSELMESH_PROGRAM, alone);
  std::filesystem::permissions(alone, std::filesystem::perms::owner_all);
  return alone;
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The largest |a - b| over the largest |a| (arrays of the same size, not empty).
inline double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  EXPECT_FALSE(a.empty());
  double largest = 0.0, difference = 0.0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    largest = std::max(largest, std::abs(a[i]));
    difference = std::max(difference, std::abs(a[i] - b[i]));
  }
  return largest > 0.0 ? difference / largest : difference;
}

// examples/pipe_pulsatile.toml for a small pipe meshed in a test's folder: the mesh `mesh_file`
// (written there by `volume` with `volume_options`), run to `end` s, the waveform found.
struct ExampleCase {
  std::string text;

  ExampleCase(const test::TemporaryFolder& tmp, const std::string& mesh_file, std::vector<std::string> volume_options,
              const std::string& end) {
    EXPECT_EQ(run({"synth", "cylinder", "--radius", "2", "--length", "8", "--resolution", "0.5", "-o",
                   tmp.path("p.stl")}).code, 0);
    std::vector<std::string> volume = {"volume", tmp.path("p.stl"), "-o", tmp.path(mesh_file), "-q"};
    volume.insert(volume.end(), volume_options.begin(), volume_options.end());
    EXPECT_EQ(run(volume).code, 0);
    text = read_text(std::string(VESSELMESH_EXAMPLES_DIR) + "/pipe_pulsatile.toml");
    replace("../build/pipe.msh", mesh_file);
    replace("cycles = 2", "end = " + end);
    replace("period = 0.8", "");
    replace("waveform = \"pulse.csv\"", "waveform = \"" + std::string(VESSELMESH_EXAMPLES_DIR) + "/pulse.csv\"");
  }
  void replace(const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
};

}  // namespace vesselmesh
