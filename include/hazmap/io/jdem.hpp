#pragma once
// JDEM v1: a text grid of one quantity (SPEC 9).
//
//   JDEM 1
//   quantity: height
//   units: m
//   rows: 42
//   cols: 42
//   resolution: 0.04
//   center_x: 1.20
//   center_y: -0.40
//   yaw: 0.0
//   nodata: nan
//   frame: 000123      (optional; unknown keys are kept as metadata)
//   data:
//   <rows lines of cols values>
//
// Row 0 is the row of largest y (north up, like an image); column 0 has the smallest x.
// In memory, cells holding the nodata value are NaN; on disk NaN is written as nodata.

#include <filesystem>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "hazmap/map/dense_grid.hpp"

namespace hazmap {

/// A JDEM file: a dense grid (map/dense_grid.hpp: size, resolution, centre, values in
/// image order) and the header's other keys. The grid's geometry helpers assume yaw 0;
/// every reader of rotated grids rejects them.
struct JdemGrid : DenseGrid {
  std::string quantity = "height";
  std::string units = "m";
  double yaw_rad = 0.0;
  std::string nodata = "nan";  ///< token written for NaN cells ("nan" or a number)
  /// Other header keys in file order, e.g. {"frame", "000123"}.
  std::vector<std::pair<std::string, std::string>> metadata;

  /// Value of a metadata key, or "" when absent.
  std::string meta(const std::string& key) const;
};

/// Serialises a grid. Values are printed with 9 significant digits, enough to read
/// back every float exactly. Throws Error if values.size() != rows * cols.
std::string format_jdem(const JdemGrid& grid);

/// Parses JDEM text. `source` names the file in error messages ("<source>:<line>: ...").
/// Rejects a wrong magic line, missing or malformed header keys, non-numeric values and
/// a data count that does not match rows x cols, naming the line.
JdemGrid parse_jdem(const std::string& text, const std::string& source);

/// Reads a JDEM file. Throws Error naming the file (and line) on any problem.
JdemGrid read_jdem(const std::filesystem::path& path);

/// Writes a JDEM file atomically.
void write_jdem(const std::filesystem::path& path, const JdemGrid& grid);

}  // namespace hazmap
