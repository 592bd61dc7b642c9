#pragma once
// Checks on the grids `hazmap evaluate` reads from a run: a hazard grid must hold classes
// (a float that is no class would reach an int conversion, undefined for -inf or NaN),
// and the grids of one layer must share one geometry. Each failure is one line naming the
// file(s) and what is wrong.

#include <string>

#include "hazmap/map/dense_grid.hpp"

namespace hazmap::eval {

/// The class a hazard grid's cell holds: 0, 1 or 2, or nodata (NaN), which reads as
/// unknown. False, `out` untouched, for any other value (-inf, 1.5, 3, ...).
bool hazard_class_of(float value, HazardClass* out);

/// Throws Error "<source>: row R, column C: value V is not a hazard class (0 unknown,
/// 1 traversable, 2 hazard, or nodata)" for the first such cell (rows and columns from 0,
/// row 0 the file's first data row).
void check_hazard_classes(const DenseGrid& grid, const std::string& source);

/// How the geometry of `a` differs from that of `b`, e.g. "size 40 x 41 cells against
/// 40 x 40" or "centre (1.2, -0.4) m against (1.2, -0.36) m"; empty when they agree.
std::string geometry_difference(const DenseGrid& a, const DenseGrid& b);

/// Throws Error "<a_file> and <b_file> differ in geometry: ..." when they do.
void check_same_geometry(const DenseGrid& a, const std::string& a_file, const DenseGrid& b,
                         const std::string& b_file);

}  // namespace hazmap::eval
