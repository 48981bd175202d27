#include "io/process.h"

#include "mesh/error.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace vesselmesh::io {
namespace {

std::string read_back(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Its exit code, its environment with ours, less the dropped, and the entries added, the signal that ended it, and a
// program that is not there.
TEST(RunProcess, GivesTheExitCodeTheEnvironmentAndTheSignal) {
  test::TemporaryFolder tmp;
  EXPECT_EQ(run_process({"sh", "-c", "exit 3"}), 3);
  EXPECT_EQ(run_process({"true"}), 0);
  const std::string out = tmp.path("env.txt");
  ASSERT_EQ(run_process({"sh", "-c", "echo \"$VESSELMESH_TEST_A $PATH\" >" + out}, {"VESSELMESH_TEST_A=given"}), 0);
  EXPECT_EQ(read_back(out), std::string("given ") + getenv("PATH") + "\n");
  setenv("VESSELMESH_TEST_B", "ours", 1);
  ASSERT_EQ(run_process({"sh", "-c", "echo \"[$VESSELMESH_TEST_B]\" >" + out}, {}, {"VESSELMESH_TEST_"}), 0);
  EXPECT_EQ(read_back(out), "[]\n");
  // A variable we have, set anew: the new value, not ours.
  ASSERT_EQ(run_process({"sh", "-c", "echo \"[$VESSELMESH_TEST_B]\" >" + out}, {"VESSELMESH_TEST_B=theirs"}), 0);
  EXPECT_EQ(read_back(out), "[theirs]\n");
  EXPECT_EQ(run_process({"sh", "-c", "kill -TERM $$"}), 128 + 15);
  try {
    run_process({"vesselmesh-no-such-program"});
    FAIL() << "a missing program ran";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot run vesselmesh-no-such-program"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vesselmesh::io
