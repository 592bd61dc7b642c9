#pragma once
// GeoTIFF grids (SPEC 9, `output.format: geotiff`), written and read with GDAL.
//
// One float32 band, DEFLATE-compressed, nodata NaN, georeferenced in the map frame W
// (a local metric frame, no geodetic CRS). North-up like JDEM: raster row 0 is the row
// of largest W y, column 0 the smallest W x, so the geotransform is
//   x = x_min + (col + 0.5) * resolution    (cell centre)
//   y = y_max - (row + 0.5) * resolution
// with x_min = center_x - cols/2 * resolution, y_max = center_y + rows/2 * resolution:
// GDAL's [x_min, resolution, 0, y_max, 0, -resolution]. The JDEM header's quantity,
// units and metadata keys (e.g. frame) become GDAL metadata items of the dataset.

#include <array>
#include <filesystem>

#include "hazmap/io/jdem.hpp"

namespace hazmap {

/// GDAL geotransform of a grid laid out as above.
std::array<double, 6> geotransform(const JdemGrid& grid);

/// Writes `grid` as a GeoTIFF atomically (temporary name, then rename). Throws Error
/// naming `path` when GDAL fails (disk full, no permission). yaw must be 0 (W-aligned).
void write_geotiff(const std::filesystem::path& path, const JdemGrid& grid);

/// Reads a GeoTIFF written by write_geotiff (or any north-up single-band raster with
/// square cells) into a JdemGrid: values, geometry, quantity, units and metadata.
JdemGrid read_geotiff(const std::filesystem::path& path);

}  // namespace hazmap
