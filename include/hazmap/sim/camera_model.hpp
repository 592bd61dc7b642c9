#pragma once
// The simulator's camera: OpenCV's pinhole model with Brown-Conrady lens distortion
// (k1, k2, p1, p2, k3), so that images rendered through it are undone exactly by
// cv::initUndistortRectifyMap / cv::undistortPoints with the same K and D.
//
// Frame C: OpenCV convention (x right, y down, z forward). Pixel centres are at integer
// (u, v); pixel (u, v) covers [u - 0.5, u + 0.5). Normalised coordinates are
// (x, y) = (X / Z, Y / Z); distortion maps them to (x_d, y_d) and then
// u = fx x_d + cx, v = fy y_d + cy.

#include <array>

#include <Eigen/Core>

namespace hazmap::sim {

struct PinholeCamera {
  int width_px = 0;
  int height_px = 0;
  double fx_px = 0.0;
  double fy_px = 0.0;
  double cx_px = 0.0;
  double cy_px = 0.0;
  /// OpenCV order k1, k2, p1, p2, k3; all zero = ideal pinhole (the fast path).
  std::array<double, 5> distortion{0.0, 0.0, 0.0, 0.0, 0.0};

  bool distorted() const {
    return distortion[0] != 0.0 || distortion[1] != 0.0 || distortion[2] != 0.0 ||
           distortion[3] != 0.0 || distortion[4] != 0.0;
  }

  /// Forward lens model: normalised (x, y) -> distorted normalised (x_d, y_d), with
  /// r^2 = x^2 + y^2, radial = 1 + k1 r^2 + k2 r^4 + k3 r^6,
  /// x_d = x radial + 2 p1 x y + p2 (r^2 + 2 x^2), y_d = y radial + p1 (r^2 + 2 y^2) + 2 p2 x y.
  Eigen::Vector2d distort(const Eigen::Vector2d& xy) const;

  /// Inverse of distort by Newton's method (analytic Jacobian), to ~1e-14 in normalised
  /// coordinates, i.e. far below a pixel. Valid where the lens model is monotonic (the
  /// image area of any sane lens); returns the last iterate otherwise.
  Eigen::Vector2d undistort(const Eigen::Vector2d& xy_d) const;

  /// Direction of the ray seen at pixel position (u, v) in C, scaled so that z = 1 (not
  /// unit). Through the lens model when distorted.
  Eigen::Vector3d ray_C(double u_px, double v_px) const {
    Eigen::Vector2d xy((u_px - cx_px) / fx_px, (v_px - cy_px) / fy_px);
    if (distorted()) xy = undistort(xy);
    return Eigen::Vector3d(xy.x(), xy.y(), 1.0);
  }

  /// Pixel position of a point in C (requires p_C.z() > 0). Through the lens model.
  Eigen::Vector2d project(const Eigen::Vector3d& p_C) const {
    Eigen::Vector2d xy(p_C.x() / p_C.z(), p_C.y() / p_C.z());
    if (distorted()) xy = distort(xy);
    return Eigen::Vector2d(fx_px * xy.x() + cx_px, fy_px * xy.y() + cy_px);
  }
};

}  // namespace hazmap::sim
