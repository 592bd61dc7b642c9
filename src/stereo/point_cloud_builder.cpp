#include "hazmap/stereo/point_cloud_builder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "hazmap/core/error.hpp"

namespace hazmap {

bool ray_blocked(const KnownTerrain& terrain, const Eigen::Vector3d& camera_W,
                 const Eigen::Vector3d& ray_W, const RayCheck& c) {
  if (!(c.depth_m > 0.0) || !(c.sample_m > 0.0)) return false;
  const double step = c.sample_m / ray_W.norm();  // one sample per cell length along the ray
  // The first depth at or after z_lo where the ray can lie below `level` (a straight line:
  // a descending ray from where it crosses the level on, another one nowhere unless it
  // starts below); infinity when none.
  const auto first_below = [&](double z_lo, double level) {
    if (ray_W.z() < 0.0) return std::max(z_lo, (camera_W.z() - level) / -ray_W.z());
    return camera_W.z() + ray_W.z() * z_lo < level ? z_lo
                                                   : std::numeric_limits<double>::infinity();
  };
  const double near_end = std::min(c.near_m, c.depth_m);
  const auto first_sample = [&](double known_level, double unseen_level) {
    const double z_known = first_below(0.0, known_level);
    const double z_unseen = first_below(0.0, unseen_level);
    return z_unseen < near_end ? std::min(z_known, z_unseen) : z_known;
  };
  // From the whole region's levels, then the levels of the blocks under the rest of the
  // ray (a box around it): most rays near a rock pass over ground.
  double z0 = first_sample(c.known_level_m, c.unseen_level_m);
  if (z0 >= c.depth_m) return false;
  const Eigen::Vector3d a = camera_W + z0 * ray_W, b = camera_W + c.depth_m * ray_W;
  const KnownTerrain::Levels local = terrain.max_levels_in(a.x(), a.y(), b.x(), b.y());
  z0 = std::max(z0, first_sample(local.top_m - c.margin_m, local.unseen_m));
  for (double z = step * std::max(1.0, std::ceil(z0 / step)); z < c.depth_m; z += step) {
    const Eigen::Vector3d p = camera_W + z * ray_W;
    double h = 0.0, var = 0.0;
    if (terrain.height_at(p.x(), p.y(), &h, &var)) {
      // Known terrain: blocked with evidence, more than the margin + 3 sigma below it.
      if (p.z() < h - c.margin_m - 3.0 * std::sqrt(var)) return true;
    } else if (z < c.near_m && terrain.unseen_height_at(p.x(), p.y(), &h) && p.z() < h) {
      // Unseen terrain next to seen terrain, in the near field: the pixel may see its
      // unseen continuation, which it cannot match.
      return true;
    }
  }
  return false;
}

PointCloudBuilder::PointCloudBuilder(const StereoConfig& stereo, const SensorConfig& sensor,
                                     const StereoGeometry& geometry, const Eigen::Matrix3d& R1,
                                     const Pose3d& T_B_C, const cv::Rect& valid_roi)
    : PointCloudBuilder(stereo, sensor, geometry, R1, T_B_C, valid_roi, cv::Rect()) {}

PointCloudBuilder::PointCloudBuilder(const StereoConfig& stereo, const SensorConfig& sensor,
                                     const StereoGeometry& geometry, const Eigen::Matrix3d& R1,
                                     const Pose3d& T_B_C, const cv::Rect& valid_roi,
                                     const cv::Rect& valid_roi_right)
    : stereo_(stereo),
      sensor_(sensor),
      model_(sensor.model == "ray" ? SensorModel::ray : SensorModel::axis),
      geometry_(geometry),
      roi_(valid_roi),
      roi_right_(valid_roi_right) {
  check(stereo.stride >= 1, "stereo.stride must be >= 1");
  T_B_Cr_ = rectified_camera_in_body(T_B_C, R1);
  const auto& r = stereo.roi_px;
  if (r[2] > 0 && r[3] > 0) roi_ &= cv::Rect(r[0], r[1], r[2], r[3]);
  default_near_m_ = near_depth_for(stereo.min_disparity + stereo.num_disparities);
}

double PointCloudBuilder::near_depth_for(int search_end_px) const {
  return search_end_px > 0 ? geometry_.focal_px * geometry_.baseline_m / search_end_px : 0.0;
}

void PointCloudBuilder::set_search_end_by_row(const std::vector<int>& end_px) {
  near_by_row_.resize(end_px.size());
  for (std::size_t v = 0; v < end_px.size(); ++v) near_by_row_[v] = near_depth_for(end_px[v]);
}

void PointCloudBuilder::prepare_terrain(KnownTerrain& terrain, const Pose3d& T_W_B) const {
  double reach = occlusion_depth_m(-1);
  for (std::size_t v = 0; v < near_by_row_.size(); ++v)
    reach = std::max(reach, occlusion_depth_m(static_cast<int>(v)));
  // Every checked stretch lies in the view frustum cut at that depth: the hull of the
  // camera centre and the corners of the region that gives points, at `reach`.
  const Pose3d T_W_Cr = rectified_camera_pose(T_W_B);
  const Eigen::Vector3d camera_W = T_W_Cr.translation();
  double x0 = camera_W.x(), x1 = x0, y0 = camera_W.y(), y1 = y0;
  for (double u : {double(roi_.x), double(roi_.x + roi_.width)})
    for (double v : {double(roi_.y), double(roi_.y + roi_.height)}) {
      const Eigen::Vector3d corner_W =
          T_W_Cr * Eigen::Vector3d((u - geometry_.cx_px) / geometry_.focal_px * reach,
                                   (v - geometry_.cy_px) / geometry_.focal_px * reach, reach);
      x0 = std::min(x0, corner_W.x());
      x1 = std::max(x1, corner_W.x());
      y0 = std::min(y0, corner_W.y());
      y1 = std::max(y1, corner_W.y());
    }
  terrain.prepare_near_field(x0, y0, x1, y1, stereo_.occlusion_fill_m, 3.0);
}

Pose3d PointCloudBuilder::rectified_camera_pose(const Pose3d& T_W_B) const {
  return T_W_B * T_B_Cr_;
}

std::size_t PointCloudBuilder::build(const cv::Mat& disparity_x16, int invalid_below_x16,
                                     const Pose3d& T_W_B, PointCloud& cloud) const {
  return build_impl(disparity_x16, invalid_below_x16, T_W_B, nullptr, cloud, nullptr).below_ground;
}

std::size_t PointCloudBuilder::build(const cv::Mat& disparity_x16, int invalid_below_x16,
                                     const Pose3d& T_W_B, PointCloud& cloud,
                                     std::vector<cv::Point>& pixels) const {
  return build_impl(disparity_x16, invalid_below_x16, T_W_B, nullptr, cloud, &pixels).below_ground;
}

PointDrops PointCloudBuilder::build(const cv::Mat& disparity_x16, int invalid_below_x16,
                                    const Pose3d& T_W_B, const KnownTerrain& terrain,
                                    PointCloud& cloud, std::vector<cv::Point>* pixels) const {
  return build_impl(disparity_x16, invalid_below_x16, T_W_B, &terrain, cloud, pixels);
}

PointDrops PointCloudBuilder::build_impl(const cv::Mat& disparity_x16, int invalid_below_x16,
                                         const Pose3d& T_W_B, const KnownTerrain* terrain,
                                         PointCloud& cloud, std::vector<cv::Point>* pixels) const {
  cloud.clear();
  if (pixels) pixels->clear();
  const Pose3d T_W_Cr = rectified_camera_pose(T_W_B);
  const Eigen::Matrix3d R = T_W_Cr.linear();
  const Eigen::Vector3d t = T_W_Cr.translation();
  const Eigen::Vector3d axis_W = R.col(2);  // the rectified optical axis in W
  const double fb = geometry_.focal_px * geometry_.baseline_m;
  // Disparity bounds equivalent to the depth gate, so the gate costs one compare.
  const double d_min = fb / stereo_.z_max_m, d_max = fb / stereo_.z_min_m;
  const int step = stereo_.stride;
  // Right-image bounds on u - d (sub-pixel: the match must lie inside the valid columns).
  const bool check_right = roi_right_.area() > 0;
  const double right_u_min = roi_right_.x, right_u_max = roi_right_.x + roi_right_.width - 1;
  const cv::Rect roi = roi_ & cv::Rect(0, 0, disparity_x16.cols, disparity_x16.rows) &
                       (check_right ? cv::Rect(0, roi_right_.y, disparity_x16.cols,
                                               roi_right_.height)
                                    : cv::Rect(0, 0, disparity_x16.cols, disparity_x16.rows));
  // SPEC 3.3 below-ground check in the body frame, where the wheel plane is z_B = 0:
  // z_B = (R_B_C' p_C')_z + t_z needs neither the pose nor a transform of the point.
  const bool check_ground = stereo_.max_below_ground_m > 0;
  const Eigen::RowVector3d up_B = T_B_Cr_.linear().row(2);
  const double ground_z = -stereo_.max_below_ground_m - T_B_Cr_.translation().z();
  // Steep rays: below -tolerance a point needs a depression wall steeper than the ray.
  const bool check_depression = check_ground && stereo_.max_depression_slope_deg < 90.0;
  const double tolerance_z = -stereo_.below_ground_tolerance_m - T_B_Cr_.translation().z();
  const double tan_wall = std::tan(stereo_.max_depression_slope_deg * M_PI / 180.0);
  PointDrops drops;
  // Occlusion by known terrain (ray_blocked): rays are sampled every finest terrain cell
  // out to the row's reach. A ray whose lowest point on that stretch stays above the
  // levels of the prepared region (bounded once per call) is not sampled.
  const bool check_occlusion = terrain != nullptr && terrain->prepared() &&
                               stereo_.occlusion_reach > 0;
  const double terrain_top =
      check_occlusion ? terrain->max_top() : -std::numeric_limits<double>::infinity();
  const double sample_m = check_occlusion ? terrain->finest_resolution_m() : 0.0;
  const double occlusion_margin = stereo_.occlusion_margin_m;
  // Levels a ray must get below to be blocked: known terrain less the margin, and in
  // the near field the highest assumed height of an unseen cell.
  const double known_level = terrain_top - occlusion_margin;
  const double unseen_level = check_occlusion ? terrain->max_unseen_height() : 0.0;
  // 64-bit counters: `u += step` in int overflows (UB, a crash) for a stride near INT_MAX
  // when the roi starts at x > 0; config validation bounds the stride too.
  const std::int64_t v_end = std::int64_t{roi.y} + roi.height;
  const std::int64_t u_end = std::int64_t{roi.x} + roi.width;
  for (std::int64_t vv = roi.y; vv < v_end; vv += step) {
    const int v = static_cast<int>(vv);
    const int16_t* row = disparity_x16.ptr<int16_t>(v);
    const double reach_row = occlusion_depth_m(v);
    const double near_row = near_depth_m(v);
    for (std::int64_t uu = roi.x; uu < u_end; uu += step) {
      const int u = static_cast<int>(uu);
      const int d16 = row[u];
      if (d16 <= invalid_below_x16 || d16 <= 0) continue;
      const double d = d16 / 16.0;
      if (d < d_min || d > d_max) continue;
      if (check_right && (u - d < right_u_min || u - d > right_u_max)) continue;
      const Eigen::Vector3d p_C = triangulate(geometry_, u, v, d);
      const double drop = up_B.dot(p_C);  // camera -> point, along body z
      if (check_ground && drop < ground_z) {
        ++drops.below_ground;
        continue;
      }
      if (check_depression && drop < tolerance_z &&
          drop * drop > tan_wall * tan_wall * (p_C.squaredNorm() - drop * drop)) {
        ++drops.below_ground;
        continue;
      }
      const Eigen::Vector3d ray_W = R * p_C;  // camera -> point in W
      if (check_occlusion) {
        // The stretch checked ends at the row's reach or at the point. Cheap test first:
        // a stretch whose lowest point (its start or end) stays above both levels cannot
        // be blocked.
        const double inv_z = 1.0 / p_C.z();
        const double down = std::min(0.0, ray_W.z() * inv_z);
        const double far = std::min(reach_row, p_C.z());
        if ((t.z() + down * far < known_level ||
             t.z() + down * std::min(far, near_row) < unseen_level) &&
            ray_blocked(*terrain, t, ray_W * inv_z,
                        RayCheck{near_row, far, occlusion_margin, sample_m, known_level,
                                 unseen_level})) {
          ++drops.occluded;
          continue;
        }
      }
      Measurement m{};
      m.p_W = (ray_W + t).cast<float>();
      if (model_ == SensorModel::axis) {
        // diag(a, a, b) rotated into W is a I + (b - a) c c^T, c = R's third column (the
        // optical axis in W): no matrix products per point.
        const AxisVariances var = axis_variances(geometry_, p_C.z(), sensor_.pointing_error_px,
                                                 sensor_.disparity_error_px);
        const double a = var.lateral_m2, k = var.depth_m2 - a;
        m.cov_xx = static_cast<float>(a + k * axis_W.x() * axis_W.x());
        m.cov_xy = static_cast<float>(k * axis_W.x() * axis_W.y());
        m.cov_xz = static_cast<float>(k * axis_W.x() * axis_W.z());
        m.cov_yy = static_cast<float>(a + k * axis_W.y() * axis_W.y());
        m.cov_yz = static_cast<float>(k * axis_W.y() * axis_W.z());
        m.cov_zz = static_cast<float>(a + k * axis_W.z() * axis_W.z());
      } else {
        const Eigen::Matrix3d cov_C = covariance_ray(geometry_, u, v, d, sensor_.pointing_error_px,
                                                     sensor_.disparity_error_px);
        const Eigen::Matrix3d cov_W = R * cov_C * R.transpose();
        m.cov_xx = static_cast<float>(cov_W(0, 0));
        m.cov_xy = static_cast<float>(cov_W(0, 1));
        m.cov_xz = static_cast<float>(cov_W(0, 2));
        m.cov_yy = static_cast<float>(cov_W(1, 1));
        m.cov_yz = static_cast<float>(cov_W(1, 2));
        m.cov_zz = static_cast<float>(cov_W(2, 2));
      }
      cloud.push_back(m);
      if (pixels) pixels->emplace_back(u, v);
    }
  }
  return drops;
}

}  // namespace hazmap
