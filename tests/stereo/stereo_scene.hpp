#pragma once
// Test scenes with exact geometry for the stereo front end: a textured plane rendered
// into real (optionally distorted) pinhole cameras by ray casting every pixel, and
// least-squares / RANSAC plane fits of the points that come back.

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "hazmap/camera/stereo_calibration.hpp"
#include "hazmap/core/types.hpp"
#include "hazmap/map/measurement.hpp"

namespace hazmap::testing {

/// Smooth random texture (blurred noise at two scales), CV_32F in [20, 235]. Its finest
/// detail spans a few texels, so sampling it at about one texel per pixel does not alias.
inline cv::Mat smooth_texture(int w, int h, int seed) {
  cv::RNG rng(static_cast<uint64_t>(seed));
  cv::Mat fine(h, w, CV_32F), coarse(h / 8, w / 8, CV_32F);
  rng.fill(fine, cv::RNG::UNIFORM, 0.0, 1.0);
  rng.fill(coarse, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::GaussianBlur(fine, fine, cv::Size(0, 0), 1.2);
  cv::resize(coarse, coarse, fine.size(), 0, 0, cv::INTER_CUBIC);
  cv::Mat sum = 0.6 * fine + 0.4 * coarse;
  cv::normalize(sum, sum, 20, 235, cv::NORM_MINMAX);
  return sum;
}

/// The plane {origin + s e1 + t e2} carrying `texture` (CV_32F) at `texels_per_m`, its
/// centre at `origin`.
struct TexturedPlane {
  Eigen::Vector3d origin_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d e1_W = Eigen::Vector3d::UnitX();
  Eigen::Vector3d e2_W = Eigen::Vector3d::UnitY();
  cv::Mat texture;
  double texels_per_m = 100.0;
  Eigen::Vector3d normal_W() const { return e1_W.cross(e2_W).normalized(); }
};

/// 8-bit image of the plane seen by a camera (K, D) at T_W_C: each pixel's ray (exactly
/// undistorted) meets the plane; the texture is sampled there (bicubic). Pixels whose
/// ray misses the plane are black.
inline cv::Mat render_plane(const TexturedPlane& plane, const CameraIntrinsics& cam,
                            const Pose3d& T_W_C, cv::Size size) {
  std::vector<cv::Point2f> pixels;
  pixels.reserve(static_cast<size_t>(size.area()));
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) pixels.emplace_back(static_cast<float>(u), static_cast<float>(v));
  cv::Mat K(3, 3, CV_64F);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) K.at<double>(r, c) = cam.K(r, c);
  const cv::Mat D = cam.D.empty() ? cv::Mat() : cv::Mat(cam.D, true).reshape(1, 1);
  std::vector<cv::Point2f> normalised;
  cv::undistortPoints(pixels, normalised, K, D, cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-10));
  cv::Mat map_x(size, CV_32F), map_y(size, CV_32F);
  const Eigen::Vector3d n = plane.normal_W();
  const Eigen::Vector3d c = T_W_C.translation();
  const Eigen::Matrix3d R = T_W_C.linear();
  const double cx = (plane.texture.cols - 1) / 2.0, cy = (plane.texture.rows - 1) / 2.0;
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) {
      const cv::Point2f& q = normalised[static_cast<size_t>(v * size.width + u)];
      const Eigen::Vector3d ray = R * Eigen::Vector3d(q.x, q.y, 1.0);
      const double t = n.dot(plane.origin_W - c) / n.dot(ray);
      float mx = -1e6f, my = -1e6f;
      if (t > 0) {
        const Eigen::Vector3d p = c + t * ray - plane.origin_W;
        mx = static_cast<float>(cx + p.dot(plane.e1_W) * plane.texels_per_m);
        my = static_cast<float>(cy + p.dot(plane.e2_W) * plane.texels_per_m);
      }
      map_x.at<float>(v, u) = mx;
      map_y.at<float>(v, u) = my;
    }
  cv::Mat sampled, out;
  cv::remap(plane.texture, sampled, map_x, map_y, cv::INTER_CUBIC, cv::BORDER_CONSTANT, 0);
  sampled.convertTo(out, CV_8U);
  return out;
}

/// Plane n . p = offset (unit n), fitted to points; residual_std = RMS distance.
struct PlaneFit {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;
  double residual_std = 0.0;
  size_t points = 0;
};

/// Total least squares (smallest eigenvector of the scatter), normal oriented so that
/// normal . hint >= 0.
inline PlaneFit fit_plane(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& hint) {
  PlaneFit fit;
  fit.points = points.size();
  if (points.size() < 3) return fit;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& p : points) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
  fit.normal = eig.eigenvectors().col(0);
  if (fit.normal.dot(hint) < 0) fit.normal = -fit.normal;
  fit.offset = fit.normal.dot(mean);
  fit.residual_std = std::sqrt(eig.eigenvalues()(0) / static_cast<double>(points.size()));
  return fit;
}

/// The plane with most points within `threshold_m` (seeded RANSAC), refitted by least
/// squares to those points twice.
inline PlaneFit fit_dominant_plane(const std::vector<Eigen::Vector3d>& points, double threshold_m,
                                   const Eigen::Vector3d& hint, int iterations = 500,
                                   unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<size_t> pick(0, points.size() - 1);
  // Count inliers on a fixed subsample to keep the search cheap.
  std::vector<Eigen::Vector3d> sample;
  for (size_t i = 0; i < points.size(); i += std::max<size_t>(1, points.size() / 20000))
    sample.push_back(points[i]);
  Eigen::Vector3d best_n = hint.normalized();
  double best_d = 0;
  size_t best_count = 0;
  for (int it = 0; it < iterations; ++it) {
    const Eigen::Vector3d a = points[pick(rng)], b = points[pick(rng)], c = points[pick(rng)];
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-9) continue;
    n.normalize();
    const double d = n.dot(a);
    size_t count = 0;
    for (const auto& p : sample) count += std::abs(n.dot(p) - d) < threshold_m;
    if (count > best_count) best_count = count, best_n = n, best_d = d;
  }
  PlaneFit fit;
  fit.normal = best_n;
  fit.offset = best_d;
  for (int refit = 0; refit < 2; ++refit) {
    std::vector<Eigen::Vector3d> inliers;
    for (const auto& p : points)
      if (std::abs(fit.normal.dot(p) - fit.offset) < threshold_m) inliers.push_back(p);
    fit = fit_plane(inliers, hint);
  }
  return fit;
}

inline std::vector<Eigen::Vector3d> positions(const PointCloud& cloud) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(cloud.size());
  for (const auto& m : cloud) out.push_back(m.p_W.cast<double>());
  return out;
}

/// Angle between two directions [deg].
inline double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

}  // namespace hazmap::testing
