#pragma once
// A 3-D point in the world frame with its covariance: what the stereo front end makes
// of a pixel. The map reads it converted (map/map_points.hpp).

#include <vector>

#include <Eigen/Core>

namespace hazmap {

struct Measurement {
  Eigen::Vector3f p_W;  ///< metres, world frame
  /// Upper triangle of the world-frame covariance [m^2]: xx xy xz yy yz zz.
  float cov_xx, cov_xy, cov_xz, cov_yy, cov_yz, cov_zz;
};

/// One frame's points; the buffer is reused from frame to frame.
using PointCloud = std::vector<Measurement>;

}  // namespace hazmap
