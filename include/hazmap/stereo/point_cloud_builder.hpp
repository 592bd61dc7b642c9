#pragma once
// Disparity image -> world-frame points with covariance (SPEC 3.3, 4).
// p_W = T_W_B * T_B_C * R1^T * p_C', Sigma_W = R_W_C' Sigma_C' R_W_C'^T, with C' the
// rectified left camera. Applying R1^T is what keeps the map level: the rectified frame
// is rotated against the real camera by up to half the angle between the two cameras.
// A pixel gives a point when its disparity is valid, it lies on the stride grid, inside
// the left camera's valid rectified region and the configured `stereo.roi`, its match
// u - d lies in the right camera's valid region, z_min <= Z <= z_max, and it lies no
// more than stereo.max_below_ground below the body's wheel plane z_B = 0 (SPEC 3.3: such
// a point is a mismatch; these are counted), nor more than below_ground_tolerance below
// it along a ray descending steeper than max_depression_slope_deg (counted with them).
// Thread safety: build() is const and may run concurrently on different clouds.

#include <vector>

#include <opencv2/core.hpp>

#include "hazmap/core/types.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/map/map_points.hpp"
#include "hazmap/map/measurement.hpp"
#include "hazmap/stereo/sensor_model.hpp"

namespace hazmap {

class PointCloudBuilder {
 public:
  /// `valid_roi`: the part of the rectified left image with valid source pixels; pixels
  /// outside produce no points. `T_B_C`: pose of the (unrectified) left camera in the
  /// body frame; `R1`: p_C' = R1 p_C (identity for rectified input).
  PointCloudBuilder(const StereoConfig& stereo, const SensorConfig& sensor,
                    const StereoGeometry& geometry, const Eigen::Matrix3d& R1,
                    const Pose3d& T_B_C, const cv::Rect& valid_roi);

  /// As above, also dropping pixels whose match u - d falls outside the rectified right
  /// image's valid region `valid_roi_right`.
  PointCloudBuilder(const StereoConfig& stereo, const SensorConfig& sensor,
                    const StereoGeometry& geometry, const Eigen::Matrix3d& R1,
                    const Pose3d& T_B_C, const cv::Rect& valid_roi,
                    const cv::Rect& valid_roi_right);

  /// Fills `cloud` (cleared first; its capacity is reused) from a fixed-point disparity
  /// image (CV_16S, x16). Keeps z_min <= Z <= z_max, every stride-th pixel. Fields
  /// beyond p_W and the covariance are left for the map to fill. Returns the number of
  /// points dropped as below ground (SPEC 3.3).
  std::size_t build(const cv::Mat& disparity_x16, int invalid_below_x16, const Pose3d& T_W_B,
                    PointCloud& cloud) const;

  /// As above, and `pixels[i]` is the rectified left pixel (u, v) of cloud[i].
  std::size_t build(const cv::Mat& disparity_x16, int invalid_below_x16, const Pose3d& T_W_B,
                    PointCloud& cloud, std::vector<cv::Point>& pixels) const;

  /// The points stage straight into the map's input (issue 20): the same pixels, gates and
  /// below-ground count as build(), but only the fields the map reads (position, vertical
  /// and major lateral variance, the CCM weight), in float, with every per-row term
  /// hoisted out of the pixel loop. The axis model only (supports_map_points()): its
  /// covariance a I + (b - a) c c^T has closed forms for all of them (c the optical axis
  /// in W: var_z = a + (b - a) c_z^2, lateral = a + max(b - a, 0)(c_x^2 + c_y^2), trace
  /// 2a + b, det a^2 b). Throws Error for the ray model. Returns the below-ground count.
  std::size_t build_map_points(const cv::Mat& disparity_x16, int invalid_below_x16,
                               const Pose3d& T_W_B, CcmWeighting weighting, MapPoints& out) const;
  bool supports_map_points() const { return model_ == SensorModel::axis; }

  /// Pose of the rectified left camera in the world: T_W_B * T_B_C * R1^T.
  Pose3d rectified_camera_pose(const Pose3d& T_W_B) const;

  /// The pixels that may give points: valid region & `stereo.roi` (rectified left image).
  cv::Rect region() const { return roi_; }

 private:
  std::size_t build_impl(const cv::Mat& disparity_x16, int invalid_below_x16, const Pose3d& T_W_B,
                         PointCloud& cloud, std::vector<cv::Point>* pixels) const;

  StereoConfig stereo_;
  SensorConfig sensor_;
  SensorModel model_;
  StereoGeometry geometry_;
  Pose3d T_B_Cr_;  ///< body <- rectified left camera
  cv::Rect roi_;
  cv::Rect roi_right_;  ///< empty: no restriction
};

}  // namespace hazmap
