#include "hazmap/io/jdem.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <fstream>
#include <random>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

JdemGrid random_grid(int rows, int cols, unsigned seed) {
  JdemGrid g;
  g.quantity = "height";
  g.units = "m";
  g.rows = rows;
  g.cols = cols;
  g.resolution_m = 0.04;
  g.center_x_m = 1.2;
  g.center_y_m = -0.4;
  g.yaw_rad = 0.125;
  g.metadata = {{"frame", "000123"}, {"source", "unit test"}};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1e3f, 1e3f);
  for (int i = 0; i < rows * cols; ++i) g.values.push_back(u(rng) * std::pow(10.0f, float(i % 7) - 4));
  return g;
}

/// Message of the Error thrown by parse_jdem(text).
std::string parse_error(const std::string& text) {
  try {
    parse_jdem(text, "grid.jdem");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

const char* kHeader =
    "JDEM 1\nquantity: height\nunits: m\nrows: 2\ncols: 3\nresolution: 0.5\n"
    "center_x: 0\ncenter_y: 0\nyaw: 0\nnodata: nan\ndata:\n";

TEST(Jdem, RoundTripThroughAFileIsBitExact) {
  testing::TempDir dir;
  const JdemGrid grid = random_grid(17, 23, 7);
  write_jdem(dir / "g.jdem", grid);
  const JdemGrid back = read_jdem(dir / "g.jdem");
  EXPECT_EQ(back.quantity, grid.quantity);
  EXPECT_EQ(back.units, grid.units);
  ASSERT_EQ(back.rows, 17);
  ASSERT_EQ(back.cols, 23);
  EXPECT_EQ(back.resolution_m, grid.resolution_m);
  EXPECT_EQ(back.center_x_m, grid.center_x_m);
  EXPECT_EQ(back.center_y_m, grid.center_y_m);
  EXPECT_EQ(back.yaw_rad, grid.yaw_rad);
  EXPECT_EQ(back.metadata, grid.metadata);
  EXPECT_EQ(back.meta("frame"), "000123");
  for (size_t i = 0; i < grid.values.size(); ++i) ASSERT_EQ(back.values[i], grid.values[i]) << i;
}

TEST(Jdem, NanIsWrittenAsNodataAndReadBackAsNan) {
  JdemGrid grid = random_grid(3, 4, 1);
  grid.at(1, 2) = NAN;
  grid.at(0, 0) = NAN;
  const std::string text = format_jdem(grid);
  EXPECT_NE(text.find("nan"), std::string::npos);
  const JdemGrid back = parse_jdem(text, "t");
  EXPECT_TRUE(std::isnan(back.at(1, 2)));
  EXPECT_TRUE(std::isnan(back.at(0, 0)));
  EXPECT_EQ(back.at(2, 3), grid.at(2, 3));
}

TEST(Jdem, NumericNodataBecomesNanInMemoryAndSurvivesRoundTrip) {
  const std::string text =
      "JDEM 1\nrows: 1\ncols: 3\nresolution: 1\ncenter_x: 0\ncenter_y: 0\nnodata: -9999\n"
      "data:\n1.5 -9999 2\n";
  JdemGrid g = parse_jdem(text, "t");
  EXPECT_EQ(g.at(0, 0), 1.5f);
  EXPECT_TRUE(std::isnan(g.at(0, 1)));
  EXPECT_EQ(g.at(0, 2), 2.0f);
  const JdemGrid again = parse_jdem(format_jdem(g), "t");
  EXPECT_NE(format_jdem(g).find("1.5 -9999 2"), std::string::npos);
  EXPECT_TRUE(std::isnan(again.at(0, 1)));
}

TEST(Jdem, HeaderCommentsAndUnknownKeysAreAccepted) {
  const std::string text =
      "JDEM 1\nquantity: hazard   # 0 unknown 1 traversable 2 hazard\nrows: 1\ncols: 2\n"
      "resolution: 0.01\ncenter_x: 1\ncenter_y: 2\nrobot: rover-a\ndata:\n0 2\n";
  const JdemGrid g = parse_jdem(text, "t");
  EXPECT_EQ(g.quantity, "hazard");
  EXPECT_EQ(g.meta("robot"), "rover-a");
  EXPECT_EQ(g.at(0, 1), 2.0f);
}

TEST(Jdem, RejectsWrongMagicOnLineOne) {
  EXPECT_EQ(parse_error("JDEM 2\nrows: 1\n"), "grid.jdem:1: expected 'JDEM 1', found 'JDEM 2'");
}

TEST(Jdem, RejectsShortRowNamingItsLine) {
  // Line 12 is the first data row, line 13 the second.
  const std::string msg = parse_error(std::string(kHeader) + "1 2 3\n4 5\n");
  EXPECT_EQ(msg, "grid.jdem:13: row has 2 values, expected 3");
}

TEST(Jdem, RejectsLongRowNamingItsLine) {
  EXPECT_EQ(parse_error(std::string(kHeader) + "1 2 3 4\n4 5 6\n"),
            "grid.jdem:12: row has more than 3 values");
}

TEST(Jdem, RejectsMissingRowsAtEndOfFile) {
  EXPECT_EQ(parse_error(std::string(kHeader) + "1 2 3\n"),
            "grid.jdem:12: data has 1 rows, expected 2 (file ends here)");
}

TEST(Jdem, RejectsExtraRows) {
  EXPECT_EQ(parse_error(std::string(kHeader) + "1 2 3\n4 5 6\n7 8 9\n"),
            "grid.jdem:14: more data rows than 'rows: 2'");
}

TEST(Jdem, RejectsNonNumericValue) {
  EXPECT_EQ(parse_error(std::string(kHeader) + "1 2 3\n4 x5 6\n"), "grid.jdem:13: not a number: 'x5'");
}

TEST(Jdem, RejectsMissingHeaderKey) {
  const std::string msg = parse_error("JDEM 1\nrows: 1\ncols: 1\ncenter_x: 0\ncenter_y: 0\ndata:\n1\n");
  EXPECT_EQ(msg, "grid.jdem:6: header lacks key 'resolution'");
}

TEST(Jdem, RejectsBadHeaderValue) {
  EXPECT_EQ(parse_error("JDEM 1\nrows: -3\n"),
            "grid.jdem:2: key 'rows': expected a non-negative integer, found '-3'");
}

TEST(Jdem, HugeClaimedSizeIsShortDataNotAnAllocation) {
  // 1e8 x 1e8 cells would be 40 PB of floats: only the values present are stored.
  EXPECT_EQ(parse_error("JDEM 1\nrows: 100000000\ncols: 100000000\nresolution: 1\ncenter_x: 0\n"
                        "center_y: 0\ndata:\n"),
            "grid.jdem:7: data has 0 rows, expected 100000000 (file ends here)");
}
TEST(Jdem, RejectsAValueBeyondFloatRange) {
  EXPECT_EQ(parse_error(std::string(kHeader) + "1 2 3\n4 1e300 6\n"),
            "grid.jdem:13: value '1e300' is beyond the range of a 32-bit float");
}
TEST(Jdem, ReadingAMissingFileNamesIt) {
  try {
    read_jdem("/nonexistent/x.jdem");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/x.jdem: cannot open JDEM file");
  }
}

TEST(Jdem, WriterRejectsInconsistentSize) {
  JdemGrid g = random_grid(2, 2, 3);
  g.values.pop_back();
  EXPECT_THROW(format_jdem(g), Error);
}

// The data lines are exactly what printf("%.9g") printed before the writer used
// std::to_chars: outputs stay byte-identical. Random bit patterns cover every exponent,
// subnormals and the values near the switch between fixed and exponent notation.
TEST(Jdem, ValuesAreWrittenExactlyAsPrintfPercentNineG) {
  std::mt19937 rng(20);
  std::vector<float> values = {0.0f, -0.0f, 1.0f, 2.0f, 0.0001f, 0.00001f, 123456789.0f,
                               1e9f, 99999.9922f, std::numeric_limits<float>::denorm_min(),
                               std::numeric_limits<float>::max(),
                               std::numeric_limits<float>::infinity(),
                               -std::numeric_limits<float>::infinity()};
  while (values.size() < 200000) {
    const std::uint32_t bits = static_cast<std::uint32_t>(rng());
    float v;
    std::memcpy(&v, &bits, sizeof v);
    if (!std::isnan(v)) values.push_back(v);
  }
  JdemGrid g;
  g.rows = 1;
  g.cols = static_cast<int>(values.size());
  g.resolution_m = 1;
  g.values = values;
  const std::string text = format_jdem(g);
  std::string expected;
  char buf[64];
  for (size_t i = 0; i < values.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(values[i]));
    expected += (i ? " " : "") + std::string(buf);
  }
  const size_t data = text.find("data:\n") + 6;
  ASSERT_EQ(text.substr(data), expected + "\n");
}

}  // namespace
}  // namespace hazmap
