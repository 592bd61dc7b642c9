#include "hazmap/map/height_range.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace hazmap {

HeightRange robust_height_range(const DenseGrid& height, double clip_pct) {
  HeightRange r;
  std::vector<float> known;
  known.reserve(height.values.size());
  for (float v : height.values)
    if (!std::isnan(v)) known.push_back(v);
  if (known.empty()) return r;
  r.any = true;
  const auto [mn, mx] = std::minmax_element(known.begin(), known.end());
  r.min = *mn;
  r.max = *mx;
  // Nearest-rank percentiles: the value below which clip_pct % of the cells lie.
  const auto rank = [&](double pct) {
    const double pos = pct / 100.0 * static_cast<double>(known.size() - 1);
    return static_cast<std::size_t>(std::lround(pos));
  };
  const std::size_t lo = rank(clip_pct), hi = rank(100.0 - clip_pct);
  std::nth_element(known.begin(), known.begin() + static_cast<long>(lo), known.end());
  r.lo = known[lo];
  std::nth_element(known.begin(), known.begin() + static_cast<long>(hi), known.end());
  r.hi = known[hi];
  return r;
}

}  // namespace hazmap
