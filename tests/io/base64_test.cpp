#include "io/base64.h"

#include <gtest/gtest.h>

#include <string>

namespace vesselmesh::io {
namespace {

// RFC 4648's examples (section 10) both ways; the decoder skips whitespace, stops at padding or a
// foreign character and after `count` bytes.
TEST(Base64, RfcExamplesBothWays) {
  const std::pair<const char*, const char*> cases[] = {{"", ""},         {"f", "Zg=="},         {"fo", "Zm8="},
                                                       {"foo", "Zm9v"},  {"foob", "Zm9vYg=="},  {"fooba", "Zm9vYmE="},
                                                       {"foobar", "Zm9vYmFy"}};
  for (const auto& [plain, coded] : cases) {
    EXPECT_EQ(encode_base64(plain, std::string(plain).size()), coded) << plain;
    EXPECT_EQ(decode_base64(coded), plain) << coded;
  }
  EXPECT_EQ(decode_base64(" Zm9v\nYmFy "), "foobar");
  EXPECT_EQ(decode_base64("Zm9vYmFy", 0, 4), "foob");
  EXPECT_EQ(decode_base64("xxZm9v", 2), "foo");
  EXPECT_EQ(decode_base64("Zm9v!YmFy"), "foo");
  const std::string bytes = {'\0', '\xff', '\x10', '\x80'};
  EXPECT_EQ(decode_base64(encode_base64(bytes.data(), bytes.size())), bytes);
}

}  // namespace
}  // namespace vesselmesh::io
