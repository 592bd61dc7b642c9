#include "hazmap/pipeline/frame_bench.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include <opencv2/calib3d.hpp>

#include "hazmap/core/error.hpp"
#include "hazmap/core/stopwatch.hpp"
#include "hazmap/io/images.hpp"

namespace hazmap {
namespace {

using Clock = std::chrono::steady_clock;

/// Median of `v` (upper median for an even count: no averaging of two samples, which
/// under load may come from different regimes). `v` is reordered.
double median(std::vector<double>& v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

std::vector<BenchFrame> read_bench_frames(const Sequence& sequence, int max_frames) {
  const std::size_t n = max_frames > 0
                            ? std::min(sequence.frames.size(), static_cast<std::size_t>(max_frames))
                            : sequence.frames.size();
  std::vector<BenchFrame> frames;
  frames.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const SequenceFrame& f = sequence.frames[i];
    frames.push_back({f.name, read_image(f.left_path), read_image(f.right_path), f.pose});
  }
  return frames;
}

FrameBenchResult run_frame_bench(const Config& config, const StereoCalibration& calibration,
                                 const std::vector<BenchFrame>& frames,
                                 const FrameBenchOptions& options) {
  check(!frames.empty(), "frame benchmark: no frames");
  check(options.repetitions >= 1, "frame benchmark: repetitions must be >= 1");

  Pipeline pipeline(config, calibration);
  // The bare reference of issue 20: full range, the config's block size, OpenCV's
  // defaults otherwise (no speckle filter, no left-right check, no band).
  cv::Ptr<cv::StereoBM> bare =
      cv::StereoBM::create(config.stereo.num_disparities, config.stereo.block_size);
  cv::Mat bare_disparity;

  FrameBenchResult result;
  result.frames = static_cast<int>(frames.size());
  result.repetitions = options.repetitions;
  result.image_size = frames.front().left.size();
  result.num_disparities = config.stereo.num_disparities;
  result.block_size = config.stereo.block_size;

  const std::size_t samples = frames.size() * static_cast<std::size_t>(options.repetitions);
  std::vector<double> rectify, disparity, points_ms, map, hazard, frame, bm, ratio, points,
      ns_per_point;
  for (auto* v : {&rectify, &disparity, &points_ms, &map, &hazard, &frame, &bm, &ratio, &points,
                  &ns_per_point})
    v->reserve(samples);

  for (int rep = -1; rep < options.repetitions; ++rep) {  // rep -1: the warm-up pass
    for (const BenchFrame& f : frames) {
      auto t = Clock::now();
      const FrameReport report = pipeline.process(f.left, f.right, f.pose.T_W_B, f.pose.noise);
      const double frame_ms = ms_since(t);

      t = Clock::now();
      bare->compute(pipeline.rectified_left(), pipeline.rectified_right(), bare_disparity);
      const double bm_ms = ms_since(t);
      if (rep < 0) continue;

      rectify.push_back(report.ms.rectify_ms);
      disparity.push_back(report.ms.disparity_ms);
      points_ms.push_back(report.ms.points_ms);
      map.push_back(report.ms.map_ms);
      hazard.push_back(report.ms.hazard_ms);
      frame.push_back(frame_ms);
      bm.push_back(bm_ms);
      ratio.push_back(frame_ms / bm_ms);
      points.push_back(static_cast<double>(report.points));
      if (report.points > 0)
        ns_per_point.push_back(report.ms.points_ms * 1e6 / static_cast<double>(report.points));
    }
  }

  result.stage_ms.rectify_ms = median(rectify);
  result.stage_ms.disparity_ms = median(disparity);
  result.stage_ms.points_ms = median(points_ms);
  result.stage_ms.map_ms = median(map);
  result.stage_ms.hazard_ms = median(hazard);
  result.frame_ms = median(frame);
  result.stereo_bm_ms = median(bm);
  result.ratio = median(ratio);
  result.points = median(points);
  result.points_ns_per_point = median(ns_per_point);
  return result;
}

std::string format_frame_bench(const FrameBenchResult& r) {
  char buffer[1024];
  std::snprintf(
      buffer, sizeof buffer,
      "frames %d x %d repetitions, %d x %d px, medians:\n"
      "  rectify     %8.1f ms\n"
      "  disparity   %8.1f ms\n"
      "  points      %8.1f ms  (%.0f points, %.1f ns / point)\n"
      "  map         %8.1f ms\n"
      "  hazard      %8.1f ms  (%.0f %% of the frame)\n"
      "  frame       %8.1f ms  (Pipeline::process, no file reading or writing)\n"
      "  StereoBM    %8.1f ms  (bare, %d disparities, block %d, same rectified pairs)\n"
      "  frame / StereoBM  %.2f  (median of per-frame ratios)\n",
      r.frames, r.repetitions, r.image_size.width, r.image_size.height, r.stage_ms.rectify_ms,
      r.stage_ms.disparity_ms, r.stage_ms.points_ms, r.points, r.points_ns_per_point,
      r.stage_ms.map_ms, r.stage_ms.hazard_ms,
      r.frame_ms > 0 ? 100.0 * r.stage_ms.hazard_ms / r.frame_ms : 0.0, r.frame_ms,
      r.stereo_bm_ms, r.num_disparities, r.block_size, r.ratio);
  return buffer;
}

}  // namespace hazmap
