#include "hazmap/stereo/disparity_image.hpp"

#include <opencv2/imgproc.hpp>

#include "hazmap/core/error.hpp"

namespace hazmap {

void disparity_to_u16(const cv::Mat& disparity_x16, int invalid_below_x16, cv::Mat& out_u16) {
  check(disparity_x16.type() == CV_16SC1, "disparity image: expected CV_16S fixed point");
  out_u16.create(disparity_x16.size(), CV_16UC1);
  for (int v = 0; v < disparity_x16.rows; ++v) {
    const int16_t* in = disparity_x16.ptr<int16_t>(v);
    uint16_t* out = out_u16.ptr<uint16_t>(v);
    for (int u = 0; u < disparity_x16.cols; ++u)
      out[u] = in[u] > invalid_below_x16 && in[u] > 0 ? static_cast<uint16_t>(in[u]) : 0;
  }
}

void colorize_disparity(const cv::Mat& disparity_x16, int invalid_below_x16, int min_disparity,
                        int num_disparities, cv::Mat& out_bgr) {
  check(disparity_x16.type() == CV_16SC1, "disparity image: expected CV_16S fixed point");
  check(num_disparities > 0, "disparity image: num_disparities must be > 0");
  cv::Mat scaled(disparity_x16.size(), CV_8UC1);
  const double scale = 255.0 / (16.0 * num_disparities);
  const double offset = 16.0 * min_disparity;
  for (int v = 0; v < disparity_x16.rows; ++v) {
    const int16_t* in = disparity_x16.ptr<int16_t>(v);
    uint8_t* out = scaled.ptr<uint8_t>(v);
    for (int u = 0; u < disparity_x16.cols; ++u)
      out[u] = cv::saturate_cast<uint8_t>((in[u] - offset) * scale);
  }
  cv::applyColorMap(scaled, out_bgr, cv::COLORMAP_TURBO);
  out_bgr.setTo(cv::Scalar::all(0), disparity_x16 <= invalid_below_x16);
}

}  // namespace hazmap
