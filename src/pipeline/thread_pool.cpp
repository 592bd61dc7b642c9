#include "hazmap/pipeline/thread_pool.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

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

// A worker thread allocates the first time it runs a cv::parallel_for_ body (OpenCV gives
// it its own cv::theRNG(), thread-local storage). A worker that sat out the first frame,
// as a busy machine makes it, would allocate in a later one; so before the pool is handed
// out, one stripe per thread waits (up to a second) until every stripe has started, which
// puts each worker on one of them.
void start_every_worker() {
  const int threads = cv::getNumThreads();
  if (threads < 2) return;
  std::atomic<int> started{0};
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  cv::parallel_for_(
      cv::Range(0, threads),
      [&](const cv::Range& r) {
        started += r.end - r.start;
        while (started.load() < threads && std::chrono::steady_clock::now() < deadline)
          std::this_thread::yield();
      },
      threads);
}

}  // namespace

const ParallelFor& opencv_parallel_for() {
  static const OpenCvParallelFor pool = [] {
    start_every_worker();
    return OpenCvParallelFor();
  }();
  return pool;
}

}  // namespace hazmap
