#pragma once
// Triangulation, the per-point covariance of a rectified stereo pair (SPEC 3.3, 4) and
// the CCM weight derived from it. Pure functions of their inputs; frame C' is the
// rectified left camera (x right, y down, z forward), pixels (u, v), disparity d in
// pixels.

#include <cmath>

#include <Eigen/Core>

#include "hazmap/core/error.hpp"
#include "hazmap/map/measurement.hpp"

namespace hazmap {

struct StereoGeometry {
  double focal_px = 0.0;    ///< f of the rectified pair
  double baseline_m = 0.0;  ///< B > 0
  double cx_px = 0.0;
  double cy_px = 0.0;
};

enum class SensorModel { axis, ray };

/// Z = f B / d, X = (u - cx) Z / f, Y = (v - cy) Z / f. Requires d > 0.
inline Eigen::Vector3d triangulate(const StereoGeometry& g, double u, double v, double d) {
  const double z = g.focal_px * g.baseline_m / d;
  return {(u - g.cx_px) * z / g.focal_px, (v - g.cy_px) * z / g.focal_px, z};
}

/// The thesis' model: independent lateral error p Z / f and depth error Z^2 m / (f B).
inline Eigen::Matrix3d covariance_axis(const StereoGeometry& g, double z_m, double pointing_px,
                                       double matching_px) {
  const double lateral = pointing_px * z_m / g.focal_px;
  const double depth = z_m * z_m * matching_px / (g.focal_px * g.baseline_m);
  return Eigen::Vector3d(lateral * lateral, lateral * lateral, depth * depth).asDiagonal();
}

/// First-order propagation of pixel noise (p, p) and disparity noise m through the
/// triangulation: the major axis lies along the viewing ray.
inline Eigen::Matrix3d covariance_ray(const StereoGeometry& g, double u, double v, double d,
                                      double pointing_px, double matching_px) {
  Eigen::Matrix3d J;
  J << 1.0, 0.0, -(u - g.cx_px) / d,  //
      0.0, 1.0, -(v - g.cy_px) / d,   //
      0.0, 0.0, -g.focal_px / d;
  J *= g.baseline_m / d;
  const Eigen::Vector3d noise(pointing_px * pointing_px, pointing_px * pointing_px,
                              matching_px * matching_px);
  return J * noise.asDiagonal() * J.transpose();
}

/// CCM point weight (SPEC 4, `rules.ccm.weighting`) from the world-frame covariance:
/// constant w = 1 (the thesis' final choice), trace w = 1 / trace(Sigma_W), det
/// w = 1 / det(Sigma_W) [m^-2, m^-6]. Computed in double: det Sigma_W of a near point
/// is ~1e-24 m^6, whose cubic terms underflow float. Throws Error when the covariance
/// is not positive (trace or det <= 0, e.g. pointing_error_px = 0 with `det`), since
/// such a weight would be infinite.
inline float ccm_weight(CcmWeighting weighting, const Measurement& m) {
  if (weighting == CcmWeighting::constant) return 1.0f;
  const double xx = m.cov_xx, xy = m.cov_xy, xz = m.cov_xz, yy = m.cov_yy, yz = m.cov_yz,
               zz = m.cov_zz;
  const double value = weighting == CcmWeighting::trace
                           ? xx + yy + zz
                           : xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) +
                                 xz * (xy * yz - yy * xz);
  const double w = 1.0 / value;
  if (!(value > 0) || !std::isfinite(static_cast<float>(w)))
    throw Error(std::string("ccm weight: covariance ") +
                (weighting == CcmWeighting::trace ? "trace" : "determinant") + " " +
                std::to_string(value) + " is not positive: the weight would be infinite");
  return static_cast<float>(w);
}

}  // namespace hazmap
