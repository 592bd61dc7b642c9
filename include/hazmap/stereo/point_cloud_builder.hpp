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
// Given the terrain the map already knows, a point is also dropped (counted apart) when
// its ray passes through that terrain on the way to it, or, nearer than the disparity
// search reaches, below the unseen continuation of it (stereo.occlusion_reach, _margin,
// _fill; ray_blocked): the pixel sees that terrain, so its disparity belongs to something
// else. Measured on a drive over a 10 cm rock, 15 cm cameras, 0.4 scale, 160 disparities
// (nothing nearer than 8.4 cm can be matched): the rock top 7 cm from the camera (true
// disparity 187 px) matched at ~100 px, points 13 cm below the rock top, beyond it along
// steep rays, which the depth and steep-ray checks let through (at most 5 cm below the
// wheel plane).
// Thread safety: build() is const and may run concurrently on different clouds.

#include <vector>

#include <opencv2/core.hpp>

#include "hazmap/core/types.hpp"
#include "hazmap/map/known_terrain.hpp"
#include "hazmap/map/map_points.hpp"
#include "hazmap/map/measurement.hpp"
#include "hazmap/stereo/sensor_model.hpp"
#include "hazmap/stereo/stereo_config.hpp"

namespace hazmap {

/// One pixel's ray against the known terrain (stereo.occlusion_*; ours, with SPEC 3.3's
/// impossible points): the ray is camera_W + z ray_W, ray_W its W offset per metre of
/// depth along the optical axis, sampled every `sample_m` of its length at depths
/// z < depth_m (the point's depth, or less). It is blocked when a sample lies
///  - more than margin_m + 3 sigma below known terrain (KnownTerrain::height_at): the pixel
///    sees that terrain, not a point behind it;
///  - in the near field, z < near_m (surfaces nearer than the disparity search reaches),
///    below the assumed height of an unseen cell next to seen ones
///    (KnownTerrain::unseen_height_at): the pixel may see the unseen continuation of a
///    surface, which it cannot match.
/// Terrain nobody knows, away from what is known, blocks nothing. `known_level_m` must
/// bound height - margin - 3 sigma over the samples (KnownTerrain::max_top - margin),
/// `unseen_level_m` the assumed heights (KnownTerrain::max_unseen_height): stretches of
/// the ray above them are not sampled.
struct RayCheck {
  double near_m = 0.0;
  double depth_m = 0.0;
  double margin_m = 0.0;
  double sample_m = 0.0;
  double known_level_m = 0.0;
  double unseen_level_m = 0.0;
};
bool ray_blocked(const KnownTerrain& terrain, const Eigen::Vector3d& camera_W,
                 const Eigen::Vector3d& ray_W, const RayCheck& check);

/// What build() dropped, by reason (none of it is in the cloud).
struct PointDrops {
  std::size_t below_ground = 0;  ///< SPEC 3.3: below the wheel plane (depth, steep rays)
  std::size_t occluded = 0;      ///< seen through known terrain (stereo.occlusion_*)
};

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
  /// image (CV_16S, x16): every stride-th pixel of the valid region whose disparity is
  /// above `invalid_below_x16` and gives a depth z_min <= Z <= z_max (and, with a right
  /// region, a match inside it) becomes p_W with its covariance (sensor.model), unless it
  /// lies below ground. Returns the number of points dropped as below ground (SPEC 3.3).
  std::size_t build(const cv::Mat& disparity_x16, int invalid_below_x16, const Pose3d& T_W_B,
                    PointCloud& cloud) const;

  /// As above, and `pixels[i]` is the rectified left pixel (u, v) of cloud[i].
  std::size_t build(const cv::Mat& disparity_x16, int invalid_below_x16, const Pose3d& T_W_B,
                    PointCloud& cloud, std::vector<cv::Point>& pixels) const;

  /// As above with the occlusion check against `terrain` (in W, the frame of T_W_B;
  /// prepared by prepare_terrain for this pose): a point whose ray is blocked
  /// (ray_blocked) nearer than both the point and stereo.occlusion_reach x the row's
  /// near-field depth f B / search end (set_search_end_by_row), with margin
  /// stereo.occlusion_margin, is dropped and counted in `occluded`. The ray is sampled
  /// every finest terrain cell along its length. A terrain without prepared tops, or
  /// occlusion_reach 0, checks nothing. `pixels` may be null. `mark_occluded`, when given
  /// (the disparity image itself, or one of its size), gets invalid_below_x16 at every
  /// occluded pixel, so that a later build() without the terrain gives the same points.
  PointDrops build(const cv::Mat& disparity_x16, int invalid_below_x16, const Pose3d& T_W_B,
                   const KnownTerrain& terrain, PointCloud& cloud,
                   std::vector<cv::Point>* pixels = nullptr,
                   cv::Mat* mark_occluded = nullptr) const;

  /// The disparities searched per rectified row end below `end_px[v]` (exclusive;
  /// DisparityMatcher::search_end_by_row): surfaces nearer than f B / end, the row's near
  /// field, cannot be matched there. Until called, every row ends at
  /// stereo.min_disparity + num_disparities (a full search); rows beyond `end_px` too.
  void set_search_end_by_row(const std::vector<int>& end_px);
  /// The rectified right image's valid region changed (a row offset measured later).
  void set_valid_roi_right(const cv::Rect& valid_roi_right) { roi_right_ = valid_roi_right; }

  /// Row v's near-field depth f B / search end [m] (0 where nothing is searched).
  double near_depth_m(int v) const {
    return v >= 0 && static_cast<std::size_t>(v) < near_by_row_.size()
               ? near_by_row_[static_cast<std::size_t>(v)]
               : default_near_m_;
  }
  /// Depth [m] along the optical axis out to which row v's rays are checked against the
  /// terrain: stereo.occlusion_reach x its near-field depth.
  double occlusion_depth_m(int v) const { return stereo_.occlusion_reach * near_depth_m(v); }

  /// Prepares `terrain` (KnownTerrain::prepare_near_field) for a pair taken at T_W_B: over
  /// the view frustum cut at the deepest occlusion_depth_m (every stretch a ray is checked
  /// on), with stereo.occlusion_fill and 3 sigma. Call before build() with that terrain.
  void prepare_terrain(KnownTerrain& terrain, const Pose3d& T_W_B) const;

  /// The points stage straight into the map's input (issue 20): the same pixels, gates and
  /// below-ground count as build(), but only the fields the map reads (position, vertical
  /// and major lateral variance, the CCM weight), in float, with every per-row term
  /// hoisted out of the pixel loop. The axis model only (supports_map_points()): its
  /// covariance a I + (b - a) c c^T has closed forms for all of them (c the optical axis
  /// in W: var_z = a + (b - a) c_z^2, lateral = a + max(b - a, 0)(c_x^2 + c_y^2), trace
  /// 2a + b, det a^2 b). Throws Error for the ray model. Returns the below-ground count.
  std::size_t build_map_points(const cv::Mat& disparity_x16, int invalid_below_x16,
                               const Pose3d& T_W_B, CcmWeighting weighting, MapPoints& out) const;
  /// As above with the occlusion check of build() against `terrain` (same rule, the
  /// ray in float), and `mark_occluded` as there.
  PointDrops build_map_points(const cv::Mat& disparity_x16, int invalid_below_x16,
                              const Pose3d& T_W_B, const KnownTerrain& terrain,
                              CcmWeighting weighting, MapPoints& out,
                              cv::Mat* mark_occluded = nullptr) const;
  bool supports_map_points() const { return model_ == SensorModel::axis; }

  /// Pose of the rectified left camera in the world: T_W_B * T_B_C * R1^T.
  Pose3d rectified_camera_pose(const Pose3d& T_W_B) const;

  /// The pixels that may give points: valid region & `stereo.roi` (rectified left image).
  cv::Rect region() const { return roi_; }

 private:
  PointDrops build_impl(const cv::Mat& disparity_x16, int invalid_below_x16, const Pose3d& T_W_B,
                        const KnownTerrain* terrain, PointCloud& cloud,
                        std::vector<cv::Point>* pixels, cv::Mat* mark_occluded) const;
  PointDrops map_points_impl(const cv::Mat& disparity_x16, int invalid_below_x16,
                             const Pose3d& T_W_B, const KnownTerrain* terrain,
                             CcmWeighting weighting, MapPoints& out,
                             cv::Mat* mark_occluded) const;
  struct PixelGates;
  struct OcclusionGate;
  /// The per-call gates both paths apply, so that they cannot drift apart.
  PixelGates pixel_gates(const cv::Mat& disparity_x16) const;
  /// `R`: the rectified camera's rotation into W this frame; `width`: the image's.
  OcclusionGate occlusion_gate(const KnownTerrain* terrain, const Eigen::Matrix3d& R,
                               int width) const;
  double near_depth_for(int search_end_px) const;

  StereoConfig stereo_;
  SensorConfig sensor_;
  SensorModel model_;
  StereoGeometry geometry_;
  Pose3d T_B_Cr_;  ///< body <- rectified left camera
  cv::Rect roi_;
  cv::Rect roi_right_;  ///< empty: no restriction
  double default_near_m_ = 0.0;      ///< near-field depth of a full search's rows
  std::vector<double> near_by_row_;  ///< per row, from set_search_end_by_row
};

}  // namespace hazmap
