#include "hazmap/eval/seen_confusion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "hazmap/core/error.hpp"
#include "hazmap/stereo/sensor_model.hpp"

namespace hazmap::eval {

SeenMap::SeenMap(const DenseGrid& gt) {
  geometry_.reset(0, 0, gt.resolution_m, gt.center_x_m, gt.center_y_m, 0.0f);
  geometry_.rows = gt.rows;
  geometry_.cols = gt.cols;
  rows_ = gt.rows;
  cols_ = gt.cols;
  first_.assign(static_cast<size_t>(rows_) * cols_, -1);
}

void SeenMap::add_depth(const cv::Mat& depth, const DepthCamera& camera, const Pose3d& T_W_C,
                        double z_max_m, int frame, const LateralGate* gate) {
  check(depth.type() == CV_32FC1, "seen cells: a depth image must be float32, one channel");
  check(camera.fx > 0 && camera.fy > 0, "seen cells: the camera needs positive focal lengths");
  // Normalised ray (x, y) of every pixel column / row, or per pixel through the lens.
  const bool distorted =
      std::any_of(camera.distortion.begin(), camera.distortion.end(), [](double d) { return d != 0.0; });
  std::vector<cv::Point2f> rays;
  if (distorted) {
    std::vector<cv::Point2f> px;
    px.reserve(static_cast<size_t>(depth.rows) * depth.cols);
    for (int v = 0; v < depth.rows; ++v)
      for (int u = 0; u < depth.cols; ++u) px.emplace_back(float(u), float(v));
    const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
    cv::undistortPoints(px, rays, K, camera.distortion);
  }
  const DenseGrid& g = geometry_;
  const Eigen::Matrix3d R = T_W_C.linear();
  const Eigen::Vector3d t = T_W_C.translation();
  const bool gated = gate && gate->max_std_m > 0.0 && std::isfinite(gate->max_std_m);
  const double max_var = gated ? gate->max_std_m * gate->max_std_m : 0.0;
  StereoGeometry geometry;
  if (gate) {
    check(gate->baseline_m > 0.0, "seen cells: the lateral gate needs a positive baseline");
    geometry = {camera.fx, gate->baseline_m, camera.cx, camera.cy};
  }
  // The largest eigenvalue of the xy block of the point's covariance in W, as the map's
  // gate reads it (map_points.cpp).
  const auto lateral_var_W = [&](int u, int v, double z) {
    const Eigen::Matrix3d C =
        gate->ray_model
            ? covariance_ray(geometry, u, v, geometry.focal_px * geometry.baseline_m / z,
                             gate->pointing_px, gate->matching_px)
            : covariance_axis(geometry, z, gate->pointing_px, gate->matching_px);
    const Eigen::Matrix3d W = R * C * R.transpose();
    return major_lateral_variance(W(0, 0), W(1, 1), W(0, 1));
  };
  for (int v = 0; v < depth.rows; ++v) {
    const float* row = depth.ptr<float>(v);
    for (int u = 0; u < depth.cols; ++u) {
      const double z = row[u];
      if (!(z > 0.0 && z <= z_max_m)) continue;  // NaN (sky) fails too
      double x, y;
      if (distorted) {
        const cv::Point2f& r = rays[static_cast<size_t>(v) * depth.cols + u];
        x = r.x;
        y = r.y;
      } else {
        x = (u - camera.cx) / camera.fx;
        y = (v - camera.cy) / camera.fy;
      }
      if (gate) {
        const double d = camera.fx * gate->baseline_m / z;
        if (u < gate->blank_columns || u - d < gate->edge_margin_px) continue;
        if (gated && lateral_var_W(u, v, z) > max_var) continue;
      }
      const Eigen::Vector3d p_W = R * Eigen::Vector3d(x * z, y * z, z) + t;
      int gr = 0, gc = 0;
      if (!g.cell_at(p_W.x(), p_W.y(), &gr, &gc)) continue;
      int& f = first_[static_cast<size_t>(gr) * cols_ + gc];
      if (f < 0 || frame < f) f = frame;
    }
  }
}

SeenMap SeenMap::whole_disc(double radius_m) const {
  check(radius_m >= 0.0 && std::isfinite(radius_m), "seen cells: the radius must be >= 0");
  SeenMap out;
  out.geometry_ = geometry_;
  out.rows_ = rows_;
  out.cols_ = cols_;
  // The latest first-seen frame over each disc (never = the largest value): a max filter
  // with the disc of dilate_obstacles (pixel centres within the radius). Off the grid
  // counts as never.
  const double res = geometry_.resolution_m;
  const int reach = static_cast<int>(std::floor(radius_m / res + 1e-9));
  const double r2 = (radius_m / res) * (radius_m / res) + 1e-9;
  const float never = std::numeric_limits<float>::max();
  cv::Mat first(rows_, cols_, CV_32FC1);
  for (int r = 0; r < rows_; ++r)
    for (int c = 0; c < cols_; ++c) {
      const int f = this->first(r, c);
      first.at<float>(r, c) = f < 0 ? never : static_cast<float>(f);
    }
  cv::Mat disc = cv::Mat::zeros(2 * reach + 1, 2 * reach + 1, CV_8UC1);
  for (int dr = -reach; dr <= reach; ++dr)
    for (int dc = -reach; dc <= reach; ++dc)
      if (double(dr * dr + dc * dc) <= r2) disc.at<unsigned char>(dr + reach, dc + reach) = 1;
  cv::Mat latest;
  cv::dilate(first, latest, disc, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(never));
  out.first_.resize(first_.size());
  for (int r = 0; r < rows_; ++r)
    for (int c = 0; c < cols_; ++c) {
      const float f = latest.at<float>(r, c);
      out.first_[static_cast<size_t>(r) * cols_ + c] = f == never ? -1 : static_cast<int>(f);
    }
  return out;
}

SeenMap SeenMap::with_ring(double radius_m, int samples) const {
  check(radius_m >= 0.0 && std::isfinite(radius_m) && samples >= 1,
        "seen cells: the ring needs a radius >= 0 and a sample");
  SeenMap out;
  out.geometry_ = geometry_;
  out.rows_ = rows_;
  out.cols_ = cols_;
  out.first_ = first_;
  // Each sample's pixel: the one holding the point radius_m from the pixel's centre
  // (rounded, as the classifiers' cell_at), off the grid never seen.
  const double res = geometry_.resolution_m;
  std::vector<std::pair<int, int>> offsets;
  for (int k = 0; k < samples; ++k) {
    const double a = 2.0 * M_PI * k / samples;
    offsets.emplace_back(static_cast<int>(std::lround(radius_m * std::sin(a) / res)),
                         static_cast<int>(std::lround(radius_m * std::cos(a) / res)));
  }
  for (int r = 0; r < rows_; ++r)
    for (int c = 0; c < cols_; ++c) {
      int& f = out.first_[static_cast<size_t>(r) * cols_ + c];
      for (const auto& [dr, dc] : offsets) {
        if (f < 0) break;
        const int rr = r + dr, cc = c + dc;
        const int g = rr < 0 || cc < 0 || rr >= rows_ || cc >= cols_ ? -1 : first(rr, cc);
        f = g < 0 ? -1 : std::max(f, g);
      }
    }
  return out;
}

SeenSums& SeenSums::operator+=(const SeenSums& o) {
  for (int t = 0; t < 3; ++t) {
    for (int l = 0; l < 3; ++l) count[t][l] += o.count[t][l];
    for (int b = 0; b < kUnknownReasonCount; ++b) {
      reason_any[t][b] += o.reason_any[t][b];
      reason_sole[t][b] += o.reason_sole[t][b];
    }
    reason_unrecorded[t] += o.reason_unrecorded[t];
  }
  if (pixel_area_m2 == 0.0) pixel_area_m2 = o.pixel_area_m2;
  return *this;
}

double SeenSums::fraction(int truth, int label) const {
  const std::size_t n = total(truth);
  return n == 0 ? std::numeric_limits<double>::quiet_NaN()
                : static_cast<double>(count[truth][label]) / static_cast<double>(n);
}

SeenSums score_seen(const DenseGrid& hazard, const DenseGrid* reasons, const GroundTruth& gt,
                    const SeenMap& seen, int frame, const Pose3d& T_map_W, double h_min_m,
                    const NearRegion* near) {
  const DenseGrid& g = gt.height;
  check(seen.rows() == g.rows && seen.cols() == g.cols && gt.hazard.rows == g.rows &&
            gt.hazard.cols == g.cols,
        "seen cells: the seen map and the ground truth differ in size");
  check(h_min_m > 0.0 && std::isfinite(h_min_m), "evaluation: h_min must be positive");
  check(reasons == nullptr || reasons->rows == 0 ||
            (reasons->rows == hazard.rows && reasons->cols == hazard.cols),
        "seen cells: the reason grid and the hazard grid differ in size");
  const bool with_reasons = reasons != nullptr && reasons->rows > 0;
  SeenSums s;
  s.pixel_area_m2 = g.resolution_m * g.resolution_m;
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      if (!seen.seen(r, c, frame)) continue;
      const double z_gt = g.at(r, c), obstacle = gt.hazard.at(r, c);
      if (!std::isfinite(z_gt) || !std::isfinite(obstacle)) continue;
      const double x = g.x_of_col(c), y = g.y_of_row(r);
      if (near && !near->contains(x, y)) continue;
      const Eigen::Vector3d p = T_map_W * Eigen::Vector3d(x, y, z_gt);
      int mr = 0, mc = 0;
      if (!hazard.cell_at(p.x(), p.y(), &mr, &mc)) continue;  // outside the map's window
      const int label = static_cast<int>(hazard.at(mr, mc));
      if (label < 0 || label > 2) continue;
      const unsigned bits =
          label == 0 && with_reasons ? static_cast<unsigned>(reasons->at(mr, mc)) : 0u;
      const auto add = [&](int truth) {
        ++s.count[truth][label];
        if (label != 0) return;
        if (bits == 0) {
          ++s.reason_unrecorded[truth];
          return;
        }
        for (int b = 0; b < kUnknownReasonCount; ++b)
          if (bits & (1u << b)) {
            ++s.reason_any[truth][b];
            if (bits == (1u << b)) ++s.reason_sole[truth][b];
          }
      };
      if (obstacle <= 0.0) add(kTruthFree);
      if (obstacle >= h_min_m) add(kTruthHazard);
      if (obstacle >= 2.0 * h_min_m) add(kTruthTall);
    }
  return s;
}

std::vector<std::pair<std::string, double>> seen_fields(const SeenSums& s) {
  std::vector<std::pair<std::string, double>> f;
  // Labels in the order "right, unknown, wrong" per truth class.
  const char* truth_names[3] = {"free", "hazard", "tall"};
  const char* label_names[3] = {"unknown", "traversable", "hazard"};
  const int order[3][3] = {{1, 0, 2}, {2, 0, 1}, {2, 0, 1}};
  for (int t = 0; t < 3; ++t) {
    f.emplace_back(std::string(truth_names[t]) + "_m2", s.area_m2(t));
    for (int k = 0; k < 3; ++k)
      f.emplace_back(std::string(truth_names[t]) + "_" + label_names[order[t][k]],
                     s.fraction(t, order[t][k]));
  }
  const std::size_t unknown = s.count[kTruthFree][0];
  const auto share = [&](std::size_t n) {
    return unknown == 0 ? std::numeric_limits<double>::quiet_NaN()
                        : static_cast<double>(n) / static_cast<double>(unknown);
  };
  for (int b = 0; b < kUnknownReasonCount; ++b) {
    const std::string name = std::string("unknown_free_") + kUnknownReasonNames[b];
    f.emplace_back(name, share(s.reason_any[kTruthFree][b]));
    f.emplace_back(name + "_sole", share(s.reason_sole[kTruthFree][b]));
  }
  f.emplace_back("unknown_free_unrecorded", share(s.reason_unrecorded[kTruthFree]));
  return f;
}

DenseGrid fused_unknown_reasons(const std::vector<ReasonLayer>& layers, double critical_height_m,
                                const DenseGrid& fused) {
  DenseGrid out;
  out.reset(fused.rows, fused.cols, fused.resolution_m, fused.center_x_m, fused.center_y_m, 0.0f);
  for (int r = 0; r < fused.rows; ++r)
    for (int c = 0; c < fused.cols; ++c) {
      if (static_cast<HazardClass>(static_cast<int>(fused.at(r, c))) != HazardClass::unknown)
        continue;
      const double x = fused.x_of_col(c), y = fused.y_of_row(r);
      unsigned bits = 0;
      bool covered = false;
      for (const ReasonLayer& l : layers) {
        int lr = 0, lc = 0;
        if (!l.hazard->cell_at(x, y, &lr, &lc)) continue;
        const auto k = static_cast<HazardClass>(static_cast<int>(l.hazard->at(lr, lc)));
        if (l.h_min_m <= critical_height_m) {
          covered = true;
          if (k == HazardClass::unknown && l.reasons && l.reasons->rows > 0)
            bits |= static_cast<unsigned>(l.reasons->at(lr, lc));
        } else if (k == HazardClass::traversable) {
          bits |= kReasonNoVouchingLayer;
        }
      }
      if (!covered) bits |= kReasonOutside;
      out.at(r, c) = static_cast<float>(bits);
    }
  return out;
}

}  // namespace hazmap::eval
