#include "hazmap/stereo/support_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hazmap/core/error.hpp"
#include "hazmap/map/internal/simd.hpp"
#include "stereo/parallel_strips.hpp"

namespace hazmap {

SupportCheck::SupportCheck(int rows, double tolerance, double margin_px)
    : rows_(rows), keep_fraction_(1.0 - tolerance), margin_x16_(16.0 * margin_px) {
  if (rows < 0) throw Error("stereo.support_rows: must be >= 0 (0: off)");
  if (!(tolerance >= 0.0 && tolerance < 1.0))
    throw Error("stereo.support_tolerance: must be in [0, 1)");
  if (!(margin_px >= 0.0 && std::isfinite(margin_px)))
    throw Error("stereo.support_margin_px: must be a non-negative number");
}

using stereo_detail::parallel_range;
using stereo_detail::strip;

namespace support_detail {

/// One row's verdicts: out[u] = 1 where pixel u is valid and more than half of its valid
/// samples (below[k][u], at least kMinValidBelow of them) are farther than threshold_of
/// its disparity. Plain loops over the row (the samples unrolled) that the compiler
/// vectorises; `thr` is scratch.
HAZMAP_KERNEL void unsupported_row(const std::int16_t* d, const std::int16_t* const* below,
                                   const std::int16_t* threshold_of, int valid_above, int cols,
                                   std::int16_t* thr, std::uint8_t* out) {
  for (int u = 0; u < cols; ++u) thr[u] = threshold_of[d[u] < 0 ? 0 : d[u]];
  constexpr int K = SupportCheck::kSamples;
  const std::int16_t* b[K];
  for (int k = 0; k < K; ++k) b[k] = below[k];
  const auto above = static_cast<std::int16_t>(valid_above);
  for (int u = 0; u < cols; ++u) {
    std::int16_t valid = 0, far = 0;
    for (int k = 0; k < K; ++k) {
      const std::int16_t sample = b[k][u];
      const std::int16_t is_valid = sample > above;
      valid = static_cast<std::int16_t>(valid + is_valid);
      far = static_cast<std::int16_t>(far + (is_valid & (sample < thr[u])));
    }
    out[u] = static_cast<std::uint8_t>((d[u] > above) & (valid >= SupportCheck::kMinValidBelow) &
                                       (2 * far > valid));
  }
}

}  // namespace support_detail

std::size_t SupportCheck::apply(cv::Mat& disparity_x16, int invalid_below_x16) {
  if (!enabled() || disparity_x16.empty()) return 0;
  if (disparity_x16.type() != CV_16S) throw Error("SupportCheck: disparity must be CV_16S");
  const int rows = disparity_x16.rows, cols = disparity_x16.cols;
  if (threshold_of_.empty()) {
    // The far threshold of every non-negative disparity, computed once (a valid pixel's
    // disparity is > 0; the others never read theirs).
    threshold_of_.resize(32768);
    for (int d = 0; d < 32768; ++d)
      threshold_of_[static_cast<std::size_t>(d)] = static_cast<std::int16_t>(
          std::max(-32768.0, std::floor(d * keep_fraction_ - margin_x16_)));
  }
  const int strips = stereo_detail::frame_strips();
  const std::size_t width = static_cast<std::size_t>(cols);
  threshold_.resize(static_cast<std::size_t>(strips) * width);
  remove_.resize(static_cast<std::size_t>(rows) * width);
  removed_by_strip_.resize(static_cast<std::size_t>(strips));
  const int valid_above = std::max(invalid_below_x16, 0);
  const auto invalid = static_cast<std::int16_t>(invalid_below_x16 - 16);
  const int spacing = std::max(1, rows_ / kSamples);
  const cv::Mat& d16 = disparity_x16;
  // Which pixels go, from the unchanged image (row strips in parallel), then away with them:
  // the same as the rule applied top to bottom in place, where row v reads only rows below.
  // Sample rows past the image's bottom or beyond `rows` read a row no pixel is valid in.
  nowhere_.assign(width, std::numeric_limits<std::int16_t>::min());
  auto decide = [&](const cv::Range& range) {
    for (int s = range.start; s < range.end; ++s) {
      std::int16_t* thr = threshold_.data() + static_cast<std::size_t>(s) * width;
      const cv::Range vs = strip(rows, strips, s);
      for (int v = vs.start; v < vs.end; ++v) {
        const std::int16_t* below[kSamples];
        for (int k = 1; k <= kSamples; ++k) {
          const int r = v + k * spacing;
          below[k - 1] = r < rows && k * spacing <= rows_ ? d16.ptr<std::int16_t>(r)
                                                          : nowhere_.data();
        }
        support_detail::unsupported_row(d16.ptr<std::int16_t>(v), below, threshold_of_.data(),
                                        valid_above, cols, thr,
                                        remove_.data() + static_cast<std::size_t>(v) * width);
      }
    }
  };
  auto clear = [&](const cv::Range& range) {
    for (int s = range.start; s < range.end; ++s) {
      std::size_t removed = 0;
      const cv::Range vs = strip(rows, strips, s);
      for (int v = vs.start; v < vs.end; ++v) {
        std::int16_t* d = disparity_x16.ptr<std::int16_t>(v);
        const std::uint8_t* out = remove_.data() + static_cast<std::size_t>(v) * width;
        for (int u = 0; u < cols; ++u) {
          d[u] = out[u] ? invalid : d[u];
          removed += out[u];
        }
      }
      removed_by_strip_[static_cast<std::size_t>(s)] = removed;
    }
  };
  parallel_range(cv::Range(0, strips), decide);
  parallel_range(cv::Range(0, strips), clear);
  std::size_t removed = 0;
  for (const std::size_t n : removed_by_strip_) removed += n;
  return removed;
}

}  // namespace hazmap
