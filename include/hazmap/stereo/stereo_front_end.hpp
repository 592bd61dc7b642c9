#pragma once
// The stereo front end of SPEC 3-4 in one object: grey conversion -> rectification
// (maps built once) -> disparity -> world-frame points with covariance. Every buffer
// lives here and is reused from frame to frame; after the first frame of a given size
// the path allocates nothing but what OpenCV's matchers allocate internally.
// Not thread-safe: one front end per thread (matching itself uses OpenCV's pool).

#include <vector>

#include <opencv2/core.hpp>

#include "hazmap/camera/grey_pair.hpp"
#include "hazmap/camera/rectifier.hpp"
#include "hazmap/camera/stereo_calibration.hpp"
#include "hazmap/stereo/disparity.hpp"
#include "hazmap/stereo/point_cloud_builder.hpp"
#include "hazmap/stereo/stereo_config.hpp"
#include "hazmap/stereo/support_check.hpp"

namespace hazmap {

/// Wall time of each stage of one frame, milliseconds.
struct StereoTimes {
  double grey_ms = 0;       ///< colour / 16-bit to 8-bit grey
  double rectify_ms = 0;    ///< cv::remap of both images
  double disparity_ms = 0;  ///< StereoBM / StereoSGBM
  double points_ms = 0;     ///< triangulation, covariance, transform to W
  double total() const { return grey_ms + rectify_ms + disparity_ms + points_ms; }
};

class StereoFrontEnd {
 public:
  /// Builds the rectification maps and the matcher. Throws Error on an unusable
  /// calibration or configuration.
  /// `keep_pixels`: also record each point's pixel (pixels()); the mapping pipeline
  /// does not need them and skips the work.
  StereoFrontEnd(const StereoConfig& stereo, const SensorConfig& sensor,
                 const StereoCalibration& calibration, bool keep_pixels = true);

  /// Runs one pair (8/16-bit, grey or colour, the calibrated size) taken at body pose
  /// T_W_B. Results stay valid until the next call. Throws Error on a bad image.
  StereoTimes process(const cv::Mat& left, const cv::Mat& right, const Pose3d& T_W_B);
  /// The same, dropping points seen through `terrain` (the map's published terrain in W;
  /// PointCloudBuilder::build, stereo.occlusion_*), whose tops it prepares for this pose
  /// first (PointCloudBuilder::prepare_terrain).
  StereoTimes process(const cv::Mat& left, const cv::Mat& right, const Pose3d& T_W_B,
                      KnownTerrain& terrain);

  const cv::Mat& rectified_left() const { return rect_left_; }    ///< 8-bit grey
  const cv::Mat& rectified_right() const { return rect_right_; }  ///< 8-bit grey
  /// CV_16S, x16; without the disparities the support and occlusion checks removed.
  const cv::Mat& disparity_x16() const { return disparity_; }
  /// World-frame points with covariance. After a frame in map-points mode they are
  /// built on this first call (from the kept disparity image), not by process().
  const PointCloud& cloud() const;
  /// Map-points mode (the mapping pipeline, axis model only): process() fills
  /// map_points() straight from the disparities (PointCloudBuilder::build_map_points)
  /// with `weighting`, and cloud() is built only when asked for. Throws Error for the
  /// ray model.
  void set_map_points_output(CcmWeighting weighting);
  bool map_points_output() const { return map_points_mode_; }
  const MapPoints& map_points() const { return map_points_; }
  /// Points of the last pair dropped as below ground (SPEC 3.3), not in cloud().
  std::size_t points_below_ground() const { return below_ground_; }
  /// Points of the last pair dropped as seen through known terrain, not in cloud().
  std::size_t points_occluded() const { return occluded_; }
  /// Disparities of the last pair removed as unsupported (support_check.hpp).
  std::size_t disparities_unsupported() const { return unsupported_; }
  /// Rectified left pixel of each point of cloud().
  const std::vector<cv::Point>& pixels() const { return pixels_; }
  /// Significant bits the last pair was scaled from (8 for 8-bit input).
  int input_bits() const { return input_bits_; }

  const Rectifier& rectifier() const { return rectifier_; }
  const DisparityMatcher& matcher() const { return matcher_; }
  const PointCloudBuilder& builder() const { return builder_; }

 private:
  /// stereo.row_offset_px `auto`: frames tried for a row-offset estimate before giving up.
  static constexpr int kAutoRowOffsetFrames = 5;
  /// Estimates the rectified pair's row offset and, if found, rebuilds the right map with it
  /// and rectifies the pair again (stereo.row_offset_px `auto`, first frames only).
  void measure_row_offset();

  GreyPairConverter grey_;
  Rectifier rectifier_;
  DisparityMatcher matcher_;
  SupportCheck support_;
  PointCloudBuilder builder_;
  cv::Mat grey_left_, grey_right_, rect_left_, rect_right_, disparity_;
  // Built lazily in map-points mode (cloud() is const to its callers).
  mutable PointCloud cloud_;
  mutable bool cloud_stale_ = false;
  Pose3d last_T_W_B_ = Pose3d::Identity();
  MapPoints map_points_;
  bool map_points_mode_ = false;
  CcmWeighting weighting_ = CcmWeighting::constant;
  std::vector<cv::Point> pixels_;
  int input_bits_ = 8;
  std::size_t below_ground_ = 0;
  std::size_t occluded_ = 0;
  std::size_t unsupported_ = 0;
  bool keep_pixels_ = true;
  int auto_row_offset_tries_ = 0;  ///< frames left to try, 0 once measured (or not auto)
};

}  // namespace hazmap
