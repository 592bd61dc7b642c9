#include "hazmap/pipeline/thread_pool.hpp"

#include <algorithm>

#include <opencv2/core/utility.hpp>

namespace hazmap {

namespace {

class TaskBody final : public cv::ParallelLoopBody {
 public:
  explicit TaskBody(const RangeTask& task) : task_(task) {}
  void operator()(const cv::Range& r) const override { task_(r.start, r.end); }

 private:
  const RangeTask& task_;
};

class OpenCvParallelFor final : public ParallelFor {
 public:
  void run(int n, const RangeTask& task) const override {
    cv::parallel_for_(cv::Range(0, n), TaskBody(task));
  }
  int threads() const override { return std::max(1, cv::getNumThreads()); }
};

}  // namespace

const ParallelFor& opencv_parallel_for() {
  static const OpenCvParallelFor pool;
  return pool;
}

}  // namespace hazmap
