#include "hazmap/hazard/distance_transform.hpp"

#include <algorithm>

namespace hazmap {

void DistanceTransform::pass(const float* f, int n, int stride_in, float* d, int stride_out) {
  // 1-D squared distance transform of sampled function f (Felzenszwalb & Huttenlocher).
  line_.resize(static_cast<size_t>(n));
  for (int q = 0; q < n; ++q) line_[q] = f[static_cast<size_t>(q) * stride_in];
  v_.resize(static_cast<size_t>(n));
  z_.resize(static_cast<size_t>(n) + 1);
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (line_[q] >= kNoSourceSquared) continue;
    double s = 0;
    while (k >= 0) {
      const int p = v_[k];
      s = ((double(line_[q]) + double(q) * q) - (double(line_[p]) + double(p) * p)) /
          (2.0 * (q - p));
      if (s <= z_[k]) --k;
      else break;
    }
    ++k;
    v_[k] = q;
    z_[k] = k == 0 ? -1e300 : s;
    z_[k + 1] = 1e300;
  }
  if (k < 0) {
    for (int q = 0; q < n; ++q) d[static_cast<size_t>(q) * stride_out] = kNoSourceSquared;
    return;
  }
  int j = 0;
  for (int q = 0; q < n; ++q) {
    while (z_[j + 1] < q) ++j;
    const float dq = float(q - v_[j]);
    d[static_cast<size_t>(q) * stride_out] = std::min(kNoSourceSquared, dq * dq + line_[v_[j]]);
  }
}

void DistanceTransform::compute(const unsigned char* is_source, int rows, int cols,
                                std::vector<float>& squared) {
  const size_t cells = static_cast<size_t>(rows) * cols;
  column_.resize(cells);
  squared.resize(cells);
  size_t sources = 0;
  for (size_t i = 0; i < cells; ++i) sources += is_source[i] != 0;
  if (sources == 0) {  // what the passes would give: no source anywhere
    std::fill(squared.begin(), squared.end(), kNoSourceSquared);
    return;
  }
  // Columns first. The input is binary, so a column's squared distance is that to its
  // nearest source, found by one sweep down and one up, row by row (in memory order: a
  // parabola pass down each column strides across the whole grid). Same values.
  const int none = rows;  // no source in the column (a distance is at most rows - 1)
  near_.resize(cells);
  for (int c = 0; c < cols; ++c) near_[c] = is_source[c] ? 0 : none;
  for (int r = 1; r < rows; ++r) {
    const size_t row = static_cast<size_t>(r) * cols;
    for (int c = 0; c < cols; ++c) {
      const int above = near_[row - cols + c];
      near_[row + c] = is_source[row + c] ? 0 : (above == none ? none : above + 1);
    }
  }
  for (int r = rows - 1; r >= 0; --r) {
    const size_t row = static_cast<size_t>(r) * cols;
    for (int c = 0; c < cols; ++c) {
      int d = near_[row + c];
      if (r + 1 < rows) {
        const int below = near_[row + cols + c];
        if (below != none && below + 1 < d) d = below + 1;
      }
      near_[row + c] = d;
      const float fd = static_cast<float>(d);
      column_[row + c] = d == none ? kNoSourceSquared : std::min(kNoSourceSquared, fd * fd);
    }
  }
  // Then rows (contiguous) with the lower envelope of parabolas.
  for (int r = 0; r < rows; ++r)
    pass(&column_[static_cast<size_t>(r) * cols], cols, 1, &squared[static_cast<size_t>(r) * cols], 1);
}

}  // namespace hazmap
