#pragma once
// Unsupported disparities (SPEC 3.3, ours): seen from above the ground, whatever a pixel
// sees rests on something, and that support is at least as near as the pixel's surface,
// so it shows below the pixel in the image with a disparity at least as large. A pixel
// whose disparity is well above most of what lies under it in its column floats: a
// mismatch (measured on rendered lunar views: blobs at the black sky line matched at
// 150 px, i.e. a few centimetres in front of the camera, above terrain seen at 10 px).
// Overhangs break the rule; a rover's terrain has few (turn it off indoors).

#include <cstddef>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace hazmap {

class SupportCheck {
 public:
  /// Samples per pixel: rows spread evenly over the `rows` below it.
  static constexpr int kSamples = 8;
  /// Fewer valid samples than this below a pixel: no evidence, the pixel stays.
  static constexpr int kMinValidBelow = 4;

  /// `rows`: how far below a pixel its support is looked for [px] (0: off);
  /// `tolerance`: a sample counts as farther than the pixel when its disparity is below
  /// d (1 - tolerance) - margin_px.
  SupportCheck(int rows, double tolerance, double margin_px);

  bool enabled() const { return rows_ > 0; }

  /// Invalidates (sets to invalid_below_x16 - 16, as OpenCV marks invalid pixels) every
  /// valid pixel of `disparity_x16` (CV_16S, x16) for which more than half of its valid
  /// samples below are farther. Returns how many. Valid: d > invalid_below_x16 and d > 0.
  /// Row strips in parallel. Buffers are kept: no allocation after the first image of a
  /// given size.
  std::size_t apply(cv::Mat& disparity_x16, int invalid_below_x16);

 private:
  int rows_;
  double keep_fraction_;  ///< 1 - tolerance
  double margin_x16_;
  std::vector<std::int16_t> threshold_;     ///< per row strip: the far threshold of each pixel
  std::vector<std::int16_t> nowhere_;       ///< a row without a valid disparity
  std::vector<std::int16_t> threshold_of_;  ///< the far threshold by disparity [0, 32768)
  std::vector<std::uint8_t> remove_;        ///< per pixel: unsupported
  std::vector<std::size_t> removed_by_strip_;
};

}  // namespace hazmap
