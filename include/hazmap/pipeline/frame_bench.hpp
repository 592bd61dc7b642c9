#pragma once
// The whole-frame benchmark of issue 20 (`hazmap bench`): the real Pipeline::process on
// frames read into memory beforehand (no file reading or writing is timed), per-stage
// medians, and in the same run, interleaved frame by frame, a bare full-range
// cv::StereoBM on the same rectified grey pair, so that the ratio frame / StereoBM
// compares like with like on a machine whose speed varies with its load.

#include <cstddef>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "hazmap/io/config.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/pipeline/pipeline.hpp"

namespace hazmap {

/// One stereo pair held in memory.
struct BenchFrame {
  std::string name;
  cv::Mat left, right;
  FramePose pose;
};

/// Reads the first `max_frames` frames of `sequence` (all of them if max_frames <= 0).
/// Throws Error on an unreadable image.
std::vector<BenchFrame> read_bench_frames(const Sequence& sequence, int max_frames);

struct FrameBenchOptions {
  /// Timed passes over all frames. One untimed pass runs first, so that buffers, the
  /// rolling map and OpenCV's thread pool are warm.
  int repetitions = 5;
};

/// Medians over every timed (repetition, frame), milliseconds.
struct FrameBenchResult {
  int frames = 0;
  int repetitions = 0;
  cv::Size image_size;
  int num_disparities = 0;  ///< the bare StereoBM's (the config's)
  int block_size = 0;
  StageTimes stage_ms;      ///< each stage's own median (their sum need not equal frame_ms)
  double frame_ms = 0;      ///< wall time of Pipeline::process
  double stereo_bm_ms = 0;  ///< bare cv::StereoBM::compute on the frame's rectified pair
  double points = 0;        ///< median valid points per frame
  double points_ns_per_point = 0;  ///< median of points_ms / points
  /// Median over samples of each frame's frame_ms / stereo_bm_ms: the two halves of one
  /// sample run back to back and share the machine's load, so their ratio varies less
  /// than the ratio of the two medians on a shared machine.
  double ratio = 0;
};

/// Runs `config`'s pipeline on `frames` (calibrated by `calibration`) `options.repetitions`
/// times after a warm-up pass; after each frame, cv::StereoBM::create(num_disparities,
/// block_size) with OpenCV's other defaults (no speckle filter, no left-right check) on
/// the pipeline's rectified pair. Throws Error if frames is empty or repetitions < 1.
FrameBenchResult run_frame_bench(const Config& config, const StereoCalibration& calibration,
                                 const std::vector<BenchFrame>& frames,
                                 const FrameBenchOptions& options);

/// The result as the lines `hazmap bench` prints.
std::string format_frame_bench(const FrameBenchResult& result);

}  // namespace hazmap
