#include "hazmap/map/pose_uncertainty.hpp"

#include "hazmap/core/error.hpp"

namespace hazmap {

PoseUncertainty::PoseUncertainty(std::size_t expected_frames) {
  cumulative_.reserve(expected_frames);
}

void PoseUncertainty::add_frame(std::uint32_t frame, const PoseNoise& n) {
  check(frame == cumulative_.size(), "pose uncertainty: frames must be added in order");
  Sums s = cumulative_.empty() ? Sums{} : cumulative_.back();
  s.xx += n.sx_m * n.sx_m;
  s.yy += n.sy_m * n.sy_m;
  s.zz += n.sz_m * n.sz_m;
  s.yaw += n.syaw_rad * n.syaw_rad;
  cumulative_.push_back(s);
}

double PoseUncertainty::added_variance(std::uint32_t updated_frame, double ox_m, double oy_m,
                                       double gx, double gy) const {
  if (cumulative_.empty() || updated_frame >= cumulative_.size()) return 0.0;
  const Sums& now = cumulative_.back();
  const Sums& then = cumulative_[updated_frame];
  const double xx = now.xx - then.xx, yy = now.yy - then.yy, zz = now.zz - then.zz;
  const double yaw = now.yaw - then.yaw;
  // Sigma_lat = diag(xx, yy) + yaw [-oy, ox]^T [-oy, ox]
  const double lx = -oy_m, ly = ox_m;
  const double g_dot_l = gx * lx + gy * ly;
  return gx * gx * xx + gy * gy * yy + yaw * g_dot_l * g_dot_l + zz;
}

}  // namespace hazmap
