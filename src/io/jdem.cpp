#include "hazmap/io/jdem.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include "hazmap/core/error.hpp"
#include "hazmap/io/atomic_file.hpp"

namespace hazmap {
namespace {

std::string trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  const auto end = s.find_last_not_of(" \t\r");
  return s.substr(begin, end - begin + 1);
}

std::string format_double(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

/// Parses a whole token as a finite-or-nan number; false on trailing junk.
bool parse_number(const char* begin, const char* end, double* out) {
  const std::string token(begin, end);
  if (token == "nan" || token == "NaN" || token == "NAN") {
    *out = std::nan("");
    return true;
  }
  char* stop = nullptr;
  errno = 0;
  const double v = std::strtod(token.c_str(), &stop);
  if (stop != token.c_str() + token.size() || token.empty() || errno == ERANGE) return false;
  *out = v;
  return true;
}

}  // namespace

std::string JdemGrid::meta(const std::string& key) const {
  for (const auto& [k, v] : metadata)
    if (k == key) return v;
  return "";
}

std::string format_jdem(const JdemGrid& grid) {
  check(grid.rows >= 0 && grid.cols >= 0 &&
            grid.values.size() == static_cast<size_t>(grid.rows) * grid.cols,
        "JDEM: values hold " + std::to_string(grid.values.size()) + " numbers, rows x cols = " +
            std::to_string(grid.rows) + " x " + std::to_string(grid.cols));
  std::string out;
  out.reserve(256 + grid.values.size() * 10);
  out += "JDEM 1\n";
  out += "quantity: " + grid.quantity + "\n";
  out += "units: " + grid.units + "\n";
  out += "rows: " + std::to_string(grid.rows) + "\n";
  out += "cols: " + std::to_string(grid.cols) + "\n";
  out += "resolution: " + format_double(grid.resolution_m) + "\n";
  out += "center_x: " + format_double(grid.center_x_m) + "\n";
  out += "center_y: " + format_double(grid.center_y_m) + "\n";
  out += "yaw: " + format_double(grid.yaw_rad) + "\n";
  out += "nodata: " + grid.nodata + "\n";
  for (const auto& [key, value] : grid.metadata) out += key + ": " + value + "\n";
  out += "data:\n";
  // The text of printf's "%.9g" (9 significant digits: every float reads back exactly),
  // through std::to_chars, which produces the same characters without printf's format
  // parsing and locale: a 1000 x 1000 grid is written several times faster.
  constexpr int kSignificantDigits = 9;
  char buf[32];
  for (int r = 0; r < grid.rows; ++r) {
    for (int c = 0; c < grid.cols; ++c) {
      if (c > 0) out += ' ';
      const float v = grid.at(r, c);
      if (std::isnan(v)) {
        out += grid.nodata;
      } else {
        const auto written = std::to_chars(buf, buf + sizeof buf, static_cast<double>(v),
                                           std::chars_format::general, kSignificantDigits);
        out.append(buf, written.ptr);
      }
    }
    out += '\n';
  }
  return out;
}

JdemGrid parse_jdem(const std::string& text, const std::string& source) {
  JdemGrid grid;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  auto fail = [&](const std::string& what) -> Error {
    return Error(source + ":" + std::to_string(line_no) + ": " + what);
  };

  if (!std::getline(in, line)) {
    line_no = 1;
    throw fail("empty file, expected 'JDEM 1'");
  }
  ++line_no;
  if (trim(line) != "JDEM 1") throw fail("expected 'JDEM 1', found '" + trim(line) + "'");

  bool have_rows = false, have_cols = false, have_res = false, have_cx = false, have_cy = false;
  bool have_data = false;
  auto number = [&](const std::string& key, const std::string& value) {
    double v = 0;
    if (!parse_number(value.data(), value.data() + value.size(), &v) || !std::isfinite(v))
      throw fail("key '" + key + "': expected a number, found '" + value + "'");
    return v;
  };
  auto count = [&](const std::string& key, const std::string& value) {
    const double v = number(key, value);
    if (v < 0 || v != std::floor(v) || v > 1e8)
      throw fail("key '" + key + "': expected a non-negative integer, found '" + value + "'");
    return static_cast<int>(v);
  };

  while (std::getline(in, line)) {
    ++line_no;
    std::string content = line;
    const auto hash = content.find('#');
    if (hash != std::string::npos) content.erase(hash);
    content = trim(content);
    if (content.empty()) continue;
    if (content == "data:") {
      have_data = true;
      break;
    }
    const auto colon = content.find(':');
    if (colon == std::string::npos) throw fail("expected 'key: value', found '" + content + "'");
    const std::string key = trim(content.substr(0, colon));
    const std::string value = trim(content.substr(colon + 1));
    if (key.empty()) throw fail("empty key");
    if (key == "quantity") grid.quantity = value;
    else if (key == "units") grid.units = value;
    else if (key == "rows") grid.rows = count(key, value), have_rows = true;
    else if (key == "cols") grid.cols = count(key, value), have_cols = true;
    else if (key == "resolution") grid.resolution_m = number(key, value), have_res = true;
    else if (key == "center_x") grid.center_x_m = number(key, value), have_cx = true;
    else if (key == "center_y") grid.center_y_m = number(key, value), have_cy = true;
    else if (key == "yaw") grid.yaw_rad = number(key, value);
    else if (key == "nodata") {
      double v = 0;
      if (!parse_number(value.data(), value.data() + value.size(), &v))
        throw fail("key 'nodata': expected 'nan' or a number, found '" + value + "'");
      grid.nodata = value;
    } else {
      grid.metadata.emplace_back(key, value);
    }
  }
  if (!have_data) throw fail("missing 'data:' line");
  const char* missing = !have_rows ? "rows" : !have_cols ? "cols" : !have_res ? "resolution"
                        : !have_cx ? "center_x" : !have_cy ? "center_y" : nullptr;
  if (missing) throw fail(std::string("header lacks key '") + missing + "'");
  if (!(grid.resolution_m > 0)) throw fail("key 'resolution' must be positive");

  double nodata_value = std::nan("");
  parse_number(grid.nodata.data(), grid.nodata.data() + grid.nodata.size(), &nodata_value);
  const bool nodata_is_nan = std::isnan(nodata_value);

  // Storage grows with the values actually read, reserved up to what the data section
  // can hold (each value takes a character and a separator): a header claiming 1e8 x 1e8
  // cells in a small file is then reported as short data, never allocated up front.
  const std::streamoff at = in.tellg();
  const size_t data_bytes = at < 0 ? 0 : text.size() - static_cast<size_t>(at);
  const double cells = static_cast<double>(grid.rows) * static_cast<double>(grid.cols);
  grid.values.reserve(static_cast<size_t>(std::min(cells, static_cast<double>(data_bytes / 2 + 1))));
  int row = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (trim(line).empty()) continue;
    if (row >= grid.rows)
      throw fail("more data rows than 'rows: " + std::to_string(grid.rows) + "'");
    const char* p = line.data();
    const char* end = p + line.size();
    int col = 0;
    while (true) {
      while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
      if (p == end) break;
      const char* start = p;
      while (p < end && *p != ' ' && *p != '\t' && *p != '\r') ++p;
      double v = 0;
      if (!parse_number(start, p, &v))
        throw fail("not a number: '" + std::string(start, p) + "'");
      if (col >= grid.cols)
        throw fail("row has more than " + std::to_string(grid.cols) + " values");
      // Grids hold floats; a finite double beyond their range has no float to become.
      if (std::isfinite(v) && std::abs(v) > std::numeric_limits<float>::max())
        throw fail("value '" + std::string(start, p) + "' is beyond the range of a 32-bit float");
      if (!nodata_is_nan && v == nodata_value) v = std::nan("");
      grid.values.push_back(static_cast<float>(v));
      ++col;
    }
    if (col != grid.cols)
      throw fail("row has " + std::to_string(col) + " values, expected " +
                 std::to_string(grid.cols));
    ++row;
  }
  if (row != grid.rows)
    throw fail("data has " + std::to_string(row) + " rows, expected " +
               std::to_string(grid.rows) + " (file ends here)");
  return grid;
}

JdemGrid read_jdem(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot open JDEM file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return parse_jdem(buffer.str(), path.string());
}

void write_jdem(const std::filesystem::path& path, const JdemGrid& grid) {
  write_file_atomically(path, format_jdem(grid));
}

}  // namespace hazmap
