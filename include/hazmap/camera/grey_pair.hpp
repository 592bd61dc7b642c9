#pragma once
// Turns a stereo pair of any supported input (8- or 16-bit, grey, BGR or BGRA; SPEC 2)
// into the 8-bit grey images the matchers need. Colour becomes luminance
// (cv::COLOR_BGR2GRAY). 16-bit pairs are scaled by 2^(8 - bits) with one factor for both
// images, where `bits` is the sensor's significant bit count: a 10- or 12-bit sensor
// stored in 16-bit PNGs uses only the low bits, and the fixed 1/256 of a full-range
// image would crush it to 4 or 16 grey levels. Both images share the factor so that
// their brightness still matches.

#include <optional>

#include <opencv2/core.hpp>

namespace hazmap {

/// Significant bits of the brighter of two 16-bit grey images: the smallest n >= 8 with
/// max < 2^n.
int significant_bits(const cv::Mat& left_u16, const cv::Mat& right_u16);

class GreyPairConverter {
 public:
  /// `input_bits`: significant bits of 16-bit input in [8, 16], or none (stereo.input_bits
  /// `auto`) to detect them per pair with significant_bits(). Throws Error otherwise.
  explicit GreyPairConverter(std::optional<int> input_bits = std::nullopt);

  /// Converts both images (same depth and channel count) into `out_*`, reusing their
  /// buffers and the converter's. Returns the bit count used (8 for 8-bit input).
  /// Throws Error for other depths, channel counts or a depth mismatch.
  int convert(const cv::Mat& left, const cv::Mat& right, cv::Mat& out_left, cv::Mat& out_right);

 private:
  std::optional<int> input_bits_;
  cv::Mat grey_left_, grey_right_;  ///< luminance of colour 16-bit input
};

}  // namespace hazmap
