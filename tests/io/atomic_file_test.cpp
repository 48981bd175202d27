#include "io/atomic_file.h"

#include "mesh/error.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <fstream>

namespace vesselmesh::io {
namespace {

TEST(AtomicFile, WriterThatFailsLeavesNothing) {
  test::TemporaryFolder tmp;
  EXPECT_THROW(write_atomically(tmp.path("out.vtp"),
                                [](const std::string& temporary) {
                                  std::ofstream(temporary) << "half a file";
                                  throw InputError("disk full");
                                }),
               InputError);
  EXPECT_TRUE(tmp.files().empty());
}

TEST(AtomicFile, OldFileStaysWhenTheNewOneFails) {
  test::TemporaryFolder tmp;
  test::write_bytes(tmp.path("out.txt"), "old");
  EXPECT_THROW(write_atomically(tmp.path("out.txt"), [](const std::string&) { throw OptionError("no"); }),
               OptionError);
  EXPECT_EQ(read_file(tmp.path("out.txt")), "old");
  EXPECT_EQ(tmp.files(), std::vector<std::string>{"out.txt"});
}

TEST(AtomicFile, TemporaryKeepsTheExtensionAndIsRenamed) {
  test::TemporaryFolder tmp;
  std::string seen;
  write_atomically(tmp.path("mesh.stl"), [&](const std::string& temporary) {
    seen = temporary;
    std::ofstream(temporary) << "x";
  });
  EXPECT_EQ(seen.substr(seen.size() - 4), ".stl");
  EXPECT_EQ(tmp.files(), std::vector<std::string>{"mesh.stl"});
}

TEST(AtomicFile, MissingFolderIsAnInputError) {
  EXPECT_THROW(write_atomically("/nonexistent-folder/x.stl", [](const std::string&) {}), InputError);
}

TEST(AtomicFile, ReadingAFolderOrAMissingFileIsAnInputError) {
  test::TemporaryFolder tmp;
  EXPECT_THROW(read_file(tmp.folder().string()), InputError);
  EXPECT_THROW(read_file(tmp.path("missing")), InputError);
}

}  // namespace
}  // namespace vesselmesh::io
