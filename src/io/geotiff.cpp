#include "hazmap/io/geotiff.hpp"

#include <cmath>
#include <cstring>
#include <mutex>
#include <string>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal.h>
#include <gdal_frmts.h>

#include "hazmap/core/error.hpp"
#include "hazmap/io/atomic_file.hpp"

namespace hazmap {
namespace {

// W is a local metric frame, not a place on a planet: an engineering CRS in metres lets
// GIS tools show lengths and areas correctly without pretending to a geodetic datum.
const char* const kWorldFrameWkt = R"(LOCAL_CS["hazmap map frame W",UNIT["metre",1]])";

// DEFLATE at zlib's fastest level, no predictor: the writer has to keep pace with the
// frame loop. On the 38 grids of a cadre_flight frame (0.4 scale) this took 35 ms for
// 0.78 MB; the floating-point predictor (PREDICTOR=3) 64 ms for 0.52 MB, and level 6
// saved under 1 % of the bytes. Either is a tenth of the frame's JDEM text (6.1 MB).
const char* const kCreationOptions[] = {"COMPRESS=DEFLATE", "ZLEVEL=1", nullptr};

void register_gtiff() {
  // Only the GTiff driver: GDALAllRegister would also load every plugin at first use.
  static std::once_flag once;
  std::call_once(once, [] { GDALRegister_GTiff(); });
}

/// GDAL reports through a per-thread handler stack; while one of these lives, its
/// messages are kept for our one-line Error instead of printed to stderr.
struct QuietGdal {
  QuietGdal() {
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
  }
  ~QuietGdal() { CPLPopErrorHandler(); }
  QuietGdal(const QuietGdal&) = delete;
  QuietGdal& operator=(const QuietGdal&) = delete;
  static std::string last() {
    const char* m = CPLGetLastErrorMsg();
    return m != nullptr && *m != '\0' ? m : "GDAL reported no reason";
  }
  static bool failed() { return CPLGetLastErrorType() >= CE_Failure; }
};

struct Dataset {
  GDALDatasetH handle = nullptr;
  explicit Dataset(GDALDatasetH h) : handle(h) {}
  ~Dataset() { close(); }
  void close() {
    if (handle != nullptr) GDALClose(handle);
    handle = nullptr;
  }
  Dataset(const Dataset&) = delete;
  Dataset& operator=(const Dataset&) = delete;
};

}  // namespace

std::array<double, 6> geotransform(const JdemGrid& grid) {
  const double r = grid.resolution_m;
  return {grid.center_x_m - grid.cols / 2.0 * r, r, 0.0, grid.center_y_m + grid.rows / 2.0 * r,
          0.0, -r};
}

void write_geotiff(const std::filesystem::path& path, const JdemGrid& grid) {
  check(grid.values.size() == static_cast<size_t>(grid.rows) * grid.cols,
        path.string() + ": GeoTIFF: values do not match rows x cols");
  check(grid.yaw_rad == 0.0, path.string() + ": GeoTIFF: only W-aligned grids (yaw 0)");
  check(grid.rows > 0 && grid.cols > 0, path.string() + ": GeoTIFF: empty grid");
  register_gtiff();
  write_via_temporary(path, [&](const std::filesystem::path& tmp) {
    QuietGdal quiet;
    auto fail = [&](const char* what) {
      return Error(path.string() + ": GeoTIFF " + what + ": " + QuietGdal::last());
    };
    GDALDriverH driver = GDALGetDriverByName("GTiff");
    if (driver == nullptr) throw fail("driver missing");
    Dataset ds(GDALCreate(driver, tmp.c_str(), grid.cols, grid.rows, 1, GDT_Float32,
                          const_cast<char**>(kCreationOptions)));
    if (ds.handle == nullptr) throw fail("cannot create");
    std::array<double, 6> gt = geotransform(grid);
    GDALSetGeoTransform(ds.handle, gt.data());
    GDALSetProjection(ds.handle, kWorldFrameWkt);
    GDALSetMetadataItem(ds.handle, "quantity", grid.quantity.c_str(), nullptr);
    GDALSetMetadataItem(ds.handle, "units", grid.units.c_str(), nullptr);
    for (const auto& [key, value] : grid.metadata)
      GDALSetMetadataItem(ds.handle, key.c_str(), value.c_str(), nullptr);
    GDALRasterBandH band = GDALGetRasterBand(ds.handle, 1);
    GDALSetDescription(band, grid.quantity.c_str());
    GDALSetRasterUnitType(band, grid.units.c_str());
    GDALSetRasterNoDataValue(band, std::nan(""));
    if (GDALRasterIO(band, GF_Write, 0, 0, grid.cols, grid.rows,
                     const_cast<float*>(grid.values.data()), grid.cols, grid.rows, GDT_Float32,
                     0, 0) != CE_None)
      throw fail("write failed");
    // Compression and the last strips happen on close: a full disk shows up here.
    ds.close();
    if (QuietGdal::failed()) throw fail("write failed");
  });
}

JdemGrid read_geotiff(const std::filesystem::path& path) {
  register_gtiff();
  QuietGdal quiet;
  Dataset ds(GDALOpen(path.c_str(), GA_ReadOnly));
  if (ds.handle == nullptr)
    throw Error(path.string() + ": cannot open GeoTIFF: " + QuietGdal::last());
  if (GDALGetRasterCount(ds.handle) != 1)
    throw Error(path.string() + ": GeoTIFF: expected one band, found " +
                std::to_string(GDALGetRasterCount(ds.handle)));
  std::array<double, 6> gt{};
  if (GDALGetGeoTransform(ds.handle, gt.data()) != CE_None)
    throw Error(path.string() + ": GeoTIFF: no geotransform");
  if (gt[2] != 0.0 || gt[4] != 0.0 || !(gt[1] > 0) || gt[5] != -gt[1])
    throw Error(path.string() + ": GeoTIFF: not a north-up grid of square cells");
  JdemGrid grid;
  grid.rows = GDALGetRasterYSize(ds.handle);
  grid.cols = GDALGetRasterXSize(ds.handle);
  grid.resolution_m = gt[1];
  grid.center_x_m = gt[0] + grid.cols / 2.0 * gt[1];
  grid.center_y_m = gt[3] - grid.rows / 2.0 * gt[1];
  grid.metadata.clear();
  if (char** items = GDALGetMetadata(ds.handle, nullptr)) {
    for (int i = 0; items[i] != nullptr; ++i) {
      char* key = nullptr;
      const char* value = CPLParseNameValue(items[i], &key);
      if (key == nullptr) continue;
      const std::string k = key;
      CPLFree(key);
      if (k == "quantity") grid.quantity = value;
      else if (k == "units") grid.units = value;
      else if (k != "AREA_OR_POINT") grid.metadata.emplace_back(k, value);
    }
  }
  GDALRasterBandH band = GDALGetRasterBand(ds.handle, 1);
  grid.values.resize(static_cast<size_t>(grid.rows) * grid.cols);
  if (GDALRasterIO(band, GF_Read, 0, 0, grid.cols, grid.rows, grid.values.data(), grid.cols,
                   grid.rows, GDT_Float32, 0, 0) != CE_None)
    throw Error(path.string() + ": GeoTIFF: cannot read band 1: " + QuietGdal::last());
  int has_nodata = 0;
  const double nodata = GDALGetRasterNoDataValue(band, &has_nodata);
  if (has_nodata && !std::isnan(nodata))
    for (float& v : grid.values)
      if (v == static_cast<float>(nodata)) v = std::nanf("");
  return grid;
}

}  // namespace hazmap
