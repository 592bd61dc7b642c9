#pragma once
// A double as text through a printf format: the one formatter behind the reports, the
// run viewer, the calibration files and the error messages.

#include <cmath>
#include <cstdio>
#include <string>

namespace hazmap {

/// `v` printed with `format`, a printf format holding one double conversion ("%.6g").
inline std::string printf_double(double v, const char* format) {
  char buffer[64];
  const int n = std::snprintf(buffer, sizeof buffer, format, v);
  if (n < 0) return std::string();
  if (n < static_cast<int>(sizeof buffer)) return std::string(buffer, static_cast<std::size_t>(n));
  std::string text(static_cast<std::size_t>(n) + 1, '\0');
  std::snprintf(text.data(), text.size(), format, v);
  text.pop_back();
  return text;
}

/// printf_double(v, format) for a finite `v`, `otherwise` for NaN and infinities.
inline std::string printf_finite(double v, const char* format, const char* otherwise) {
  return std::isfinite(v) ? printf_double(v, format) : std::string(otherwise);
}

}  // namespace hazmap
