#pragma once
// Progress of a long loop for a person watching it: "3/30, 0.52 frames/s, 52 s left".
// The rate is the mean over the whole loop so far (frames of one run cost about the same;
// a moving window would swing with the machine's other load). Text only: the caller
// logs it, so --quiet silences it with everything else.

#include <chrono>
#include <string>

namespace hazmap {

/// "3/30, 0.52 frames/s, 52 s left" for `done` of `total` items after `elapsed_s`
/// seconds; "30/30, 0.52 frames/s, 58 s in all" once done == total. `unit` is the
/// plural ("frames").
std::string progress_text(int done, int total, double elapsed_s, const std::string& unit = "frames");

/// The same without the count: "0.52 frames/s, 52 s left" ("" before the first item).
std::string rate_and_time_left(int done, int total, double elapsed_s,
                               const std::string& unit = "frames");

/// A duration for people: "45 s", "3 min 05 s", "2 h 04 min".
std::string human_duration(double seconds);

/// Times a loop from construction; step(done) gives progress_text at that moment.
class Progress {
 public:
  explicit Progress(int total, std::string unit = "frames")
      : total_(total), unit_(std::move(unit)), start_(std::chrono::steady_clock::now()) {}
  std::string step(int done) const { return progress_text(done, total_, elapsed_s(), unit_); }
  /// rate_and_time_left at this moment.
  std::string rate(int done) const { return rate_and_time_left(done, total_, elapsed_s(), unit_); }
  double elapsed_s() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  int total_;
  std::string unit_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace hazmap
