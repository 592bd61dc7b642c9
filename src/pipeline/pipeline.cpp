#include "hazmap/pipeline/pipeline.hpp"

#include <chrono>
#include <cmath>

#include "hazmap/hazard/fused_hazard.hpp"

namespace hazmap {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace

RoughnessParams roughness_params(const LayerConfig& layer, const HazardConfig& hazard) {
  RoughnessParams p;
  p.kernel = layer.hazard.kernel;
  p.min_fill = hazard.min_kernel_fill;
  p.threshold_m = layer.hazard.roughness_threshold_m >= 0
                      ? layer.hazard.roughness_threshold_m
                      : (p.kernel - 1) * layer.resolution_m *
                            std::tan(hazard.max_slope_deg * M_PI / 180.0);
  return p;
}

CcmHazardParams ccm_params(const LayerConfig& layer, const HazardConfig& hazard) {
  const double h_min = layer.hazard.h_min_m > 0 ? layer.hazard.h_min_m : 0.75 * layer.resolution_m;
  return ccm_hazard_params(layer.resolution_m, h_min, layer.hazard.rho_max_m2,
                           hazard.max_slope_deg, hazard.wheelbase_m);
}

void classify_layer(bool has_plane, const RoughnessParams& roughness, const CcmHazardParams& ccm,
                    RoughnessFilter& filter, LayerView& view) {
  if (has_plane) {
    classify_ccm(view.map, ccm, view.hazard);
    return;
  }
  filter.compute(view.map.height, roughness.kernel, view.kernel_range, view.kernel_fill);
  classify_roughness(view.map.height, view.kernel_range, view.kernel_fill, roughness, view.hazard);
}

Pipeline::Pipeline(const Config& config, const StereoCalibration& calibration)
    : config_(config),
      front_(config.stereo, config.sensor, calibration, /*keep_pixels=*/false),
      map_(config.map, config.rules, config.hazard, config.pose_uncertainty.enabled),
      weighting_(ccm_weighting(config.rules.ccm)),
      layer_map_ms_(config.map.layers.size(), 0.0),
      layer_gates_(config.map.layers.size()),
      views_(config.map.layers.size()) {
  for (const auto& layer : config.map.layers) {
    roughness_params_.push_back(roughness_params(layer, config.hazard));
    ccm_params_.push_back(ccm_params(layer, config.hazard));
  }
  for (const auto& view : views_) hazard_ptrs_.push_back(&view.hazard);
}

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
  report.ms.points_ms = stereo.points_ms + ms_since(t);

  t = Clock::now();
  const Eigen::Vector3d robot = T_W_B.translation();
  map_.begin_frame(robot.x(), robot.y(), noise);
  report.updates = map_.insert(points_, layer_map_ms_.data());
  report.ms.map_ms = ms_since(t);
  for (size_t i = 0; i < map_.size(); ++i) {
    layer_gates_[i] = map_.gate_counts(i);
    report.gated.std_gate += layer_gates_[i].std_gate;
    report.gated.consistency_gate += layer_gates_[i].consistency_gate;
  }

  t = Clock::now();
  analyse_hazards();
  report.ms.hazard_ms = ms_since(t);
  return report;
}

void Pipeline::analyse_hazards() {
  for (size_t i = 0; i < map_.size(); ++i) {
    LayerView& view = views_[i];
    map_.export_layer(i, view.map);
    classify_layer(map_.layer(i).has_plane(), roughness_params_[i], ccm_params_[i], roughness_,
                   view);
  }
  fuse_hazards(hazard_ptrs_, fused_);
}

}  // namespace hazmap
