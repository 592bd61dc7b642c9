#pragma once
// The ground a frame's points lie on, as one plane: what `hazmap check` reports (camera
// height, tilt in W and in the body frame) and what `hazmap run` compares with
// hazard.max_slope_deg to catch a wrong pose or calibration convention (a tilted map).
//
// RANSAC over a deterministic, evenly strided subset of the points: each hypothesis is the
// plane through three of them, its inliers the points within k_sigma of their own standard
// deviation along the plane's normal (stereo error grows as Z^2, so one metric threshold
// would be too tight far away or too loose near by); the best hypothesis is refined by a
// weighted total-least-squares fit to its inliers (weights 1/sigma_n^2), repeated
// until the normal settles.
// Deterministic: the same points give the same plane.
// Thread safety: a free function of its arguments.

#include <cstddef>

#include <Eigen/Core>

#include "hazmap/map/measurement.hpp"

namespace hazmap {

struct GroundPlaneOptions {
  std::size_t max_points = 20000;  ///< subset size the hypotheses are scored on
  int iterations = 300;           ///< RANSAC hypotheses
  double k_sigma = 3.0;           ///< inlier: |n.(p - p0)| <= k_sigma sigma_n
  /// A metre floor under sigma_n, so that points whose claimed sigma is tiny (near the
  /// cameras) do not reject a plane for sub-millimetre texture. 5 mm: well under the
  /// obstacles that matter (SPEC 8's 2.2 cm h_min on the 1 cm layer).
  double min_sigma_m = 0.005;
  int max_refinements = 20;       ///< weighted refits of the inliers, at most
  double converged_rad = 1e-5;    ///< ... until the normal moves less than this
  /// A plane needs at least this share of the subset as inliers to count as found...
  double min_inlier_share = 0.2;
  /// ... and this many inliers: a few dozen far points with decimetre sigmas fit any
  /// plane (measured: 28 points at 10 m gave a "ground" tilted 56 deg).
  std::size_t min_inliers = 200;
};

struct GroundPlane {
  bool found = false;
  /// Unit normal, oriented towards `viewpoint` (the side the cameras saw it from).
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< the inliers' weighted centroid
  double inlier_share = 0.0;  ///< of the scored subset
  std::size_t points_used = 0;  ///< size of the scored subset

  /// Signed distance of `p` from the plane, positive on the normal's side.
  double height_of(const Eigen::Vector3d& p) const { return normal.dot(p - point); }
  /// Angle between the normal and `up` (unit), degrees: the plane's tilt against the
  /// horizontal of the frame whose z axis `up` is.
  double tilt_deg(const Eigen::Vector3d& up) const;
};

/// Fits the dominant plane of `cloud` (any frame; `viewpoint` in the same frame, e.g. the
/// camera centre, orients the normal). Not found when the cloud has fewer than three
/// points or no plane reaches min_inlier_share.
GroundPlane fit_ground_plane(const PointCloud& cloud, const Eigen::Vector3d& viewpoint,
                             const GroundPlaneOptions& options = {});

}  // namespace hazmap
