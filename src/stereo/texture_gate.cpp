#include "hazmap/stereo/texture_gate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <opencv2/imgproc.hpp>

#include "hazmap/core/error.hpp"

namespace hazmap {

double image_noise_dn(const cv::Mat& grey) {
  if (grey.type() != CV_8UC1) throw Error("texture gate: expected an 8-bit grey image");
  const int rows = grey.rows, cols = grey.cols;
  if (rows < 3 || cols < 3) return 0.0;
  // [1 -2 1; -2 4 -2; 1 -2 1], row by row; integers are exact.
  long long total = 0;
  for (int y = 1; y + 1 < rows; ++y) {
    const std::uint8_t* a = grey.ptr<std::uint8_t>(y - 1);
    const std::uint8_t* b = grey.ptr<std::uint8_t>(y);
    const std::uint8_t* c = grey.ptr<std::uint8_t>(y + 1);
    for (int x = 1; x + 1 < cols; ++x) {
      const int v = (a[x - 1] - 2 * a[x] + a[x + 1]) - 2 * (b[x - 1] - 2 * b[x] + b[x + 1]) +
                    (c[x - 1] - 2 * c[x] + c[x + 1]);
      total += std::abs(v);
    }
  }
  return std::sqrt(M_PI / 2.0) * double(total) / (6.0 * double(cols - 2) * double(rows - 2));
}

TextureGate::TextureGate(double min_snr, cv::Size window) : min_snr_(min_snr), window_(window) {}

double TextureGate::apply(const cv::Mat& left, cv::Mat& disparity_x16, short invalid) {
  if (left.type() != CV_8UC1 || disparity_x16.type() != CV_16SC1 || left.size() != disparity_x16.size())
    throw Error("texture gate: expected an 8-bit grey image and a CV_16S disparity of its size");
  if (!enabled()) return 0.0;
  const double noise = image_noise_dn(left);
  cv::integral(left, sum_, sqsum_, CV_64F, CV_64F);
  const double limit = noise * noise * (1.0 + min_snr_ * min_snr_);
  const int rows = left.rows, cols = left.cols;
  const int hx = window_.width / 2, hy = window_.height / 2;
  for (int y = 0; y < rows; ++y) {
    const int y0 = std::max(y - hy, 0), y1 = std::min(y + hy + 1, rows);
    const double* s0 = sum_.ptr<double>(y0);
    const double* s1 = sum_.ptr<double>(y1);
    const double* q0 = sqsum_.ptr<double>(y0);
    const double* q1 = sqsum_.ptr<double>(y1);
    short* d = disparity_x16.ptr<short>(y);
    for (int x = 0; x < cols; ++x) {
      if (d[x] <= invalid) continue;
      const int x0 = std::max(x - hx, 0), x1 = std::min(x + hx + 1, cols);
      const double n = double(x1 - x0) * double(y1 - y0);
      const double s = s1[x1] - s1[x0] - s0[x1] + s0[x0];
      const double q = q1[x1] - q1[x0] - q0[x1] + q0[x0];
      const double variance = q / n - (s / n) * (s / n);
      if (variance < limit) d[x] = invalid;
    }
  }
  return noise;
}

}  // namespace hazmap
