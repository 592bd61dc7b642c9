#include "hazmap/stereo/speckle_filter.hpp"

#include <algorithm>
#include <cstdlib>

#include "hazmap/core/error.hpp"
#include "stereo/parallel_strips.hpp"

namespace hazmap {

namespace {

/// Root of x: parent[k] <= k throughout, a root points to itself (path halving).
int find_root(int* parent, int x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

/// Joins the sets of two different roots under the smaller index (keeping parent[k] <= k);
/// returns it.
int join(int* parent, int a, int b) {
  const int lo = std::min(a, b);
  parent[std::max(a, b)] = lo;
  return lo;
}

}  // namespace

void SpeckleFilter::apply(cv::Mat& disparity, int invalid, int max_size, int max_diff) {
  if (disparity.type() != CV_16SC1) throw Error("speckle filter: expected a CV_16S disparity image");
  const int w = disparity.cols, h = disparity.rows;
  if (w == 0 || h == 0 || max_size <= 0) return;  // a component holds >= 1 pixel
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  if (parent_.size() < n) {
    parent_.resize(n);
    count_.resize(n);
  }
  const int strips = std::min(h, stereo_detail::frame_strips());
  const std::size_t joins = static_cast<std::size_t>(w) * static_cast<std::size_t>(strips - 1);
  if (absorbed_.capacity() < joins) absorbed_.reserve(joins);
  int* const parent = parent_.data();
  int* const count = count_.data();
  const auto joined = [&](int a, int b) { return std::abs(a - b) <= max_diff; };

  // 1. Each strip on its own: labels joined to the left and upper neighbour within the
  // strip, every pixel then pointing at its strip root, and each root's pixel count.
  stereo_detail::parallel_range(cv::Range(0, strips), [&](const cv::Range& range) {
    for (int s = range.start; s < range.end; ++s) {
      const cv::Range ys = stereo_detail::strip(h, strips, s);
      for (int y = ys.start; y < ys.end; ++y) {
        const std::int16_t* d = disparity.ptr<std::int16_t>(y);
        const std::int16_t* up = y > ys.start ? disparity.ptr<std::int16_t>(y - 1) : nullptr;
        int* p = parent + static_cast<std::size_t>(y) * w;
        const int row0 = y * w;
        for (int u = 0; u < w; ++u) {
          if (d[u] == invalid) {
            p[u] = -1;
            continue;
          }
          int root = row0 + u;
          if (u > 0 && d[u - 1] != invalid && joined(d[u], d[u - 1]))
            root = find_root(parent, row0 + u - 1);
          if (up && up[u] != invalid && joined(d[u], up[u])) {
            const int other = find_root(parent, row0 + u - w);
            if (root == row0 + u)
              root = other;
            else if (root != other)
              root = join(parent, root, other);
          }
          p[u] = root;
        }
      }
      const int first = ys.start * w, last = ys.end * w;
      for (int i = first; i < last; ++i) {
        count[i] = 0;
        if (parent[i] >= 0) parent[i] = parent[parent[i]];  // parent[i] <= i: already flat
      }
      for (int i = first; i < last; ++i)
        if (parent[i] >= 0) ++count[parent[i]];
    }
  });

  // 2. Across the strip borders, on one thread (w pixels per border): strip roots joined.
  absorbed_.clear();
  for (int s = 1; s < strips; ++s) {
    const int y = stereo_detail::strip(h, strips, s).start;
    const std::int16_t* d = disparity.ptr<std::int16_t>(y);
    const std::int16_t* up = disparity.ptr<std::int16_t>(y - 1);
    for (int u = 0; u < w; ++u) {
      if (d[u] == invalid || up[u] == invalid || !joined(d[u], up[u])) continue;
      const int i = y * w + u;
      const int a = find_root(parent, parent[i]), b = find_root(parent, parent[i - w]);
      if (a == b) continue;
      absorbed_.push_back(std::max(a, b));  // the root join() makes a child
      join(parent, a, b);
    }
  }
  // Each absorbed strip root adds its count to its final root and points at it.
  for (const int t : absorbed_) {
    const int g = find_root(parent, t);
    count[g] += count[t];
  }
  for (const int t : absorbed_) parent[t] = find_root(parent, t);

  // 3. Small components cleared: a pixel's final root is its strip root's parent.
  const auto cleared = static_cast<std::int16_t>(invalid);
  stereo_detail::parallel_range(cv::Range(0, strips), [&](const cv::Range& range) {
    for (int s = range.start; s < range.end; ++s) {
      const cv::Range ys = stereo_detail::strip(h, strips, s);
      for (int y = ys.start; y < ys.end; ++y) {
        std::int16_t* d = disparity.ptr<std::int16_t>(y);
        const int* p = parent + static_cast<std::size_t>(y) * w;
        for (int u = 0; u < w; ++u)
          if (p[u] >= 0 && count[parent[p[u]]] <= max_size) d[u] = cleared;
      }
    }
  });
}

}  // namespace hazmap
