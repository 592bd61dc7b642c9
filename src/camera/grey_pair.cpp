#include "hazmap/camera/grey_pair.hpp"

#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

/// Luminance of colour `in` into `out`.
void to_luminance(const cv::Mat& in, cv::Mat& out) {
  switch (in.channels()) {
    case 3: cv::cvtColor(in, out, cv::COLOR_BGR2GRAY); break;
    case 4: cv::cvtColor(in, out, cv::COLOR_BGRA2GRAY); break;
    default:
      throw Error("stereo input: image has " + std::to_string(in.channels()) +
                  " channels (expected 1, 3 or 4)");
  }
}

}  // namespace

int significant_bits(const cv::Mat& left_u16, const cv::Mat& right_u16) {
  double max_left = 0, max_right = 0;
  cv::minMaxLoc(left_u16, nullptr, &max_left);
  cv::minMaxLoc(right_u16, nullptr, &max_right);
  const double max_value = std::max(max_left, max_right);
  int bits = 8;
  while (bits < 16 && max_value >= static_cast<double>(1 << bits)) ++bits;
  return bits;
}

GreyPairConverter::GreyPairConverter(std::optional<int> input_bits) : input_bits_(input_bits) {
  if (input_bits && (*input_bits < 8 || *input_bits > 16))
    throw Error("config: key 'stereo.input_bits': must be `auto` (detect) or in [8, 16]");
}

int GreyPairConverter::convert(const cv::Mat& left, const cv::Mat& right, cv::Mat& out_left,
                               cv::Mat& out_right) {
  if (left.depth() != right.depth() || left.channels() != right.channels())
    throw Error("stereo input: left and right images differ in depth or channel count");
  if (left.depth() == CV_8U) {
    // Grey input is copied, not shared: a later colour or 16-bit frame converts into the
    // same buffers and must not overwrite the caller's image.
    if (left.channels() == 1) {
      left.copyTo(out_left);
      right.copyTo(out_right);
    } else {
      to_luminance(left, out_left);
      to_luminance(right, out_right);
    }
    return 8;
  }
  if (left.depth() != CV_16U)
    throw Error("stereo input: unsupported image depth (expected 8 or 16 bit)");
  const bool grey = left.channels() == 1;
  if (!grey) {
    to_luminance(left, grey_left_);
    to_luminance(right, grey_right_);
  }
  const cv::Mat& l16 = grey ? left : grey_left_;
  const cv::Mat& r16 = grey ? right : grey_right_;
  const int bits = input_bits_ ? *input_bits_ : significant_bits(l16, r16);
  const double scale = 1.0 / static_cast<double>(1 << (bits - 8));
  l16.convertTo(out_left, CV_8U, scale);
  r16.convertTo(out_right, CV_8U, scale);
  return bits;
}

}  // namespace hazmap
