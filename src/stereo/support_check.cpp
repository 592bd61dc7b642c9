#include "hazmap/stereo/support_check.hpp"

#include <algorithm>
#include <cmath>

#include "hazmap/core/error.hpp"

namespace hazmap {

SupportCheck::SupportCheck(int rows, double tolerance, double margin_px)
    : rows_(rows), keep_fraction_(1.0 - tolerance), margin_x16_(16.0 * margin_px) {
  if (rows < 0) throw Error("stereo.support_rows: must be >= 0 (0: off)");
  if (!(tolerance >= 0.0 && tolerance < 1.0))
    throw Error("stereo.support_tolerance: must be in [0, 1)");
  if (!(margin_px >= 0.0 && std::isfinite(margin_px)))
    throw Error("stereo.support_margin_px: must be a non-negative number");
}

std::size_t SupportCheck::apply(cv::Mat& disparity_x16, int invalid_below_x16) {
  if (!enabled() || disparity_x16.empty()) return 0;
  if (disparity_x16.type() != CV_16S) throw Error("SupportCheck: disparity must be CV_16S");
  const int rows = disparity_x16.rows, cols = disparity_x16.cols;
  valid_below_.resize(static_cast<std::size_t>(cols));
  far_below_.resize(static_cast<std::size_t>(cols));
  threshold_.resize(static_cast<std::size_t>(cols));
  const int valid_above = std::max(invalid_below_x16, 0);
  const auto invalid = static_cast<std::int16_t>(invalid_below_x16 - 16);
  const int spacing = std::max(1, rows_ / kSamples);
  std::size_t removed = 0;
  // Top to bottom, in place: row v reads only rows below it, which are still unchanged.
  for (int v = 0; v < rows; ++v) {
    std::int16_t* d = disparity_x16.ptr<std::int16_t>(v);
    std::uint8_t* nv = valid_below_.data();
    std::uint8_t* nf = far_below_.data();
    std::int16_t* thr = threshold_.data();
    std::fill(nv, nv + cols, std::uint8_t{0});
    std::fill(nf, nf + cols, std::uint8_t{0});
    for (int u = 0; u < cols; ++u)
      thr[u] = static_cast<std::int16_t>(
          std::max(-32768.0, std::floor(d[u] * keep_fraction_ - margin_x16_)));
    for (int k = 1; k <= kSamples; ++k) {
      const int r = v + k * spacing;
      if (r >= rows || k * spacing > rows_) break;
      const std::int16_t* below = disparity_x16.ptr<std::int16_t>(r);
      for (int u = 0; u < cols; ++u) {
        const bool valid = below[u] > valid_above;
        nv[u] = static_cast<std::uint8_t>(nv[u] + valid);
        nf[u] = static_cast<std::uint8_t>(nf[u] + (valid && below[u] < thr[u]));
      }
    }
    for (int u = 0; u < cols; ++u)
      if (d[u] > valid_above && nv[u] >= kMinValidBelow && 2 * nf[u] > nv[u]) {
        d[u] = invalid;
        ++removed;
      }
  }
  return removed;
}

}  // namespace hazmap
