#include "hazmap/pipeline/pipeline.hpp"

#include <chrono>
#include <cmath>

namespace hazmap {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace

Pipeline::Pipeline(const Config& config, const StereoCalibration& calibration)
    : config_(config),
      front_(config.stereo, config.sensor, calibration, /*keep_pixels=*/false),
      map_(config.map, config.rules, config.hazard, config.pose_uncertainty.enabled),
      weighting_(ccm_weighting(config.rules.ccm)),
      layer_map_ms_(config.map.layers.size(), 0.0),
      layer_gates_(config.map.layers.size()),
      hazards_(resolve_hazard_params(config), config.hazard.incremental) {}

FrameReport Pipeline::process(const cv::Mat& left, const cv::Mat& right, const Pose3d& T_W_B,
                              const PoseNoise& noise) {
  FrameReport report;
  const StereoTimes stereo = front_.process(left, right, T_W_B);
  report.ms.rectify_ms = stereo.grey_ms + stereo.rectify_ms;
  report.ms.disparity_ms = stereo.disparity_ms;
  auto t = Clock::now();
  points_.assign(front_.cloud(), weighting_);
  report.points = front_.cloud().size();
  report.points_below_ground = front_.points_below_ground();
  report.disparities_unsupported = front_.disparities_unsupported();
  report.ms.points_ms = stereo.points_ms + ms_since(t);

  t = Clock::now();
  const Eigen::Vector3d robot = T_W_B.translation();
  map_.begin_frame(robot.x(), robot.y(), noise);
  report.updates = map_.insert(points_, layer_map_ms_.data());
  report.ms.map_ms = ms_since(t);
  for (size_t i = 0; i < map_.size(); ++i) {
    layer_gates_[i] = map_.gate_counts(i);
    report.gated += layer_gates_[i];
  }

  t = Clock::now();
  hazards_.run(map_);
  report.ms.hazard_ms = ms_since(t);
  return report;
}

}  // namespace hazmap
