#include "hazmap/stereo/ground_plane_fit.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Eigenvalues>

namespace hazmap {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Sample {
  Eigen::Vector3d p;
  Eigen::Matrix3d cov;
};

double sigma_along(const Sample& s, const Eigen::Vector3d& n, double floor_m) {
  const double var = std::max(0.0, n.dot(s.cov * n));
  return std::max(std::sqrt(var), floor_m);
}

bool is_inlier(const Sample& s, const Eigen::Vector3d& n, const Eigen::Vector3d& p0,
               const GroundPlaneOptions& o) {
  return std::abs(n.dot(s.p - p0)) <= o.k_sigma * sigma_along(s, n, o.min_sigma_m);
}

/// Weighted total least squares: the plane through the weighted centroid whose normal is
/// the weighted scatter's smallest eigenvector. Weights 1/sigma_n^2 along `n_prior`.
bool refine(const std::vector<Sample>& samples, const GroundPlaneOptions& o, Eigen::Vector3d& n,
            Eigen::Vector3d& p0) {
  double w_sum = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  std::vector<double> w(samples.size(), 0.0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!is_inlier(samples[i], n, p0, o)) continue;
    const double s = sigma_along(samples[i], n, o.min_sigma_m);
    w[i] = 1.0 / (s * s);
    w_sum += w[i];
    centroid += w[i] * samples[i].p;
  }
  if (w_sum <= 0.0) return false;
  centroid /= w_sum;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (w[i] == 0.0) continue;
    const Eigen::Vector3d d = samples[i].p - centroid;
    scatter += w[i] * d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
  if (eig.info() != Eigen::Success) return false;
  n = eig.eigenvectors().col(0).normalized();  // eigenvalues ascending
  p0 = centroid;
  return true;
}

}  // namespace

double GroundPlane::tilt_deg(const Eigen::Vector3d& up) const {
  const double c = std::clamp(normal.dot(up.normalized()), -1.0, 1.0);
  return std::acos(c) * 180.0 / kPi;
}

GroundPlane fit_ground_plane(const PointCloud& cloud, const Eigen::Vector3d& viewpoint,
                             const GroundPlaneOptions& options) {
  GroundPlane plane;
  // An even stride over the cloud keeps the subset spread over the whole image (the
  // builder emits points row by row) and the fit deterministic.
  const std::size_t n_total = cloud.size();
  const std::size_t count = std::min(n_total, std::max<std::size_t>(options.max_points, 3));
  if (count < 3) return plane;
  std::vector<Sample> samples(count);
  for (std::size_t k = 0; k < count; ++k) {
    const Measurement& m = cloud[k * n_total / count];
    Sample& s = samples[k];
    s.p = m.p_W.cast<double>();
    s.cov << m.cov_xx, m.cov_xy, m.cov_xz, m.cov_xy, m.cov_yy, m.cov_yz, m.cov_xz, m.cov_yz,
        m.cov_zz;
  }
  plane.points_used = count;

  std::mt19937 rng(20261124u);  // fixed: the same cloud gives the same plane
  std::uniform_int_distribution<std::size_t> pick(0, count - 1);
  std::size_t best = 0;
  Eigen::Vector3d best_n = Eigen::Vector3d::UnitZ(), best_p = Eigen::Vector3d::Zero();
  for (int it = 0; it < options.iterations; ++it) {
    const Eigen::Vector3d& a = samples[pick(rng)].p;
    const Eigen::Vector3d& b = samples[pick(rng)].p;
    const Eigen::Vector3d& c = samples[pick(rng)].p;
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    const double norm = cross.norm();
    if (!(norm > 1e-12)) continue;  // repeated or collinear picks
    const Eigen::Vector3d n = cross / norm;
    std::size_t inliers = 0;
    for (const Sample& s : samples) inliers += is_inlier(s, n, a, options) ? 1 : 0;
    if (inliers > best) {
      best = inliers;
      best_n = n;
      best_p = a;
    }
  }
  if (best < 3) return plane;
  // The inlier set moves with the plane: refine until the normal settles.
  for (int pass = 0; pass < options.max_refinements; ++pass) {
    const Eigen::Vector3d before = best_n;
    if (!refine(samples, options, best_n, best_p)) return plane;
    if (std::abs(best_n.dot(before)) > std::cos(options.converged_rad)) break;
  }

  std::size_t inliers = 0;
  for (const Sample& s : samples) inliers += is_inlier(s, best_n, best_p, options) ? 1 : 0;
  plane.inlier_share = static_cast<double>(inliers) / static_cast<double>(count);
  if (best_n.dot(viewpoint - best_p) < 0.0) best_n = -best_n;
  plane.normal = best_n;
  plane.point = best_p;
  plane.found = plane.inlier_share >= options.min_inlier_share && inliers >= options.min_inliers;
  return plane;
}

}  // namespace hazmap
