#include "hazmap/pipeline/pipeline.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "hazmap/core/error.hpp"
#include "hazmap/core/stopwatch.hpp"
#include "hazmap/pipeline/thread_pool.hpp"
#include "hazmap/rules/rule_registry.hpp"
#include "hazmap/stereo/sensor_model.hpp"

namespace hazmap {
namespace {

using Clock = std::chrono::steady_clock;

/// Bytes a map cell costs in all of a layer's grids, measured as the growth of peak memory
/// from size 512 to 1024 (hazmap run, one layer): 117 for kalman, 265 for ccm. The grids
/// follow the rule's kHasPlane: a plane rule exports the plane grids, the others the same
/// piecewise-constant grids as kalman.
double bytes_per_cell(RuleKind rule) { return rule_info(rule).has_plane ? 270.0 : 120.0; }

/// The map is allocated once, up front (SPEC 5), sized by the config: a stack that
/// cannot fit in this machine's memory is reported here, by key, instead of as
/// std::bad_alloc or the out-of-memory killer half-way through.
const Config& check_map_fits_memory(const Config& config) {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return config;  // unknown: nothing to compare with
  const double memory = static_cast<double>(pages) * static_cast<double>(page);
  double need = 0;
  std::string cells;
  for (size_t i = 0; i < config.map.layers.size(); ++i) {
    const LayerConfig& l = config.map.layers[i];
    const double n = static_cast<double>(l.size);
    need += n * n * bytes_per_cell(l.rule);
    cells += (i ? ", " : "") + std::string("layer ") + std::to_string(i) + ": " +
             std::to_string(l.size) + "^2";
  }
  if (need > memory) {
    char text[160];
    std::snprintf(text, sizeof text, " cells need about %.1f GB, more than this machine's %.1f GB of memory",
                  need / 1e9, memory / 1e9);
    throw Error("config: key 'map.layers': " + cells + text);
  }
  return config;
}

}  // namespace

Pipeline::Pipeline(const Config& config, const StereoCalibration& calibration)
    : config_(check_map_fits_memory(config)),
      front_(config.stereo, config.sensor, calibration, /*keep_pixels=*/false),
      mapper_(config, config.pose_uncertainty.enabled) {
  mapper_.set_parallel(&opencv_parallel_for());  // the stereo stages' pool, idle by then
  // The axis model's covariance has closed forms for all the map reads: skip the cloud.
  if (config.sensor.model == SensorModel::axis) front_.set_map_points_output(mapper_.weighting());
  const Rectifier& rect = front_.rectifier();
  view_.T_B_C = rectified_camera_in_body(calibration.T_B_C, rect.R1());
  view_.focal_px = rect.geometry().focal_px;
  view_.cx_px = rect.geometry().cx_px;
  view_.cy_px = rect.geometry().cy_px;
  view_.width_px = rect.image_size().width;
  view_.height_px = rect.image_size().height;
  // No disparity within half a matching window of the border, nor in the band OpenCV
  // leaves blank on the left when it is not matched (stereo.match_left_border).
  view_.edge_margin_px = (config.stereo.block_size + 1) / 2;
  view_.blank_left_px = blank_left_columns(config.stereo);
  // Nor where the match falls within half a window of the right image's left border (no
  // matcher compares a whole window there), or within the band bm and sgbm drop.
  view_.right_edge_margin_px =
      std::max<double>(view_.edge_margin_px, right_border_drop_px(config.stereo));
  view_.z_min_m = config.stereo.z_min_m;
  view_.z_max_m = config.stereo.z_max_m;
  view_.band_below_m = config.stereo.band_max_depth_m;
  view_.band_above_m = config.stereo.band_max_height_m;
  view_.baseline_m = rect.geometry().baseline_m;
  view_.stride = config.stereo.stride;
  // Where each layer's lateral gate ends, for the body level: the depth at which a point
  // at the image centre gets the gate's lateral sigma in W (the sensor model's, as the
  // map reads it: the largest eigenvalue of its xy covariance).
  const StereoGeometry& geometry = rect.geometry();
  const Eigen::Matrix3d R = view_.T_B_C.linear();
  const auto lateral_std = [&](double z) {
    const Eigen::Matrix3d C =
        config.sensor.model == SensorModel::ray
            ? covariance_ray(geometry, geometry.cx_px, geometry.cy_px, geometry.focal_px * geometry.baseline_m / z,
                             config.sensor.pointing_error_px, config.sensor.disparity_error_px)
            : covariance_axis(geometry, z, config.sensor.pointing_error_px, config.sensor.disparity_error_px);
    const Eigen::Matrix3d W = R * C * R.transpose();
    return std::sqrt(major_lateral_variance(W(0, 0), W(1, 1), W(0, 1)));
  };
  for (const LayerConfig& layer : config.map.layers) {
    const double gate = gate_std_m(layer, config.rules);
    double lo = config.stereo.z_min_m, hi = config.stereo.z_max_m;
    if (gate > 0 && lateral_std(hi) > gate) {
      for (int k = 0; k < 60; ++k) (lateral_std(0.5 * (lo + hi)) > gate ? hi : lo) = 0.5 * (lo + hi);
    }
    view_.layer_depth_limit_m.push_back(gate > 0 ? hi : 0.0);
  }
}

FrameReport Pipeline::process(const cv::Mat& left, const cv::Mat& right, const Pose3d& T_W_B,
                              const PoseNoise& noise) {
  FrameReport report;
  const StereoTimes stereo = front_.process(left, right, T_W_B, mapper_.known_terrain());
  report.ms.rectify_ms = stereo.grey_ms + stereo.rectify_ms;
  report.ms.disparity_ms = stereo.disparity_ms;
  auto t = Clock::now();
  // The axis model's points go straight from the disparities into the map's arrays
  // (front_.map_points()); the ray model goes through the cloud.
  const MapPoints& points =
      front_.map_points_output() ? front_.map_points() : mapper_.assign_points(front_.cloud());
  report.points = static_cast<std::size_t>(points.size());
  report.points_below_ground = front_.points_below_ground();
  report.points_occluded = front_.points_occluded();
  report.disparities_unsupported = front_.disparities_unsupported();
  report.ms.points_ms = stereo.points_ms + ms_since(t);

  t = Clock::now();
  const Eigen::Vector3d robot = T_W_B.translation();
  report.updates = mapper_.insert(points, robot.x(), robot.y(), noise);
  report.ms.map_ms = ms_since(t);
  report.gated = mapper_.gated();

  t = Clock::now();
  view_.T_W_B = T_W_B;
  // The disparity image as it reached the map (occluded pixels marked invalid), for the
  // hole-free test; the region may change with a row offset measured later.
  const cv::Mat& disparity = front_.disparity_x16();
  const cv::Rect region = front_.builder().region();
  view_.disparity_x16 = disparity.empty() ? nullptr : disparity.ptr<std::int16_t>(0);
  view_.disparity_stride = static_cast<int>(disparity.step1());
  view_.invalid_below_x16 = front_.matcher().invalid_below();
  view_.roi_x0 = region.x;
  view_.roi_y0 = region.y;
  view_.roi_x1 = region.x + region.width;
  view_.roi_y1 = region.y + region.height;
  mapper_.classify(&view_);
  report.ms.hazard_ms = ms_since(t);
  return report;
}

}  // namespace hazmap
