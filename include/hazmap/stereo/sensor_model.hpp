#pragma once
// Triangulation and the per-point covariance of a rectified stereo pair (SPEC 3.3, 4)
// (its geometry: camera/stereo_geometry.hpp); the CCM weight derived from it is in map/map_points.hpp. Pure functions of their
// inputs; frame C' is the rectified left camera (x right, y down, z forward), pixels
// (u, v), disparity d in pixels.

#include <cmath>

#include <Eigen/Core>

#include "hazmap/camera/stereo_geometry.hpp"
#include "hazmap/core/types.hpp"

namespace hazmap {

enum class SensorModel { axis, ray };

/// Z = f B / d, X = (u - cx) Z / f, Y = (v - cy) Z / f. Requires d > 0.
inline Eigen::Vector3d triangulate(const StereoGeometry& g, double u, double v, double d) {
  const double z = g.focal_px * g.baseline_m / d;
  return {(u - g.cx_px) * z / g.focal_px, (v - g.cy_px) * z / g.focal_px, z};
}

/// The thesis' model: independent lateral error p Z / f and depth error Z^2 m / (f B).
/// The axis model's two variances: lateral (p Z / f)^2 and depth (Z^2 m / (f B))^2 [m^2].
struct AxisVariances {
  double lateral_m2, depth_m2;
};
inline AxisVariances axis_variances(const StereoGeometry& g, double z_m, double pointing_px,
                                    double matching_px) {
  const double lateral = pointing_px * z_m / g.focal_px;
  const double depth = z_m * z_m * matching_px / (g.focal_px * g.baseline_m);
  return {lateral * lateral, depth * depth};
}

inline Eigen::Matrix3d covariance_axis(const StereoGeometry& g, double z_m, double pointing_px,
                                       double matching_px) {
  const AxisVariances v = axis_variances(g, z_m, pointing_px, matching_px);
  return Eigen::Vector3d(v.lateral_m2, v.lateral_m2, v.depth_m2).asDiagonal();
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

/// Variance along the major axis of a point's horizontal spread: the largest eigenvalue of
/// the x-y block [[xx, xy], [xy, yy]] of its covariance in W, which the map's lateral gate
/// compares with the gate (map_points.cpp, in float there).
inline double major_lateral_variance(double xx, double yy, double xy) {
  const double half_sum = 0.5 * (xx + yy), half_gap = 0.5 * (xx - yy);
  return half_sum + std::sqrt(half_gap * half_gap + xy * xy);
}

}  // namespace hazmap
