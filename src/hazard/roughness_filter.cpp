#include "hazmap/hazard/roughness_filter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// Sliding max (sign = +1) or min (sign = -1) over windows [c - w, c + w] of one row;
/// NaN entries are skipped. Result -inf/+inf where a window holds no value.
void sliding_extreme(const float* in, int n, int w, float sign, float* out, std::vector<int>& dq) {
  dq.resize(static_cast<size_t>(n));
  int head = 0, tail = 0;
  // Window for output c is [c - w, c + w]; push index j = c + w as c advances.
  int next = 0;
  for (int c = 0; c < n; ++c) {
    const int hi = std::min(n - 1, c + w);
    for (; next <= hi; ++next) {
      const float v = in[next];
      if (std::isnan(v)) continue;
      while (tail > head && sign * in[dq[tail - 1]] <= sign * v) --tail;
      dq[tail++] = next;
    }
    while (tail > head && dq[head] < c - w) ++head;
    out[c] = tail > head ? in[dq[head]] : -sign * kInf;
  }
}

}  // namespace

std::vector<int> kernel_half_widths(int kernel) {
  check(kernel >= 1 && kernel % 2 == 1, "roughness kernel must be odd and >= 1");
  const int half = (kernel - 1) / 2;
  const double radius = kernel / 2.0;
  std::vector<int> widths;
  for (int dy = -half; dy <= half; ++dy)
    widths.push_back(static_cast<int>(std::floor(std::sqrt(radius * radius - dy * dy) + 1e-9)));
  return widths;
}

void RoughnessFilter::compute(const DenseGrid& height, int kernel, DenseGrid& roughness,
                              DenseGrid& fill) {
  if (kernel != kernel_) {  // allocation only when the kernel changes, not per frame
    widths_ = kernel_half_widths(kernel);
    kernel_ = kernel;
    width_used_.assign(static_cast<size_t>(kernel), 0);
    for (int w : widths_) width_used_[static_cast<size_t>(w)] = 1;
  }
  const std::vector<int>& widths = widths_;
  const int half = (kernel - 1) / 2;
  const int rows = height.rows, cols = height.cols;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  roughness.reset(rows, cols, height.resolution_m, height.center_x_m, height.center_y_m, nan);
  fill.reset(rows, cols, height.resolution_m, height.center_x_m, height.center_y_m, 0.0f);

  // Per distinct half-width w: sliding max/min/count of every row over [c - w, c + w].
  const int max_w = *std::max_element(widths.begin(), widths.end());
  const size_t plane = static_cast<size_t>(rows) * cols;
  row_max_.resize(plane * (max_w + 1));
  row_min_.resize(plane * (max_w + 1));
  row_count_.resize(plane * (max_w + 1));
  int kernel_cells = 0;
  for (int w : widths) kernel_cells += 2 * w + 1;

  for (int w = 0; w <= max_w; ++w) {
    if (!width_used_[static_cast<size_t>(w)]) continue;
    for (int r = 0; r < rows; ++r) {
      const float* in = &height.values[static_cast<size_t>(r) * cols];
      const size_t off = plane * w + static_cast<size_t>(r) * cols;
      sliding_extreme(in, cols, w, +1.0f, &row_max_[off], deque_);
      sliding_extreme(in, cols, w, -1.0f, &row_min_[off], deque_);
      // Observed count by a running window sum.
      int count = 0;
      for (int c = 0; c <= std::min(cols - 1, w); ++c) count += !std::isnan(in[c]);
      for (int c = 0; c < cols; ++c) {
        row_count_[off + c] = static_cast<float>(count);
        const int add = c + w + 1, drop = c - w;
        if (add < cols) count += !std::isnan(in[add]);
        if (drop >= 0) count -= !std::isnan(in[drop]);
      }
    }
  }

  for (int r = half; r < rows - half; ++r) {
    for (int c = half; c < cols - half; ++c) {
      float hi = -kInf, lo = kInf, count = 0;
      for (int k = 0; k < kernel; ++k) {
        const size_t idx = plane * widths[k] + static_cast<size_t>(r + k - half) * cols + c;
        hi = std::max(hi, row_max_[idx]);
        lo = std::min(lo, row_min_[idx]);
        count += row_count_[idx];
      }
      fill.at(r, c) = count / static_cast<float>(kernel_cells);
      if (count > 0) roughness.at(r, c) = hi - lo;
    }
  }
}

void roughness_brute_force(const DenseGrid& height, int kernel, DenseGrid& roughness,
                           DenseGrid& fill) {
  const std::vector<int> widths = kernel_half_widths(kernel);
  const int half = (kernel - 1) / 2;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  roughness.reset(height.rows, height.cols, height.resolution_m, height.center_x_m,
                  height.center_y_m, nan);
  fill.reset(height.rows, height.cols, height.resolution_m, height.center_x_m, height.center_y_m,
             0.0f);
  int kernel_cells = 0;
  for (int w : widths) kernel_cells += 2 * w + 1;
  for (int r = half; r < height.rows - half; ++r) {
    for (int c = half; c < height.cols - half; ++c) {
      float hi = -kInf, lo = kInf;
      int count = 0;
      for (int dy = -half; dy <= half; ++dy) {
        const int w = widths[dy + half];
        for (int dx = -w; dx <= w; ++dx) {
          const float v = height.at(r + dy, c + dx);
          if (std::isnan(v)) continue;
          hi = std::max(hi, v);
          lo = std::min(lo, v);
          ++count;
        }
      }
      fill.at(r, c) = static_cast<float>(count) / static_cast<float>(kernel_cells);
      if (count > 0) roughness.at(r, c) = hi - lo;
    }
  }
}

void classify_roughness(const DenseGrid& height, const DenseGrid& roughness,
                        const DenseGrid& fill, const RoughnessParams& params, DenseGrid& hazard) {
  hazard.reset(height.rows, height.cols, height.resolution_m, height.center_x_m,
               height.center_y_m, static_cast<float>(HazardClass::unknown));
  for (size_t i = 0; i < height.values.size(); ++i) {
    if (std::isnan(height.values[i]) || std::isnan(roughness.values[i])) continue;
    if (fill.values[i] < params.min_fill) continue;
    hazard.values[i] = static_cast<float>(roughness.values[i] > params.threshold_m
                                              ? HazardClass::hazard
                                              : HazardClass::traversable);
  }
}

}  // namespace hazmap
