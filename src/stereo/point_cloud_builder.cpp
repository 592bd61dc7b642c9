#include "hazmap/stereo/point_cloud_builder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "hazmap/core/error.hpp"

namespace hazmap {

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
}

Pose3d PointCloudBuilder::rectified_camera_pose(const Pose3d& T_W_B) const {
  return T_W_B * T_B_Cr_;
}

std::size_t PointCloudBuilder::build(const cv::Mat& disparity_x16, int invalid_below_x16,
                                     const Pose3d& T_W_B, PointCloud& cloud) const {
  return build_impl(disparity_x16, invalid_below_x16, T_W_B, cloud, nullptr);
}

std::size_t PointCloudBuilder::build(const cv::Mat& disparity_x16, int invalid_below_x16,
                                     const Pose3d& T_W_B, PointCloud& cloud,
                                     std::vector<cv::Point>& pixels) const {
  return build_impl(disparity_x16, invalid_below_x16, T_W_B, cloud, &pixels);
}

std::size_t PointCloudBuilder::build_impl(const cv::Mat& disparity_x16, int invalid_below_x16,
                                          const Pose3d& T_W_B, PointCloud& cloud,
                                          std::vector<cv::Point>* pixels) const {
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
  std::size_t below_ground = 0;
  // 64-bit counters: `u += step` in int overflows (UB, a crash) for a stride near INT_MAX
  // when the roi starts at x > 0; config validation bounds the stride too.
  const std::int64_t v_end = std::int64_t{roi.y} + roi.height;
  const std::int64_t u_end = std::int64_t{roi.x} + roi.width;
  for (std::int64_t vv = roi.y; vv < v_end; vv += step) {
    const int v = static_cast<int>(vv);
    const int16_t* row = disparity_x16.ptr<int16_t>(v);
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
        ++below_ground;
        continue;
      }
      if (check_depression && drop < tolerance_z &&
          drop * drop > tan_wall * tan_wall * (p_C.squaredNorm() - drop * drop)) {
        ++below_ground;
        continue;
      }
      Measurement m{};
      m.p_W = (R * p_C + t).cast<float>();
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
  return below_ground;
}

std::size_t PointCloudBuilder::build_map_points(const cv::Mat& disparity_x16, int invalid_below_x16,
                                               const Pose3d& T_W_B, CcmWeighting weighting,
                                               MapPoints& out) const {
  if (!supports_map_points())
    throw Error("points: the direct map-points path needs sensor.model axis");
  const Pose3d T_W_Cr = rectified_camera_pose(T_W_B);
  const Eigen::Matrix3d R = T_W_Cr.linear();
  const Eigen::Vector3d t = T_W_Cr.translation();
  const Eigen::Vector3d axis_W = R.col(2);
  const double f = geometry_.focal_px, cx = geometry_.cx_px, cy = geometry_.cy_px;
  const double fb = f * geometry_.baseline_m;
  const double d_min = fb / stereo_.z_max_m, d_max = fb / stereo_.z_min_m;
  const int step = stereo_.stride;
  const bool check_right = roi_right_.area() > 0;
  const double right_u_min = roi_right_.x, right_u_max = roi_right_.x + roi_right_.width - 1;
  const cv::Rect roi = roi_ & cv::Rect(0, 0, disparity_x16.cols, disparity_x16.rows) &
                       (check_right ? cv::Rect(0, roi_right_.y, disparity_x16.cols,
                                               roi_right_.height)
                                    : cv::Rect(0, 0, disparity_x16.cols, disparity_x16.rows));
  const bool check_ground = stereo_.max_below_ground_m > 0;
  const Eigen::Vector3d up_B = T_B_Cr_.linear().row(2).transpose();
  const double ground_z = -stereo_.max_below_ground_m - T_B_Cr_.translation().z();
  const bool check_depression = check_ground && stereo_.max_depression_slope_deg < 90.0;
  const double tolerance_z = -stereo_.below_ground_tolerance_m - T_B_Cr_.translation().z();
  const double tan_wall = std::tan(stereo_.max_depression_slope_deg * M_PI / 180.0);

  // Per point, with Z = f B / d and the ray r = ((u - cx) / f, (v - cy) / f, 1):
  //   p_W = Z (R r) + t, R r = row term + u * R.col(0) / f; drop = Z (up_B . r);
  //   a = (p Z / f)^2 = la Z^2, b = (Z^2 m / (f B))^2 = lb Z^4.
  const float la = static_cast<float>(std::pow(sensor_.pointing_error_px / f, 2));
  const float lb = static_cast<float>(std::pow(sensor_.disparity_error_px / fb, 2));
  const float cz2 = static_cast<float>(axis_W.z() * axis_W.z());
  const float ch2 = static_cast<float>(axis_W.x() * axis_W.x() + axis_W.y() * axis_W.y());
  const Eigen::Vector3f du = (R.col(0) / f).cast<float>();
  const Eigen::Vector3f tf = t.cast<float>();
  const float fbf = static_cast<float>(fb);
  const float up_du = static_cast<float>(up_B.x() / f);
  const float tan2 = static_cast<float>(tan_wall * tan_wall);

  const std::size_t max_points =
      static_cast<std::size_t>((roi.height + step - 1) / step) *
      static_cast<std::size_t>((roi.width + step - 1) / step);
  const MapPoints::Fill fill = out.begin_fill(max_points);
  int n = 0;
  std::size_t below_ground = 0;
  const std::int64_t v_end = std::int64_t{roi.y} + roi.height;
  const std::int64_t u_end = std::int64_t{roi.x} + roi.width;
  for (std::int64_t vv = roi.y; vv < v_end; vv += step) {
    const int v = static_cast<int>(vv);
    const int16_t* row = disparity_x16.ptr<int16_t>(v);
    const double ry = (v - cy) / f;
    const Eigen::Vector3f ray_row = (R * Eigen::Vector3d(-cx / f, ry, 1.0)).cast<float>();
    const float up_row = static_cast<float>(up_B.dot(Eigen::Vector3d(-cx / f, ry, 1.0)));
    const float ry2_1 = static_cast<float>(ry * ry + 1.0);
    for (std::int64_t uu = roi.x; uu < u_end; uu += step) {
      const int u = static_cast<int>(uu);
      const int d16 = row[u];
      if (d16 <= invalid_below_x16 || d16 <= 0) continue;
      const double d = d16 / 16.0;
      if (d < d_min || d > d_max) continue;
      if (check_right && (u - d < right_u_min || u - d > right_u_max)) continue;
      const float uf = static_cast<float>(u);
      const float z = fbf * 16.0f / static_cast<float>(d16);
      const float drop = z * (up_row + uf * up_du);
      if (check_ground && drop < ground_z) {
        ++below_ground;
        continue;
      }
      if (check_depression && drop < tolerance_z) {
        const float rx = static_cast<float>((u - cx) / f);
        const float norm2 = z * z * (rx * rx + ry2_1);
        if (drop * drop > tan2 * (norm2 - drop * drop)) {
          ++below_ground;
          continue;
        }
      }
      const Eigen::Vector3f p = z * (ray_row + uf * du) + tf;
      const float z2 = z * z;
      const float a = la * z2, b = lb * z2 * z2, k = b - a;
      fill.x[n] = p.x();
      fill.y[n] = p.y();
      fill.z[n] = p.z();
      const float var_z = a + k * cz2;
      fill.var_z[n] = var_z;
      fill.inv_var_z[n] = 1.0f / var_z;
      fill.lateral_var[n] = a + std::max(k, 0.0f) * ch2;
      if (weighting == CcmWeighting::trace) {
        fill.ccm_weight[n] = static_cast<float>(1.0 / (2.0 * a + b));
      } else if (weighting == CcmWeighting::det) {
        // In double: a^2 b of a near point is ~1e-24 m^6.
        fill.ccm_weight[n] = static_cast<float>(1.0 / (double(a) * a * b));
      }
      ++n;
    }
  }
  out.end_fill(n, weighting == CcmWeighting::constant);
  return below_ground;
}

}  // namespace hazmap
