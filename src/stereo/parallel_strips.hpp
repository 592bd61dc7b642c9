#pragma once
// Row-strip parallelism for the stereo stages that must not allocate per frame.

#include <algorithm>
#include <opencv2/core/utility.hpp>

#include "hazmap/core/parallel_for.hpp"

namespace hazmap::stereo_detail {

/// cv::parallel_for_ with a plain body: its std::function overload allocates for a lambda
/// capturing more than a pointer or two, and the per-frame path allocates nothing.
template <class F>
class ParallelBody : public cv::ParallelLoopBody {
 public:
  explicit ParallelBody(const F& f) : f_(f) {}
  void operator()(const cv::Range& r) const override { f_(r); }

 private:
  const F& f_;
};

/// Runs f(sub-range) over `range` on OpenCV's thread pool.
template <class F>
void parallel_range(cv::Range range, const F& f) {
  cv::parallel_for_(range, ParallelBody<F>(f));
}

/// How many strips a frame-sized pass is cut into: two per thread, so that a thread
/// finishing early takes another.
inline int frame_strips() { return std::max(1, cv::getNumThreads()) * 2; }

/// Splits [0, n) into `parts` nearly equal pieces; returns piece i.
inline cv::Range strip(int n, int parts, int i) {
  const EvenPart p = even_part(n, parts, i);
  return {p.begin, p.end};
}

}  // namespace hazmap::stereo_detail
