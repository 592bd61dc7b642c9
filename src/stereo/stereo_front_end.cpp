#include "hazmap/stereo/stereo_front_end.hpp"

#include "hazmap/core/error.hpp"
#include "hazmap/core/stopwatch.hpp"

#include <chrono>

#include <spdlog/spdlog.h>

#include "hazmap/stereo/ground_band.hpp"
#include "hazmap/stereo/row_offset.hpp"

namespace hazmap {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

StereoFrontEnd::StereoFrontEnd(const StereoConfig& stereo, const SensorConfig& sensor,
                               const StereoCalibration& calibration, bool keep_pixels)
    : grey_(stereo.input_bits),
      rectifier_(calibration, stereo.rectify_alpha,
                 stereo.row_offset.value_or(0.0)),
      matcher_(stereo, rectifier_.geometry(),
               rectified_camera_in_body(calibration.T_B_C, rectifier_.R1()),
               rectifier_.image_size()),
      support_(stereo.support_rows, stereo.support_tolerance, stereo.support_margin_px),
      builder_(stereo, sensor, rectifier_.geometry(), rectifier_.R1(), calibration.T_B_C,
               rectifier_.valid_roi(), rectifier_.valid_roi_right()),
      keep_pixels_(keep_pixels),
      auto_row_offset_tries_(stereo.row_offset ? 0 : kAutoRowOffsetFrames) {
  builder_.set_search_end_by_row(matcher_.search_end_by_row(rectifier_.image_size().height));
}

StereoTimes StereoFrontEnd::process(const cv::Mat& left, const cv::Mat& right,
                                    const Pose3d& T_W_B) {
  KnownTerrain none;
  return process(left, right, T_W_B, none);
}

StereoTimes StereoFrontEnd::process(const cv::Mat& left, const cv::Mat& right,
                                    const Pose3d& T_W_B, KnownTerrain& terrain) {
  StereoTimes times;
  auto t = Clock::now();
  input_bits_ = grey_.convert(left, right, grey_left_, grey_right_);
  times.grey_ms = ms_since(t);

  t = Clock::now();
  rectifier_.rectify(grey_left_, grey_right_, rect_left_, rect_right_);
  if (auto_row_offset_tries_ > 0) measure_row_offset();
  times.rectify_ms = ms_since(t);

  t = Clock::now();
  matcher_.compute(rect_left_, rect_right_, disparity_);
  unsupported_ = support_.apply(disparity_, matcher_.invalid_below());
  times.disparity_ms = ms_since(t);

  t = Clock::now();
  last_T_W_B_ = T_W_B;
  if (!terrain.empty()) builder_.prepare_terrain(terrain, T_W_B);
  // Occluded pixels leave the disparity image (as unsupported ones do), so that it and a
  // cloud built later from it hold exactly what reached the map.
  PointDrops drops;
  if (map_points_mode_) {
    drops = builder_.build_map_points(disparity_, matcher_.invalid_below(), T_W_B, terrain,
                                      weighting_, map_points_, &disparity_);
    cloud_stale_ = true;
  } else {
    drops = builder_.build(disparity_, matcher_.invalid_below(), T_W_B, terrain, cloud_,
                           keep_pixels_ ? &pixels_ : nullptr, &disparity_);
  }
  below_ground_ = drops.below_ground;
  occluded_ = drops.occluded;
  times.points_ms = ms_since(t);
  return times;
}

void StereoFrontEnd::measure_row_offset() {
  --auto_row_offset_tries_;
  const RowOffsetEstimate e = estimate_row_offset(rect_left_, rect_right_);
  if (!e.found) {
    if (auto_row_offset_tries_ > 0)
      spdlog::info("stereo.row_offset_px auto: {} matches, {} consistent, too few; trying the "
                   "next frame", e.matches, e.inliers);
    else
      spdlog::warn("stereo.row_offset_px auto: too few feature matches in the first {} frames; "
                   "rows left as rectified (offset 0)", kAutoRowOffsetFrames);
    return;
  }
  auto_row_offset_tries_ = 0;
  spdlog::info("stereo.row_offset_px auto: {:+.2f} px (spread {:.2f} px, {} of {} matches)",
               e.offset_px, e.spread_px, e.inliers, e.matches);
  rectifier_.set_row_offset(e.offset_px);
  builder_.set_valid_roi_right(rectifier_.valid_roi_right());
  rectifier_.rectify(grey_left_, grey_right_, rect_left_, rect_right_);
}

void StereoFrontEnd::set_map_points_output(CcmWeighting weighting) {
  if (!builder_.supports_map_points())
    throw Error("stereo front end: map-points output needs sensor.model axis");
  map_points_mode_ = true;
  weighting_ = weighting;
}

const PointCloud& StereoFrontEnd::cloud() const {
  if (cloud_stale_) {
    builder_.build(disparity_, matcher_.invalid_below(), last_T_W_B_, cloud_);
    cloud_stale_ = false;
  }
  return cloud_;
}

}  // namespace hazmap
