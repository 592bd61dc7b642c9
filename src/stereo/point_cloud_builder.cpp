#include "hazmap/stereo/point_cloud_builder.hpp"

#include <algorithm>
#include <array>
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
      model_(sensor.model),
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

// The gates of SPEC 3.3 every pixel passes before it becomes a point, built once per
// call and shared by both paths.
struct PointCloudBuilder::PixelGates {
  cv::Rect roi;  ///< valid left region & stereo.roi & the right image's valid rows
  std::int64_t step = 1;
  double d_min = 0, d_max = 0;  ///< the depth gate as disparity bounds: one compare
  bool check_right = false;     ///< the match u - d inside the right image's valid columns
  double right_u_min = 0, right_u_max = 0;
  // Below-ground check in the body frame, where the wheel plane is z_B = 0: with `drop`
  // the camera -> point offset along body z, z_B = drop + t_z needs no transform.
  bool check_ground = false;
  double ground_z = 0;
  // Steep rays: below -tolerance a point needs a depression wall steeper than the ray.
  bool check_depression = false;
  double tolerance_z = 0, tan2_wall = 0;

  bool disparity_ok(int u, int d16, int invalid_below_x16) const {
    if (d16 <= invalid_below_x16 || d16 <= 0) return false;
    const double d = d16 / 16.0;
    if (d < d_min || d > d_max) return false;
    return !check_right || (u - d >= right_u_min && u - d <= right_u_max);
  }
  /// `norm2()`: the point's squared distance from the camera, asked only of steep rays.
  template <class T, class Norm2>
  bool below_ground(T drop, const Norm2& norm2) const {
    if (!check_ground) return false;
    if (drop < ground_z) return true;
    if (!check_depression || !(drop < tolerance_z)) return false;
    return drop * drop > static_cast<T>(tan2_wall) * (norm2() - drop * drop);
  }
};

PointCloudBuilder::PixelGates PointCloudBuilder::pixel_gates(const cv::Mat& disparity_x16) const {
  PixelGates g;
  const double fb = geometry_.focal_px * geometry_.baseline_m;
  g.d_min = fb / stereo_.z_max_m;
  g.d_max = fb / stereo_.z_min_m;
  g.step = stereo_.stride;  // 64-bit: see for_each_gated_pixel; validation bounds it too
  g.check_right = roi_right_.area() > 0;
  g.right_u_min = roi_right_.x;
  g.right_u_max = roi_right_.x + roi_right_.width - 1;
  const cv::Rect image(0, 0, disparity_x16.cols, disparity_x16.rows);
  g.roi = roi_ & image &
          (g.check_right ? cv::Rect(0, roi_right_.y, disparity_x16.cols, roi_right_.height)
                         : image);
  g.check_ground = stereo_.max_below_ground_m > 0;
  g.ground_z = -stereo_.max_below_ground_m - T_B_Cr_.translation().z();
  g.check_depression = g.check_ground && stereo_.max_depression_slope_deg < 90.0;
  g.tolerance_z = -stereo_.below_ground_tolerance_m - T_B_Cr_.translation().z();
  const double tan_wall = std::tan(stereo_.max_depression_slope_deg * M_PI / 180.0);
  g.tan2_wall = tan_wall * tan_wall;
  return g;
}

// Occlusion by known terrain (ray_blocked): a ray is sampled every finest terrain cell out
// to its row's reach, unless its lowest point on that stretch stays above the levels of
// the prepared region (bounded once per call) or of its row segment's box (below).
struct PointCloudBuilder::OcclusionGate {
  const KnownTerrain* terrain = nullptr;
  bool on = false;
  double margin_m = 0, sample_m = 0;
  double known_level = 0;   ///< known terrain less the margin, highest
  double unseen_level = 0;  ///< the highest assumed height of an unseen cell (near field)

  // Most rays dip below the whole region's levels (one rock anywhere raises them), and
  // each then pays for its own box (ray_blocked). The rays of kSegmentPx neighbouring
  // pixels of a row, out to the row's reach, lie in the triangle of the camera and the
  // segment's two end rays at that depth (a ray is linear in u), so that triangle's box
  // bounds them all: one box per segment, and a ray whose stretch stays above the
  // segment's levels is not blocked, exactly as its own box would say.
  static constexpr int kSegmentPx = 32;
  static constexpr int kMaxSegments = 512;
  struct Segment {
    int row = -1;  ///< the image row the levels are for (-1: none yet)
    double known = 0, unseen = 0;
  };
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< rectified camera -> W
  double f = 1, cx = 0, cy = 0;
  int segment_px = kSegmentPx, width = 0;
  mutable std::array<Segment, kMaxSegments> segments{};

  /// The segment of pixel (u, v): its levels, computed on first use in row v.
  const Segment& segment(const Eigen::Vector3d& camera_W, int u, int v, double reach) const {
    Segment& s = segments[static_cast<std::size_t>(u / segment_px)];
    if (s.row == v) return s;
    const int u0 = u / segment_px * segment_px, u1 = std::min(u0 + segment_px - 1, width - 1);
    const Eigen::Vector3d r0 = R * Eigen::Vector3d((u0 - cx) / f, (v - cy) / f, 1.0);
    const Eigen::Vector3d r1 = R * Eigen::Vector3d((u1 - cx) / f, (v - cy) / f, 1.0);
    const Eigen::Vector3d b = camera_W + reach * r0, c = camera_W + reach * r1;
    // A pad far above the rays' rounding (float rays: ~1e-7 m at a metre).
    constexpr double kPad = 1e-5;
    const double x0 = std::min({camera_W.x(), b.x(), c.x()}) - kPad;
    const double x1 = std::max({camera_W.x(), b.x(), c.x()}) + kPad;
    const double y0 = std::min({camera_W.y(), b.y(), c.y()}) - kPad;
    const double y1 = std::max({camera_W.y(), b.y(), c.y()}) + kPad;
    const KnownTerrain::Levels l = terrain->max_levels_in(x0, y0, x1, y1);
    s.row = v;
    s.known = std::min(known_level, l.top_m - margin_m);
    s.unseen = std::min(unseen_level, l.unseen_m);
    return s;
  }

  /// `ray`: camera -> point in W per metre of depth; `depth` the point's; `reach`, `near`
  /// its row's occlusion and near-field depths; (u, v) its pixel.
  bool blocked(const Eigen::Vector3d& camera_W, const Eigen::Vector3d& ray, double depth,
               double reach, double near, int u, int v) const {
    const double down = std::min(0.0, ray.z());
    const double far = std::min(reach, depth);
    // Cheap test first: a stretch whose lowest point (its start or end) stays above both
    // levels cannot be blocked.
    const auto above = [&](double known, double unseen) {
      return !(camera_W.z() + down * far < known ||
               camera_W.z() + down * std::min(far, near) < unseen);
    };
    if (above(known_level, unseen_level)) return false;
    const Segment& s = segment(camera_W, u, v, reach);
    if (above(s.known, s.unseen)) return false;
    return ray_blocked(*terrain, camera_W, ray,
                       RayCheck{near, far, margin_m, sample_m, known_level, unseen_level});
  }
};

PointCloudBuilder::OcclusionGate PointCloudBuilder::occlusion_gate(const KnownTerrain* terrain,
                                                                   const Eigen::Matrix3d& R,
                                                                   int width) const {
  OcclusionGate g;
  g.on = terrain != nullptr && terrain->prepared() && stereo_.occlusion_reach > 0;
  if (!g.on) return g;
  g.terrain = terrain;
  g.margin_m = stereo_.occlusion_margin_m;
  g.sample_m = terrain->finest_resolution_m();
  g.known_level = terrain->max_top() - g.margin_m;
  g.unseen_level = terrain->max_unseen_height();
  g.R = R;
  g.f = geometry_.focal_px;
  g.cx = geometry_.cx_px;
  g.cy = geometry_.cy_px;
  g.width = width;
  g.segment_px = std::max(OcclusionGate::kSegmentPx,
                          (width + OcclusionGate::kMaxSegments - 1) / OcclusionGate::kMaxSegments);
  return g;
}

std::size_t PointCloudBuilder::build(const cv::Mat& disparity_x16, int invalid_below_x16,
                                     const Pose3d& T_W_B, PointCloud& cloud) const {
  return build_impl(disparity_x16, invalid_below_x16, T_W_B, nullptr, cloud, nullptr, nullptr)
      .below_ground;
}

std::size_t PointCloudBuilder::build(const cv::Mat& disparity_x16, int invalid_below_x16,
                                     const Pose3d& T_W_B, PointCloud& cloud,
                                     std::vector<cv::Point>& pixels) const {
  return build_impl(disparity_x16, invalid_below_x16, T_W_B, nullptr, cloud, &pixels, nullptr)
      .below_ground;
}

PointDrops PointCloudBuilder::build(const cv::Mat& disparity_x16, int invalid_below_x16,
                                    const Pose3d& T_W_B, const KnownTerrain& terrain,
                                    PointCloud& cloud, std::vector<cv::Point>* pixels,
                                    cv::Mat* mark_occluded) const {
  return build_impl(disparity_x16, invalid_below_x16, T_W_B, &terrain, cloud, pixels,
                    mark_occluded);
}

namespace {

void check_mark_size(const cv::Mat* mark, const cv::Mat& disparity) {
  if (mark != nullptr && (mark->size() != disparity.size() || mark->type() != CV_16S))
    throw Error("points: the occlusion mark image must be CV_16S of the disparity's size");
}

/// What became of a pixel that passed the disparity gates.
enum class PixelFate { kept, below_ground, occluded };

/// The pixel loop both paths share, so that they visit, count and mark alike: every pixel
/// of the gates' region on the stride grid whose disparity passes goes to
/// `pixel(row_state, u, v, d16)`, with `row_state = row(v)` computed once per row; the
/// path's verdict is counted here, and an occluded pixel is marked invalid in
/// `mark_occluded` (if given; checked by the caller) so that a cloud built later from that disparity image holds
/// exactly what reached the map.
template <class Gates, class RowFn, class PixelFn>
PointDrops for_each_gated_pixel(const cv::Mat& disparity_x16, int invalid_below_x16,
                                const Gates& gates, cv::Mat* mark_occluded, RowFn&& row,
                                PixelFn&& pixel) {
  PointDrops drops;
  const cv::Rect& roi = gates.roi;
  // 64-bit counters: `u += step` in int overflows for a stride near INT_MAX when the roi
  // starts at x > 0.
  const std::int64_t v_end = std::int64_t{roi.y} + roi.height;
  const std::int64_t u_end = std::int64_t{roi.x} + roi.width;
  for (std::int64_t vv = roi.y; vv < v_end; vv += gates.step) {
    const int v = static_cast<int>(vv);
    const int16_t* disparity_row = disparity_x16.ptr<int16_t>(v);
    const auto row_state = row(v);
    for (std::int64_t uu = roi.x; uu < u_end; uu += gates.step) {
      const int u = static_cast<int>(uu);
      const int d16 = disparity_row[u];
      if (!gates.disparity_ok(u, d16, invalid_below_x16)) continue;
      switch (pixel(row_state, u, v, d16)) {
        case PixelFate::kept:
          break;
        case PixelFate::below_ground:
          ++drops.below_ground;
          break;
        case PixelFate::occluded:
          ++drops.occluded;
          if (mark_occluded)
            mark_occluded->at<int16_t>(v, u) = static_cast<int16_t>(invalid_below_x16);
          break;
      }
    }
  }
  return drops;
}

}  // namespace

PointDrops PointCloudBuilder::build_impl(const cv::Mat& disparity_x16, int invalid_below_x16,
                                         const Pose3d& T_W_B, const KnownTerrain* terrain,
                                         PointCloud& cloud, std::vector<cv::Point>* pixels,
                                         cv::Mat* mark_occluded) const {
  check_mark_size(mark_occluded, disparity_x16);
  cloud.clear();
  if (pixels) pixels->clear();
  const Pose3d T_W_Cr = rectified_camera_pose(T_W_B);
  const Eigen::Matrix3d R = T_W_Cr.linear();
  const Eigen::Vector3d t = T_W_Cr.translation();
  const Eigen::Vector3d axis_W = R.col(2);  // the rectified optical axis in W
  const PixelGates gates = pixel_gates(disparity_x16);
  const OcclusionGate occlusion = occlusion_gate(terrain, R, disparity_x16.cols);
  const Eigen::RowVector3d up_B = T_B_Cr_.linear().row(2);
  struct Row {
    double reach_m, near_m;  // the row's occlusion and near-field depths
  };
  const auto row = [&](int v) { return Row{occlusion_depth_m(v), near_depth_m(v)}; };
  const auto pixel = [&](const Row& r, int u, int v, int d16) {
    const Eigen::Vector3d p_C = triangulate(geometry_, u, v, d16 / 16.0);
    const double drop = up_B.dot(p_C);  // camera -> point, along body z
    if (gates.below_ground(drop, [&] { return p_C.squaredNorm(); }))
      return PixelFate::below_ground;
    const Eigen::Vector3d ray_W = R * p_C;  // camera -> point in W
    if (occlusion.on &&
        occlusion.blocked(t, ray_W * (1.0 / p_C.z()), p_C.z(), r.reach_m, r.near_m, u, v))
      return PixelFate::occluded;
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
      const Eigen::Matrix3d cov_C = covariance_ray(geometry_, u, v, d16 / 16.0,
                                                   sensor_.pointing_error_px,
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
    return PixelFate::kept;
  };
  return for_each_gated_pixel(disparity_x16, invalid_below_x16, gates, mark_occluded, row,
                              pixel);
}

std::size_t PointCloudBuilder::build_map_points(const cv::Mat& disparity_x16, int invalid_below_x16,
                                               const Pose3d& T_W_B, CcmWeighting weighting,
                                               MapPoints& out) const {
  return map_points_impl(disparity_x16, invalid_below_x16, T_W_B, nullptr, weighting, out,
                         nullptr)
      .below_ground;
}

PointDrops PointCloudBuilder::build_map_points(const cv::Mat& disparity_x16, int invalid_below_x16,
                                              const Pose3d& T_W_B, const KnownTerrain& terrain,
                                              CcmWeighting weighting, MapPoints& out,
                                              cv::Mat* mark_occluded) const {
  return map_points_impl(disparity_x16, invalid_below_x16, T_W_B, &terrain, weighting, out,
                         mark_occluded);
}

PointDrops PointCloudBuilder::map_points_impl(const cv::Mat& disparity_x16, int invalid_below_x16,
                                              const Pose3d& T_W_B, const KnownTerrain* terrain,
                                              CcmWeighting weighting, MapPoints& out,
                                              cv::Mat* mark_occluded) const {
  if (!supports_map_points())
    throw Error("points: the direct map-points path needs sensor.model axis");
  check_mark_size(mark_occluded, disparity_x16);  // before the fill: `out` stays untouched
  const Pose3d T_W_Cr = rectified_camera_pose(T_W_B);
  const Eigen::Matrix3d R = T_W_Cr.linear();
  const Eigen::Vector3d t = T_W_Cr.translation();
  const Eigen::Vector3d axis_W = R.col(2);
  const double f = geometry_.focal_px, cx = geometry_.cx_px, cy = geometry_.cy_px;
  const double fb = f * geometry_.baseline_m;
  const PixelGates gates = pixel_gates(disparity_x16);
  const OcclusionGate occlusion = occlusion_gate(terrain, R, disparity_x16.cols);
  const Eigen::Vector3d up_B = T_B_Cr_.linear().row(2).transpose();

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

  const cv::Rect& roi = gates.roi;
  const std::size_t max_points =
      static_cast<std::size_t>((roi.height + gates.step - 1) / gates.step) *
      static_cast<std::size_t>((roi.width + gates.step - 1) / gates.step);
  const MapPoints::Fill fill = out.begin_fill(max_points);
  int n = 0;
  struct Row {
    Eigen::Vector3f ray;  // camera -> pixel (u = 0) in W per metre of Z
    float up;             // its component along body z
    float ry2_1;          // (v - cy)^2 / f^2 + 1
    double reach_m, near_m;
  };
  const auto row = [&](int v) {
    const double ry = (v - cy) / f;
    const Eigen::Vector3d r(-cx / f, ry, 1.0);
    return Row{(R * r).cast<float>(), static_cast<float>(up_B.dot(r)),
               static_cast<float>(ry * ry + 1.0), occlusion_depth_m(v), near_depth_m(v)};
  };
  const auto pixel = [&](const Row& r, int u, int v, int d16) {
    const float uf = static_cast<float>(u);
    const float z = fbf * 16.0f / static_cast<float>(d16);
    const float drop = z * (r.up + uf * up_du);
    if (gates.below_ground(drop, [&] {
          const float rx = static_cast<float>((u - cx) / f);
          return z * z * (rx * rx + r.ry2_1);
        }))
      return PixelFate::below_ground;
    const Eigen::Vector3f ray = r.ray + uf * du;  // camera -> point in W per metre of Z
    if (occlusion.on && occlusion.blocked(t, ray.cast<double>(), z, r.reach_m, r.near_m, u, v))
      return PixelFate::occluded;
    const Eigen::Vector3f p = z * ray + tf;
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
    return PixelFate::kept;
  };
  const PointDrops drops =
      for_each_gated_pixel(disparity_x16, invalid_below_x16, gates, mark_occluded, row, pixel);
  out.end_fill(n, weighting == CcmWeighting::constant);
  return drops;
}

}  // namespace hazmap
