// Running the program as a user does, for the command-line tests (tests/apps/*_test.cpp): its
// exit code, standard output and error; the last line of the error (the message); a file's text.
#pragma once

#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

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

}  // namespace vesselmesh
