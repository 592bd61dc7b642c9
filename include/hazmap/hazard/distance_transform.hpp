#pragma once
// Exact Euclidean distance transform on a grid: the distance to the nearest source along
// each column (binary input: two sweeps), then Felzenszwalb and Huttenlocher's lower
// envelope of parabolas along each row: O(cells), no allocation once the buffers have
// grown.

#include <vector>

namespace hazmap {

class DistanceTransform {
 public:
  /// `squared[i]` gets the squared distance, in cells, from cell i (row-major, rows x
  /// cols) to the nearest cell with `is_source[i]` != 0; a huge value when there is none.
  void compute(const unsigned char* is_source, int rows, int cols, std::vector<float>& squared);

 private:
  void pass(const float* f, int n, int stride_in, float* d, int stride_out);
  std::vector<float> column_;   ///< first pass result
  std::vector<int> near_;       ///< first pass: cells to the nearest source in the column
  std::vector<float> line_, out_;
  std::vector<int> v_;
  std::vector<double> z_;  ///< parabola boundaries (double: q^2 reaches 1e6)
};

/// Squared distance value that stands for "no source" (far beyond any grid).
constexpr float kNoSourceSquared = 1e20f;

}  // namespace hazmap
