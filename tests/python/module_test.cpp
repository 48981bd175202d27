// The Python module (python/vesselmesh_module.cpp) imported from the build folder by Debian's
// /usr/bin/python3 and checked against analytic answers by check_module.py (a pipe's ends,
// curvature, centerline, distance map, remesh, volume, Poiseuille's WSS; errors as ValueError).
// Skipped with a message where the module was not built (no python3-dev, python3-numpy, pybind11-dev).
#include "io/atomic_file.h"
#include "test_support.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace vesselmesh {
namespace {

TEST(PythonModule, ImportsAndAgreesWithAnalyticAnswers) {
#ifndef VESSELMESH_PYTHON_DIR
  GTEST_SKIP() << "the Python module was not built (apt-get install python3-dev python3-numpy pybind11-dev)";
#else
  test::TemporaryFolder tmp;
  const std::string script = (std::filesystem::path(__FILE__).parent_path() / "check_module.py").string();
  const std::string command =
      fmt::format("PYTHONPATH='{}' /usr/bin/python3 '{}' '{}' '{}' '{}' >'{}' 2>&1", VESSELMESH_PYTHON_DIR, script,
                  VESSELMESH_PROGRAM, tmp.path(""), VESSELMESH_EXAMPLES_DIR, tmp.path("check.log"));
  const int code = std::system(command.c_str());
  const std::string log = io::read_file(tmp.path("check.log"));
  std::printf("%s", log.c_str());
  EXPECT_EQ(code, 0) << log;
  EXPECT_NE(log.find("all checks passed"), std::string::npos) << log;
#endif
}

}  // namespace
}  // namespace vesselmesh
