#pragma once
// Work split over threads the map core does not own. The core is Eigen only, so a thread
// pool comes from the application (the pipeline hands in OpenCV's, pipeline/thread_pool.hpp);
// without one every loop runs in the calling thread. Callers give each part its own
// scratch and write disjoint outputs, so results do not depend on the split.

namespace hazmap {

/// One part of a range cut into nearly equal parts: [begin, end).
struct EvenPart {
  int begin, end;
};

/// Part `i` of [0, n) cut into `parts` nearly equal pieces (their sizes differ by at most
/// one; together they cover [0, n) in order).
inline EvenPart even_part(int n, int parts, int i) {
  return {static_cast<int>(static_cast<long long>(n) * i / parts),
          static_cast<int>(static_cast<long long>(n) * (i + 1) / parts)};
}

/// The body of a parallel loop: called with disjoint [begin, end) that cover [0, n).
class RangeTask {
 public:
  virtual void operator()(int begin, int end) const = 0;

 protected:
  ~RangeTask() = default;
};

/// Runs a RangeTask over [0, n), its parts possibly on several threads at once; returns
/// when every part is done.
class ParallelFor {
 public:
  virtual ~ParallelFor() = default;
  virtual void run(int n, const RangeTask& task) const = 0;
  /// Threads it runs on (>= 1): how many parts are worth their scratch.
  virtual int threads() const = 0;
};

namespace detail {
template <class F>
class RangeLambda final : public RangeTask {
 public:
  explicit RangeLambda(const F& f) : f_(f) {}
  void operator()(int begin, int end) const override { f_(begin, end); }

 private:
  const F& f_;
};
}  // namespace detail

/// f(begin, end) over [0, n): on `pool` when given and n > 1, else here in one call. A
/// plain wrapper (no std::function), so the per-frame path allocates nothing.
template <class F>
void parallel_for(const ParallelFor* pool, int n, const F& f) {
  if (n <= 0) return;
  if (pool == nullptr || n == 1) {
    f(0, n);
    return;
  }
  pool->run(n, detail::RangeLambda<F>(f));
}

}  // namespace hazmap
