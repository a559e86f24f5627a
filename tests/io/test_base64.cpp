// Base64 (output/base64.h): RFC 4648's test vectors, a round trip of every
// byte value and length, and text that is not base64.

#include "output/base64.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace robophi::output {
namespace {

std::string encode(const std::string& bytes) {
  std::string out = "prefix:";
  appendBase64(out, bytes.data(), bytes.size());
  EXPECT_EQ(out.size(), 7 + base64Size(bytes.size()));
  return out.substr(7);
}

TEST(Base64, EncodesRfc4648sVectors) {
  EXPECT_EQ(encode(""), "");
  EXPECT_EQ(encode("f"), "Zg==");
  EXPECT_EQ(encode("fo"), "Zm8=");
  EXPECT_EQ(encode("foo"), "Zm9v");
  EXPECT_EQ(encode("foob"), "Zm9vYg==");
  EXPECT_EQ(encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(encode("foobar"), "Zm9vYmFy");
}

TEST(Base64, DecodesWhatItEncodesForEveryByteAndLength) {
  std::vector<std::uint8_t> bytes;
  for (int k = 0; k < 300; ++k) bytes.push_back(static_cast<std::uint8_t>((k * 151 + 7) % 256));
  for (std::size_t length = 0; length <= bytes.size(); ++length) {
    std::string text;
    appendBase64(text, bytes.data(), length);
    const std::vector<std::uint8_t> back = decodeBase64(text);
    ASSERT_EQ(back, std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + length)) << length;
  }
}

TEST(Base64, RefusesTextThatIsNotBase64) {
  EXPECT_THROW(decodeBase64("Zm9"), std::invalid_argument);       // not a multiple of 4
  EXPECT_THROW(decodeBase64("Zm9v!A=="), std::invalid_argument);  // '!' outside the alphabet
  EXPECT_THROW(decodeBase64("Z=9v"), std::invalid_argument);      // padding before the end
  EXPECT_THROW(decodeBase64("Zg=v"), std::invalid_argument);      // padding then a character
  try {
    decodeBase64("Zm9v!A==");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("offset 4"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace robophi::output
