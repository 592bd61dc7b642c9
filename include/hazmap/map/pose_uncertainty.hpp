#pragma once
// Lazy pose-uncertainty propagation (SPEC 7). Instead of re-projecting the map when the
// pose estimate drifts, keep running sums of the pose noise added per frame; a cell
// updated at frame f has since accumulated sums(now) - sums(f). At query time that
// inflates its height variance by g^T Sigma_lat g + Sigma_zz, with g the local gradient
// and Sigma_lat = Sigma_xy + syaw^2 [-o_y, o_x]^T [-o_y, o_x] (o = cell - robot).
// O(1) per queried cell; it changes reported variance only.

#include <cstdint>
#include <vector>

#include "hazmap/core/types.hpp"

namespace hazmap {

class PoseUncertainty {
 public:
  /// Reserves history for `expected_frames` frames (more is allowed, then it grows).
  explicit PoseUncertainty(std::size_t expected_frames = 1 << 16);

  /// Adds the noise of frame `frame` (frames numbered 0, 1, ... consecutively).
  void add_frame(std::uint32_t frame, const PoseNoise& noise);

  /// Variance added to a cell last updated at `updated_frame`, seen from the current
  /// frame, at offset (ox, oy) [m] from the robot, with local gradient (gx, gy).
  double added_variance(std::uint32_t updated_frame, double ox_m, double oy_m, double gx,
                        double gy) const;

 private:
  struct Sums {
    double xx = 0, yy = 0, zz = 0, yaw = 0;
  };
  std::vector<Sums> cumulative_;  ///< cumulative_[f]: noise variance summed over frames 0..f
};

}  // namespace hazmap
