#include "hazmap/eval/grid_checks.hpp"

#include <cmath>
#include <cstdio>

#include "hazmap/core/error.hpp"
#include "hazmap/core/number_text.hpp"

namespace hazmap::eval {
namespace {

std::string number(double v) { return printf_double(v, "%.9g"); }

}  // namespace

bool hazard_class_of(float value, HazardClass* out) {
  if (std::isnan(value)) {
    *out = HazardClass::unknown;
    return true;
  }
  // Compared as floats: no conversion of a value that may be out of int's range.
  for (const HazardClass c : {HazardClass::unknown, HazardClass::traversable, HazardClass::hazard})
    if (value == static_cast<float>(c)) {
      *out = c;
      return true;
    }
  return false;
}

void check_hazard_classes(const DenseGrid& grid, const std::string& source) {
  HazardClass c;
  for (int r = 0; r < grid.rows; ++r)
    for (int col = 0; col < grid.cols; ++col) {
      const float v = grid.at(r, col);
      if (!hazard_class_of(v, &c))
        throw Error(source + ": row " + std::to_string(r) + ", column " + std::to_string(col) +
                    ": value " + number(v) +
                    " is not a hazard class (0 unknown, 1 traversable, 2 hazard, or nodata)");
    }
}

std::string geometry_difference(const DenseGrid& a, const DenseGrid& b) {
  std::string d;
  const auto add = [&](const std::string& part) { d += (d.empty() ? "" : ", ") + part; };
  if (a.rows != b.rows || a.cols != b.cols)
    add("size " + std::to_string(a.rows) + " x " + std::to_string(a.cols) + " cells against " +
        std::to_string(b.rows) + " x " + std::to_string(b.cols));
  if (a.resolution_m != b.resolution_m)
    add("resolution " + number(a.resolution_m) + " m against " + number(b.resolution_m) + " m");
  if (a.center_x_m != b.center_x_m || a.center_y_m != b.center_y_m)
    add("centre (" + number(a.center_x_m) + ", " + number(a.center_y_m) + ") m against (" +
        number(b.center_x_m) + ", " + number(b.center_y_m) + ") m");
  return d;
}

void check_same_geometry(const DenseGrid& a, const std::string& a_file, const DenseGrid& b,
                         const std::string& b_file) {
  const std::string d = geometry_difference(a, b);
  if (!d.empty()) throw Error(a_file + " and " + b_file + " differ in geometry: " + d);
}

}  // namespace hazmap::eval
