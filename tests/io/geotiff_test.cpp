// GeoTIFF grids (SPEC 9): written with our writer, read back with GDAL's own API (not
// through read_geotiff alone), and by the gdalinfo tool when it is installed.

#include "hazmap/io/geotiff.hpp"

#include <array>
#include <cmath>
#include <cstring>

#include <gdal.h>
#include <gdal_frmts.h>
#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

/// 3 rows x 4 columns, 5 cm cells centred at (1.2, -0.4); value 10*row + col, one NaN.
JdemGrid sample_grid() {
  JdemGrid g;
  g.quantity = "height";
  g.units = "m";
  g.rows = 3;
  g.cols = 4;
  g.resolution_m = 0.05;
  g.center_x_m = 1.2;
  g.center_y_m = -0.4;
  g.metadata.emplace_back("frame", "000123");
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) g.values.push_back(static_cast<float>(10 * r + c) + 0.25f);
  g.at(1, 2) = std::nanf("");
  return g;
}

TEST(GeoTiff, GdalReadsBackValuesGeotransformNodataAndCompression) {
  testing::TempDir dir;
  const JdemGrid g = sample_grid();
  const auto path = dir / "L0_height.tif";
  write_geotiff(path, g);

  GDALRegister_GTiff();
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  ASSERT_NE(ds, nullptr);
  EXPECT_EQ(GDALGetRasterXSize(ds), 4);
  EXPECT_EQ(GDALGetRasterYSize(ds), 3);
  ASSERT_EQ(GDALGetRasterCount(ds), 1);
  std::array<double, 6> gt{};
  ASSERT_EQ(GDALGetGeoTransform(ds, gt.data()), CE_None);
  // North-up: the top-left corner is (smallest x, largest y), like JDEM's row 0.
  EXPECT_NEAR(gt[0], 1.2 - 2 * 0.05, 1e-12);
  EXPECT_DOUBLE_EQ(gt[1], 0.05);
  EXPECT_EQ(gt[2], 0.0);
  EXPECT_NEAR(gt[3], -0.4 + 1.5 * 0.05, 1e-12);
  EXPECT_EQ(gt[4], 0.0);
  EXPECT_DOUBLE_EQ(gt[5], -0.05);
  const char* compression = GDALGetMetadataItem(ds, "COMPRESSION", "IMAGE_STRUCTURE");
  ASSERT_NE(compression, nullptr);
  EXPECT_STREQ(compression, "DEFLATE");
  const char* frame = GDALGetMetadataItem(ds, "frame", nullptr);
  ASSERT_NE(frame, nullptr);
  EXPECT_STREQ(frame, "000123");
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  EXPECT_EQ(GDALGetRasterDataType(band), GDT_Float32);
  int has_nodata = 0;
  EXPECT_TRUE(std::isnan(GDALGetRasterNoDataValue(band, &has_nodata)));
  EXPECT_TRUE(has_nodata);
  std::vector<float> values(12);
  ASSERT_EQ(GDALRasterIO(band, GF_Read, 0, 0, 4, 3, values.data(), 4, 3, GDT_Float32, 0, 0),
            CE_None);
  GDALClose(ds);
  for (size_t i = 0; i < values.size(); ++i) {
    if (std::isnan(g.values[i])) {
      EXPECT_TRUE(std::isnan(values[i])) << i;
    } else {
      EXPECT_EQ(values[i], g.values[i]) << i;  // float32 stored losslessly
    }
  }
  // Row 0 holds the largest y: the top-left cell's centre maps to row 0, column 0.
  const double x = g.center_x_m - 1.5 * 0.05, y = g.center_y_m + 1.0 * 0.05;
  EXPECT_EQ(std::floor((x - gt[0]) / gt[1]), 0.0);
  EXPECT_EQ(std::floor((y - gt[3]) / gt[5]), 0.0);
}

TEST(GeoTiff, RoundTripsThroughReadGeotiffAndLeavesNoTemporaries) {
  testing::TempDir dir;
  const JdemGrid g = sample_grid();
  write_geotiff(dir / "a.tif", g);
  write_geotiff(dir / "a.tif", g);  // replacing an existing file
  const JdemGrid back = read_geotiff(dir / "a.tif");
  EXPECT_EQ(back.rows, g.rows);
  EXPECT_EQ(back.cols, g.cols);
  EXPECT_NEAR(back.resolution_m, g.resolution_m, 1e-15);
  EXPECT_NEAR(back.center_x_m, g.center_x_m, 1e-12);
  EXPECT_NEAR(back.center_y_m, g.center_y_m, 1e-12);
  EXPECT_EQ(back.quantity, "height");
  EXPECT_EQ(back.units, "m");
  EXPECT_EQ(back.meta("frame"), "000123");
  ASSERT_EQ(back.values.size(), g.values.size());
  for (size_t i = 0; i < g.values.size(); ++i)
    EXPECT_TRUE(back.values[i] == g.values[i] || (std::isnan(back.values[i]) && std::isnan(g.values[i])));
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir.path()))
    names.push_back(e.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"a.tif"});  // no .tmp, no .aux.xml
}

TEST(GeoTiff, FailureNamesTheFileAndLeavesNothing) {
  testing::TempDir dir;
  write_geotiff(dir / "blocker", sample_grid());  // a file where a folder should be
  try {
    write_geotiff(dir / "blocker/x.tif", sample_grid());
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("blocker"), std::string::npos) << e.what();
  }
  JdemGrid yawed = sample_grid();
  yawed.yaw_rad = 0.1;
  EXPECT_THROW(write_geotiff(dir / "yawed.tif", yawed), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "yawed.tif"));
}

TEST(GeoTiff, GdalinfoReadsAWrittenFile) {
  if (testing::run_command("command -v gdalinfo >/dev/null 2>&1").exit_code != 0)
    GTEST_SKIP() << "gdalinfo not installed (Debian package gdal-bin)";
  testing::TempDir dir;
  write_geotiff(dir / "g.tif", sample_grid());
  const testing::CommandResult r = testing::run_command("gdalinfo " + (dir / "g.tif").string() + " 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Driver: GTiff"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Size is 4, 3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Type=Float32"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("COMPRESSION=DEFLATE"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("NoData Value=nan"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Pixel Size = (0.05"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace hazmap
