#include "hazmap/hazard/roughness_filter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// Sliding max (sign = +1) or min (sign = -1) over windows [c - w, c + w] of one row;
/// NaN entries are skipped. Result -inf/+inf where a window holds no value; `out_var`
/// gets the variance of the extreme cell.
void sliding_extreme(const float* in, const float* var, int n, int w, float sign, float* out,
                     float* out_var, std::vector<int>& dq) {
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
    out_var[c] = tail > head ? var[dq[head]] : 0.0f;
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

void RoughnessFilter::compute(const DenseGrid& height, const DenseGrid& variance, int kernel,
                              DenseGrid& roughness, DenseGrid& sigma, DenseGrid& fill,
                              DenseGrid* slope, DenseGrid* slope_sigma) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  roughness.reset(height.rows, height.cols, height.resolution_m, height.center_x_m, height.center_y_m, nan);
  sigma.reset(height.rows, height.cols, height.resolution_m, height.center_x_m, height.center_y_m, nan);
  fill.reset(height.rows, height.cols, height.resolution_m, height.center_x_m, height.center_y_m, 0.0f);
  for (DenseGrid* g : {slope, slope_sigma})
    if (g) g->reset(height.rows, height.cols, height.resolution_m, height.center_x_m, height.center_y_m, nan);
  compute(height, variance, kernel, GridRect::full(height.rows, height.cols), roughness, sigma,
          fill, slope, slope_sigma);
}

void RoughnessFilter::compute(const DenseGrid& height, const DenseGrid& variance, int kernel,
                              const GridRect& region, DenseGrid& roughness, DenseGrid& sigma,
                              DenseGrid& fill, DenseGrid* slope, DenseGrid* slope_sigma) {
  if (kernel != kernel_) {  // allocation only when the kernel changes, not per frame
    widths_ = kernel_half_widths(kernel);
    kernel_ = kernel;
    width_used_.assign(static_cast<size_t>(kernel), 0);
    for (int w : widths_) width_used_[static_cast<size_t>(w)] = 1;
  }
  const std::vector<int>& widths = widths_;
  const int half = (kernel - 1) / 2;
  const int rows = height.rows, cols = height.cols;
  const GridRect out = region.clipped(rows, cols);
  if (out.empty()) return;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Cells whose kernel leaves the grid, or holds no observed cell, keep these.
  roughness.fill_rect(out.row0, out.row1, out.col0, out.col1, nan);
  sigma.fill_rect(out.row0, out.row1, out.col0, out.col1, nan);
  fill.fill_rect(out.row0, out.row1, out.col0, out.col1, 0.0f);
  if (detrended_) {
    for (DenseGrid* g : {slope, slope_sigma})
      if (g) g->fill_rect(out.row0, out.row1, out.col0, out.col1, nan);
    compute_detrended(height, variance, out, roughness, sigma, fill, slope, slope_sigma);
    return;
  }

  // Per distinct half-width w: sliding max/min/count of the rows the region's kernels
  // cover, over [c - w, c + w]. Each row is scanned over [col_lo, col_hi) only: a window
  // cut to that holds the same cells as one cut to the row, because its ends lie a whole
  // max_w beyond the region (or at the row's ends), so the extremes, the cell they come
  // from and the counts are those of the whole-row scan.
  const int max_w = *std::max_element(widths.begin(), widths.end());
  const int row_lo = std::max(0, out.row0 - half), row_hi = std::min(rows, out.row1 + half);
  const int col_lo = std::max(0, out.col0 - max_w), col_hi = std::min(cols, out.col1 + max_w);
  const size_t plane = static_cast<size_t>(rows) * cols;
  row_max_.resize(plane * (max_w + 1));
  row_min_.resize(plane * (max_w + 1));
  row_count_.resize(plane * (max_w + 1));
  row_max_var_.resize(plane * (max_w + 1));
  row_min_var_.resize(plane * (max_w + 1));
  int kernel_cells = 0;
  for (int w : widths) kernel_cells += 2 * w + 1;

  for (int w = 0; w <= max_w; ++w) {
    if (!width_used_[static_cast<size_t>(w)]) continue;
    for (int r = row_lo; r < row_hi; ++r) {
      const float* in = &height.values[static_cast<size_t>(r) * cols + col_lo];
      const float* var = &variance.values[static_cast<size_t>(r) * cols + col_lo];
      const size_t off = plane * w + static_cast<size_t>(r) * cols + col_lo;
      const int n = col_hi - col_lo;
      sliding_extreme(in, var, n, w, +1.0f, &row_max_[off], &row_max_var_[off], deque_);
      sliding_extreme(in, var, n, w, -1.0f, &row_min_[off], &row_min_var_[off], deque_);
      // Observed count by a running window sum.
      int count = 0;
      for (int c = 0; c <= std::min(n - 1, w); ++c) count += !std::isnan(in[c]);
      for (int c = 0; c < n; ++c) {
        row_count_[off + c] = static_cast<float>(count);
        const int add = c + w + 1, drop = c - w;
        if (add < n) count += !std::isnan(in[add]);
        if (drop >= 0) count -= !std::isnan(in[drop]);
      }
    }
  }

  for (int r = std::max(half, out.row0); r < std::min(rows - half, out.row1); ++r) {
    for (int c = std::max(half, out.col0); c < std::min(cols - half, out.col1); ++c) {
      float hi = -kInf, lo = kInf, count = 0, hi_var = 0, lo_var = 0;
      for (int k = 0; k < kernel; ++k) {
        const size_t idx = plane * widths[k] + static_cast<size_t>(r + k - half) * cols + c;
        if (row_max_[idx] > hi) hi = row_max_[idx], hi_var = row_max_var_[idx];
        if (row_min_[idx] < lo) lo = row_min_[idx], lo_var = row_min_var_[idx];
        count += row_count_[idx];
      }
      fill.at(r, c) = count / static_cast<float>(kernel_cells);
      if (count > 0) {
        roughness.at(r, c) = hi - lo;
        sigma.at(r, c) = std::sqrt(hi_var + lo_var);
      }
    }
  }
}

KernelPlane fit_kernel_plane(const int* dx, const int* dy, const float* z, int n) {
  KernelPlane p;
  if (n <= 0) return p;
  double sx = 0, sy = 0, sz = 0;
  for (int i = 0; i < n; ++i) sx += dx[i], sy += dy[i], sz += z[i];
  const double mx = sx / n, my = sy / n, mz = sz / n;
  double cxx = 0, cxy = 0, cyy = 0, cxz = 0, cyz = 0;
  for (int i = 0; i < n; ++i) {
    const double u = dx[i] - mx, v = dy[i] - my, w = z[i] - mz;
    cxx += u * u, cxy += u * v, cyy += v * v, cxz += u * w, cyz += v * w;
  }
  // Offsets are whole cells: non-collinear points give det >= 1 (a lattice triangle has
  // twice-area >= 1), so 0.5 separates collinear from not without a scale.
  const double det = cxx * cyy - cxy * cxy;
  p.slope_variance_factor = std::numeric_limits<double>::infinity();
  if (det > 0.5) {
    p.b = (cyy * cxz - cxy * cyz) / det;
    p.c = (cxx * cyz - cxy * cxz) / det;
    p.slope_variance_factor = (cxx + cyy) / det;
  } else if (cxx + cyy > 0.5) {  // collinear: the slope along their line, none across
    const double theta = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);
    const double ex = std::cos(theta), ey = std::sin(theta);
    const double along = ex * ex * cxx + 2 * ex * ey * cxy + ey * ey * cyy;
    const double slope = (ex * cxz + ey * cyz) / along;
    p.b = slope * ex;
    p.c = slope * ey;
    p.slope_variance_factor = 1.0 / along;
  }
  p.a = mz - p.b * mx - p.c * my;
  return p;
}

void RoughnessFilter::compute_detrended(const DenseGrid& height, const DenseGrid& variance,
                                        const GridRect& out, DenseGrid& roughness,
                                        DenseGrid& sigma, DenseGrid& fill, DenseGrid* slope,
                                        DenseGrid* slope_sigma) {
  const double r = height.resolution_m;
  const std::vector<int>& widths = widths_;
  const int kernel = kernel_, half = (kernel - 1) / 2;
  const int rows = height.rows, cols = height.cols;
  int kernel_cells = 0;
  for (int w : widths) kernel_cells += 2 * w + 1;
  // Scratch for one kernel's observed cells (sized once per kernel: no per-frame growth).
  kdx_.resize(static_cast<size_t>(kernel_cells));
  kdy_.resize(kdx_.size());
  kz_.resize(kdx_.size());
  kvar_.resize(kdx_.size());
  for (int row = std::max(half, out.row0); row < std::min(rows - half, out.row1); ++row) {
    for (int col = std::max(half, out.col0); col < std::min(cols - half, out.col1); ++col) {
      int n = 0;
      for (int dy = -half; dy <= half; ++dy) {
        const int w = widths[dy + half];
        const float* hrow = &height.values[static_cast<size_t>(row + dy) * cols];
        const float* vrow = &variance.values[static_cast<size_t>(row + dy) * cols];
        for (int dx = -w; dx <= w; ++dx) {
          const float v = hrow[col + dx];
          if (std::isnan(v)) continue;
          kdx_[n] = dx, kdy_[n] = dy, kz_[n] = v, kvar_[n] = vrow[col + dx];
          ++n;
        }
      }
      fill.at(row, col) = static_cast<float>(n) / static_cast<float>(kernel_cells);
      if (n == 0) continue;
      const KernelPlane p = fit_kernel_plane(kdx_.data(), kdy_.data(), kz_.data(), n);
      double hi = -kInf, lo = kInf, var_sum = 0;
      float hi_var = 0, lo_var = 0;
      for (int i = 0; i < n; ++i) {
        var_sum += kvar_[i];
        const double e = kz_[i] - (p.a + p.b * kdx_[i] + p.c * kdy_[i]);
        if (e > hi) hi = e, hi_var = kvar_[i];
        if (e < lo) lo = e, lo_var = kvar_[i];
      }
      roughness.at(row, col) = static_cast<float>(hi - lo);
      sigma.at(row, col) = std::sqrt(hi_var + lo_var);
      if (slope && std::isfinite(p.slope_variance_factor)) {
        // Offsets are in cells: slopes per cell / r. The cells' mean variance stands for
        // each one's in the least-squares propagation.
        slope->at(row, col) = static_cast<float>(std::hypot(p.b, p.c) / r);
        if (slope_sigma)
          slope_sigma->at(row, col) =
              static_cast<float>(std::sqrt(var_sum / n * p.slope_variance_factor) / r);
      }
    }
  }
}

void roughness_brute_force(const DenseGrid& height, const DenseGrid& variance, int kernel,
                           DenseGrid& roughness, DenseGrid& sigma, DenseGrid& fill) {
  const std::vector<int> widths = kernel_half_widths(kernel);
  const int half = (kernel - 1) / 2;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  roughness.reset(height.rows, height.cols, height.resolution_m, height.center_x_m,
                  height.center_y_m, nan);
  sigma.reset(height.rows, height.cols, height.resolution_m, height.center_x_m,
              height.center_y_m, nan);
  fill.reset(height.rows, height.cols, height.resolution_m, height.center_x_m, height.center_y_m,
             0.0f);
  int kernel_cells = 0;
  for (int w : widths) kernel_cells += 2 * w + 1;
  for (int r = half; r < height.rows - half; ++r) {
    for (int c = half; c < height.cols - half; ++c) {
      float hi = -kInf, lo = kInf, hi_var = 0, lo_var = 0;
      int count = 0;
      for (int dy = -half; dy <= half; ++dy) {
        const int w = widths[dy + half];
        for (int dx = -w; dx <= w; ++dx) {
          const float v = height.at(r + dy, c + dx);
          if (std::isnan(v)) continue;
          if (v > hi) hi = v, hi_var = variance.at(r + dy, c + dx);
          if (v < lo) lo = v, lo_var = variance.at(r + dy, c + dx);
          ++count;
        }
      }
      fill.at(r, c) = static_cast<float>(count) / static_cast<float>(kernel_cells);
      if (count > 0) {
        roughness.at(r, c) = hi - lo;
        sigma.at(r, c) = std::sqrt(hi_var + lo_var);
      }
    }
  }
}

}  // namespace hazmap
