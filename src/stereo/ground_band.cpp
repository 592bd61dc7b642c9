#include "hazmap/stereo/ground_band.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kDegToRad = M_PI / 180.0;

/// The depths Z > 0 with Z k <= c: [near, far] (far may be infinite); false if none.
bool depths_where(double k, double c, double& near, double& far) {
  if (k > 0) {
    if (c <= 0) return false;
    near = 0.0;
    far = c / k;
  } else if (k < 0) {
    near = c >= 0 ? 0.0 : c / k;
    far = kInf;
  } else {
    if (c < 0) return false;
    near = 0.0;
    far = kInf;
  }
  return true;
}

}  // namespace

void DisparityInterval::include(const DisparityInterval& other) {
  if (other.empty()) return;
  if (empty()) {
    *this = other;
    return;
  }
  lo = std::min(lo, other.lo);
  hi = std::max(hi, other.hi);
}

TerrainEnvelope TerrainEnvelope::from(const StereoConfig& stereo) {
  TerrainEnvelope e;
  e.max_slope_deg = stereo.band_max_slope_deg;
  e.max_height_m = stereo.band_max_height_m;
  e.max_depth_m = stereo.band_max_depth_m;
  return e;
}

GroundBand::GroundBand(const StereoGeometry& geometry, const Pose3d& T_B_Cr,
                       const TerrainEnvelope& envelope, double max_disparity_px)
    : geometry_(geometry),
      envelope_(envelope),
      R_B_Cr_(T_B_Cr.linear()),
      camera_height_m_(T_B_Cr.translation().z()),
      max_disparity_(max_disparity_px) {
  check(geometry.focal_px > 0 && geometry.baseline_m > 0,
        "ground band: focal length and baseline must be positive");
  check(max_disparity_px > 0, "ground band: the disparity cap must be positive");
  check(envelope.max_slope_deg >= 0 && envelope.max_slope_deg < 90,
        "ground band: slope must be in [0, 90) deg");
  check(envelope.max_height_m >= 0 && envelope.max_depth_m >= 0,
        "ground band: height and depth must be >= 0");
  tan_slope_ = std::tan(envelope.max_slope_deg * kDegToRad);
}

DisparityInterval GroundBand::pixel(double u, double v) const {
  const double f = geometry_.focal_px;
  const Eigen::Vector3d r =
      R_B_Cr_ * Eigen::Vector3d((u - geometry_.cx_px) / f, (v - geometry_.cy_px) / f, 1.0);
  // Along p(Z) = c + Z r: height z = h + Z b, horizontal distance rho = Z a.
  const double a = std::hypot(r.x(), r.y()), b = r.z(), h = camera_height_m_;
  // z <= max_height + tan(slope) rho   <=>  Z (b - tan a) <= max_height - h
  // z >= -max_depth - tan(slope) rho   <=>  Z (-b - tan a) <= max_depth + h
  double near_up = 0, far_up = 0, near_down = 0, far_down = 0;
  if (!depths_where(b - tan_slope_ * a, envelope_.max_height_m - h, near_up, far_up) ||
      !depths_where(-b - tan_slope_ * a, envelope_.max_depth_m + h, near_down, far_down))
    return {};
  double near = std::max(near_up, near_down);
  const double far = std::min(far_up, far_down);
  // Level ground alone (no slope, height or depth) leaves a single depth, computed
  // twice: let rounding not empty it.
  constexpr double kRoundoff = 1e-12;
  if (near > far * (1 + kRoundoff)) return {};
  near = std::min(near, far);
  const double fb = f * geometry_.baseline_m;
  DisparityInterval d;
  d.lo = far == kInf ? 0.0 : fb / far;
  d.hi = near > 0 ? std::min(fb / near, max_disparity_) : max_disparity_;
  return d;  // empty if all of it lies beyond the cap (lo > hi)
}

DisparityInterval GroundBand::row(int v, int width) const {
  DisparityInterval hull;
  for (int u = 0; u < width; ++u) hull.include(pixel(u, v));
  return hull;
}

std::vector<DisparityInterval> GroundBand::rows(cv::Size size) const {
  std::vector<DisparityInterval> out(static_cast<std::size_t>(size.height));
  for (int v = 0; v < size.height; ++v) out[static_cast<std::size_t>(v)] = row(v, size.width);
  return out;
}

}  // namespace hazmap
