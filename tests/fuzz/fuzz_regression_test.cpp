// Runs the fuzz targets' code in the ordinary test suite (no clang needed): every file of the seed
// corpus, and a fixed set of deterministic mutations of each (bytes flipped, cut, repeated),
// must be read or refused with a vesselmesh error, never crash or throw anything else.
// Inputs that once crashed a fuzzer are kept in the corpus.
#include "fuzz_targets.h"
#include "synth/random.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <cstring>
#include <fstream>
#include <sstream>

namespace {

namespace fs = std::filesystem;

std::vector<std::string> corpus(const std::string& kind) {
  std::vector<std::string> inputs;
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(fs::path(VESSELMESH_FUZZ_CORPUS) / kind)) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    std::ifstream in(file, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    inputs.push_back(ss.str());
  }
  return inputs;
}

std::string mutate(std::string bytes, vesselmesh::synth::Random& random) {
  if (bytes.empty()) return std::string(1, static_cast<char>(random.next()));
  switch (random.next() % 4) {
    case 0:  // flip a few bytes
      for (int i = 0, n = 1 + random.next() % 8; i < n; ++i) bytes[random.next() % bytes.size()] = static_cast<char>(random.next());
      break;
    case 1:  // cut
      bytes.resize(random.next() % bytes.size());
      break;
    case 2: {  // repeat a slice
      const size_t at = random.next() % bytes.size(), length = random.next() % (bytes.size() - at + 1);
      bytes = bytes.substr(0, at + length) + bytes.substr(at);
      break;
    }
    default:  // overwrite a 4-byte word (counts, offsets, sizes)
      if (bytes.size() >= 4) {
        const uint32_t value = static_cast<uint32_t>(random.next());
        std::memcpy(bytes.data() + random.next() % (bytes.size() - 3), &value, 4);
      }
  }
  return bytes;
}

using vesselmesh::fuzz::Reader;

void exercise(const std::string& kind, Reader reader, int mutations) {
  const std::vector<std::string> seeds = corpus(kind);
  ASSERT_FALSE(seeds.empty()) << "no seeds in the " << kind << " corpus";
  vesselmesh::synth::Random random(2024);
  for (const std::string& seed : seeds) {
    EXPECT_EQ(vesselmesh::fuzz::read_surface_bytes(reader, reinterpret_cast<const uint8_t*>(seed.data()), seed.size()), 0);
    for (int i = 0; i < mutations; ++i) {
      const std::string input = mutate(seed, random);
      EXPECT_NO_THROW(vesselmesh::fuzz::read_surface_bytes(reader, reinterpret_cast<const uint8_t*>(input.data()), input.size()));
    }
  }
}

TEST(FuzzRegression, StlReaderSurvivesItsCorpusAndMutations) { exercise("stl", Reader::stl, 300); }
TEST(FuzzRegression, VtpReaderSurvivesItsCorpusAndMutations) { exercise("vtp", Reader::vtp, 150); }
TEST(FuzzRegression, PlyReaderSurvivesItsCorpusAndMutations) { exercise("ply", Reader::ply, 300); }
TEST(FuzzRegression, ObjReaderSurvivesItsCorpusAndMutations) { exercise("obj", Reader::obj, 300); }

}  // namespace
