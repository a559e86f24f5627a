// The PGM heightfield reader: pixel values to heights, image rows to y, and a
// message naming the file and what is wrong with it.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "robophi/scene/heightfield_pgm.h"

namespace robophi {
namespace {

std::string writeFile(const std::string& name, const std::string& bytes) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream out(path, std::ios::binary);
  out << bytes;
  return path;
}

TEST(HeightfieldPgm, TextImageLoads) {
  const std::string path = writeFile("terrain.pgm", "P2\n# a ramp\n3 2\n255\n0 0 0\n0 255 255\n");
  Heightfield field;
  field.material = 3;
  const std::string error = loadHeightfieldPgm(path, 0.0, 0.0, 1.0, 1.0, 0.0, 2.0, field);
  ASSERT_EQ(error, "");
  EXPECT_EQ(field.columns, 3);
  EXPECT_EQ(field.rows, 2);
  EXPECT_EQ(field.material, 3);  // kept
  // Image row 0 is the top (y index 1).
  EXPECT_DOUBLE_EQ(field.heightAt(0.0, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(field.heightAt(2.0, 0.0), 2.0);
  EXPECT_DOUBLE_EQ(field.heightAt(1.5, 0.0), 2.0);
  EXPECT_DOUBLE_EQ(field.heightAt(0.5, 0.0), 1.0);
  EXPECT_NE(loadHeightfieldPgm(path + ".missing", 0, 0, 1, 1, 0, 1, field), "");
}

TEST(HeightfieldPgm, BinaryImagesOf8And16BitsLoad) {
  Heightfield field;
  const std::string p8 =
      writeFile("b8.pgm", std::string("P5 2 2 255\n") + '\x00' + '\xff' + '\x80' + '\x00');
  ASSERT_EQ(loadHeightfieldPgm(p8, 0, 0, 1, 1, -1.0, 1.0, field), "");
  EXPECT_DOUBLE_EQ(field.heightAt(1.0, 1.0), 1.0);  // image row 0, column 1
  EXPECT_DOUBLE_EQ(field.heightAt(0.0, 1.0), -1.0);
  const std::string p16 =
      writeFile("b16.pgm", std::string("P5 2 2 1000\n") + std::string("\x03\xe8\x00\x00", 4) +
                               std::string("\x00\x00\x01\xf4", 4));
  ASSERT_EQ(loadHeightfieldPgm(p16, 0, 0, 1, 1, 0.0, 2.0, field), "");
  EXPECT_DOUBLE_EQ(field.heightAt(0.0, 1.0), 2.0);  // 1000 / 1000
  EXPECT_DOUBLE_EQ(field.heightAt(1.0, 0.0), 1.0);  // 500 / 1000
}

TEST(HeightfieldPgm, ErrorsNameTheFileAndTheProblem) {
  struct Case {
    const char* name;
    const char* bytes;
    const char* fragment;
  };
  const Case cases[] = {
      {"magic.pgm", "P6\n2 2\n255\n", "not a PGM image (expected P2 or P5, got 'P6')"},
      {"header.pgm", "P2\n2 2\n", "truncated header"},
      {"value.pgm", "P2\n2 x\n255\n", "bad header value 'x'"},
      {"small.pgm", "P2\n1 2\n255\n0 0\n", "size 1×2 must be at least 2×2"},
      {"maxval.pgm", "P2\n2 2\n70000\n", "maxval 70000 must be in [1, 65535]"},
      {"pixels.pgm", "P2\n2 2\n255\n0 0 0\n", "truncated pixel data"},
      {"range.pgm", "P2\n2 2\n255\n0 0 0 300\n", "pixel (1, 1) = 300 exceeds maxval 255"},
  };
  for (const Case& c : cases) {
    const std::string path = writeFile(c.name, c.bytes);
    Heightfield field;
    field.columns = 7;
    const std::string error = loadHeightfieldPgm(path, 0, 0, 1, 1, 0, 1, field);
    EXPECT_NE(error.find(path), std::string::npos) << error;
    EXPECT_NE(error.find(c.fragment), std::string::npos) << error;
    EXPECT_EQ(field.columns, 7) << "a failed read must leave the field unchanged";
  }
  const std::string path = writeFile("ok.pgm", "P2\n2 2\n255\n0 0 0 0\n");
  Heightfield field;
  EXPECT_NE(
      loadHeightfieldPgm(path, 0, 0, 0.0, 1, 0, 1, field).find("cell sizes (0, 1) must be > 0"),
      std::string::npos);
  EXPECT_NE(loadHeightfieldPgm("/nonexistent/t.pgm", 0, 0, 1, 1, 0, 1, field)
                .find("/nonexistent/t.pgm: cannot open the file"),
            std::string::npos);
}

}  // namespace
}  // namespace robophi
