#include "hazmap/pipeline/preflight_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "hazmap/core/error.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/stereo/row_offset.hpp"
#include "hazmap/map/layer_stack.hpp"
#include "hazmap/pipeline/rig_geometry.hpp"
#include "hazmap/stereo/sensor_model.hpp"
#include "hazmap/stereo/stereo_front_end.hpp"

namespace hazmap {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Boards tried when none is named: OpenCV's samples (9x6) and the usual printed ones.
const cv::Size kCommonBoards[] = {{9, 6}, {8, 6}, {7, 6}, {7, 5}, {6, 5}, {10, 7}, {11, 8}};

/// Rays of the lowest valid row sampled across it for the nearest visible ground.
constexpr int kNearestGroundRays = 33;

std::string fmt(const char* format, double a, double b = 0, double c = 0, double d = 0) {
  char text[256];
  std::snprintf(text, sizeof text, format, a, b, c, d);
  return text;
}

double median(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return std::isnan(x); }), v.end());
  if (v.empty()) return kNaN;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

/// Chessboard corners in one rectified image, refined to sub-pixel; empty if not found.
std::vector<cv::Point2f> find_board(const cv::Mat& grey, cv::Size board) {
  std::vector<cv::Point2f> corners;
  const int flags = cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE |
                    cv::CALIB_CB_FAST_CHECK;
  if (!cv::findChessboardCorners(grey, board, corners, flags)) return {};
  cv::cornerSubPix(grey, corners, cv::Size(5, 5), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.01));
  return corners;
}

/// Adds one rectified pair's row differences of `board` to `rows`; false if the board is
/// not found in both images.
bool add_row_errors(const cv::Mat& left, const cv::Mat& right, cv::Size board,
                    std::vector<double>& dv) {
  const std::vector<cv::Point2f> l = find_board(left, board);
  if (l.empty()) return false;
  std::vector<cv::Point2f> r = find_board(right, board);
  if (r.size() != l.size()) return false;
  // OpenCV may start the corner order at the opposite end in the other view; the same
  // order has the first-to-last vector pointing the same way in both.
  const cv::Point2f dl = l.back() - l.front(), dr = r.back() - r.front();
  if (dl.dot(dr) < 0) std::reverse(r.begin(), r.end());
  for (size_t i = 0; i < l.size(); ++i) dv.push_back(static_cast<double>(l[i].y - r[i].y));
  return true;
}

/// The ground point seen through rectified pixel (u, v): ray from `T_W_Cr` meeting the
/// plane (n, p0); false if the ray runs parallel to it or away from it.
bool ray_meets(const Pose3d& T_W_Cr, const StereoGeometry& g, double u, double v,
               const Eigen::Vector3d& n, const Eigen::Vector3d& p0, double& depth,
               Eigen::Vector3d& hit) {
  const Eigen::Vector3d c = T_W_Cr.translation();
  const Eigen::Vector3d r =
      T_W_Cr.linear() * Eigen::Vector3d((u - g.cx_px) / g.focal_px, (v - g.cy_px) / g.focal_px, 1.0);
  const double denom = n.dot(r);
  if (std::abs(denom) < 1e-12) return false;
  const double s = n.dot(p0 - c) / denom;  // the ray's z_C' component is 1: s is the depth
  if (!(s > 0)) return false;
  depth = s;
  hit = c + s * r;
  return true;
}

FrameCheck check_frame(StereoFrontEnd& front, const SequenceFrame& frame, const Config& config,
                       const StereoCalibration& calibration) {
  FrameCheck fc;
  fc.name = frame.name;
  const cv::Mat left = read_image(frame.left_path), right = read_image(frame.right_path);
  const Pose3d& T_W_B = frame.pose.T_W_B;
  front.process(left, right, T_W_B);

  const cv::Rect region = front.builder().region();
  const cv::Mat disp = front.disparity_x16()(region);
  const int invalid = front.matcher().invalid_below();
  std::size_t valid = 0;
  for (int y = 0; y < disp.rows; ++y) {
    const short* row = disp.ptr<short>(y);
    for (int x = 0; x < disp.cols; ++x) valid += row[x] > invalid ? 1 : 0;
  }
  fc.valid_disparity_share = region.area() > 0 ? static_cast<double>(valid) / region.area() : 0.0;

  const PointCloud& cloud = front.cloud();
  fc.points = cloud.size();
  fc.points_below_ground = front.points_below_ground();
  const Pose3d T_W_Cr = front.builder().rectified_camera_pose(T_W_B);
  const Eigen::Vector3d camera = T_W_Cr.translation();
  const Eigen::Vector3d body = T_W_B.translation();
  const Eigen::Vector3d body_up = T_W_B.linear().col(2);

  fc.ground = fit_ground_plane(cloud, camera);
  fc.tilt_w_deg = fc.ground.found ? fc.ground.tilt_deg(Eigen::Vector3d::UnitZ()) : kNaN;
  fc.tilt_body_deg = fc.ground.found ? fc.ground.tilt_deg(body_up) : kNaN;
  fc.camera_height_m = fc.ground.found ? fc.ground.height_of(camera) : kNaN;
  fc.body_height_m = fc.ground.found ? fc.ground.height_of(body) : kNaN;
  if (fc.ground.found)
    fc.scalar_first_hint = scalar_first_hint(calibration, T_W_B, fc.ground.normal,
                                             config.hazard.max_slope_deg);

  // Nearest visible ground: the fitted plane, else the wheel plane z_B = 0.
  const Eigen::Vector3d n = fc.ground.found ? fc.ground.normal : body_up;
  const Eigen::Vector3d p0 = fc.ground.found ? fc.ground.point : body;
  const StereoGeometry& g = front.rectifier().geometry();
  fc.nearest_ground_depth_m = fc.nearest_ground_disparity_px = fc.nearest_ground_distance_m = kNaN;
  const double v = region.y + region.height - 1;
  for (int k = 0; k < kNearestGroundRays && region.width > 0; ++k) {
    const double u = region.x + (region.width - 1) * k / double(kNearestGroundRays - 1);
    double depth = 0;
    Eigen::Vector3d hit;
    if (!ray_meets(T_W_Cr, g, u, v, n, p0, depth, hit)) continue;
    if (std::isnan(fc.nearest_ground_depth_m) || depth < fc.nearest_ground_depth_m) {
      fc.nearest_ground_depth_m = depth;
      fc.nearest_ground_disparity_px = g.focal_px * g.baseline_m / depth;
      fc.nearest_ground_distance_m = (hit - body).head<2>().norm();
    }
  }

  fc.nearest_point_distance_m = kNaN;
  const auto& layers = config.map.layers;
  std::vector<std::size_t> inside(layers.size(), 0);
  // A point reaches a layer inside its window and through its lateral gate (SPEC 4), as
  // the map takes it: the largest eigenvalue of its x-y covariance against the gate.
  std::vector<double> gate_var(layers.size(), std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < layers.size(); ++i) {
    const double gate = gate_std_m(layers[i], config.rules);
    if (gate > 0) gate_var[i] = gate * gate;
  }
  for (const Measurement& m : cloud) {
    const double dx = m.p_W.x() - body.x(), dy = m.p_W.y() - body.y();
    const double d = std::hypot(dx, dy);
    if (std::isnan(fc.nearest_point_distance_m) || d < fc.nearest_point_distance_m)
      fc.nearest_point_distance_m = d;
    const double lateral_var = major_lateral_variance(m.cov_xx, m.cov_yy, m.cov_xy);
    for (size_t i = 0; i < layers.size(); ++i) {
      const double half = 0.5 * layers[i].size * layers[i].resolution_m;
      if (std::abs(dx) <= half && std::abs(dy) <= half && lateral_var <= gate_var[i]) ++inside[i];
    }
  }
  for (std::size_t c : inside)
    fc.layer_share.push_back(cloud.empty() ? 0.0 : static_cast<double>(c) / static_cast<double>(cloud.size()));
  return fc;
}

/// Adds the row offset of the front end's current rectified pair to `per_frame`.
void add_row_offset(const StereoFrontEnd& front, std::vector<RowOffsetEstimate>& per_frame) {
  const RowOffsetEstimate e = estimate_row_offset(front.rectified_left(), front.rectified_right());
  per_frame.push_back(e);
}

/// The frames' row offsets in one figure: medians over the frames with an estimate.
RowOffsetCheck summarise_row_offsets(const std::vector<RowOffsetEstimate>& per_frame,
                                     const StereoFrontEnd& front, const Config& config) {
  RowOffsetCheck out;
  out.applied_px = front.rectifier().row_offset();
  out.automatic = !config.stereo.row_offset.has_value();
  std::vector<double> offsets, spreads;
  for (const RowOffsetEstimate& e : per_frame) {
    out.matches += e.matches;
    if (!e.found) continue;
    ++out.frames;
    out.inliers += e.inliers;
    offsets.push_back(e.offset_px);
    spreads.push_back(e.spread_px);
  }
  if (out.frames > 0) {
    out.offset_px = median(offsets);
    out.spread_px = median(spreads);
  }
  return out;
}

/// The verdict's line on the row offset (empty when fine or not measured).
std::string row_offset_problem(const RowOffsetCheck& o, double max_px) {
  if (o.frames == 0 || std::abs(o.offset_px) <= max_px) return "";
  return fmt("rectified rows disagree by %+.2f px (y_left - y_right, spread %.2f px, feature "
             "matches; > %.2f px): set stereo.row_offset_px to %.2f (or auto)",
             o.offset_px, o.spread_px, max_px, o.applied_px + o.offset_px);
}

/// The report's line on the row offset.
std::string format_row_offset(const RowOffsetCheck& o) {
  std::string applied = fmt("%+.2f px", o.applied_px);
  if (o.automatic) applied += " (auto)";
  if (o.frames == 0)
    return "row offset: too few feature matches to measure (" + std::to_string(o.matches) +
           " matches); stereo.row_offset_px " + applied + "\n";
  return fmt("row offset (features): y_left - y_right %+.2f px, spread %.2f px, ", o.offset_px,
             o.spread_px) +
         std::to_string(o.inliers) + " of " + std::to_string(o.matches) + " matches in " +
         std::to_string(o.frames) + " frames; after stereo.row_offset_px " + applied + "\n";
}

/// The search against the image: the columns a block matcher leaves without disparity.
void add_search_fit_problems(PreflightReport& r, const Config& config, const cv::Rect& region,
                             const PreflightLimits& limits) {
  const int blank = r.search_min_disparity + r.search_num_disparities;
  if (region.width <= 0) return;
  const double span = std::clamp(static_cast<double>(blank - region.x) / region.width, 0.0, 1.0);
  r.blanked_share = r.matches_left_border ? 0.0 : span;
  if (span <= limits.max_blanked_share) return;
  const std::string fix = "lower stereo.num_disparities (the config may be for larger images" +
                          std::string(config.stereo.num_disparities >= r.calibration.image.width / 2
                                          ? ", e.g. full-resolution ones)"
                                          : ")");
  if (r.matches_left_border)
    r.problems.push_back(fmt("the disparity search [%.0f, %.0f) px spans ", r.search_min_disparity,
                             blank) +
                         fmt("%.0f %% of the %.0f px wide image (> %.0f %%): every pixel is "
                             "searched that far, at that cost, and far nearer than the ground: ",
                             100 * span, r.calibration.image.width, 100 * limits.max_blanked_share) +
                         fix);
  else
    r.problems.push_back(fmt("the disparity search [%.0f, %.0f) px leaves the leftmost %.0f px, "
                             "",
                             r.search_min_disparity, blank, blank) +
                         fmt("%.0f %% of the %.0f px wide image, without disparity (> %.0f %%): ",
                             100 * r.blanked_share, r.calibration.image.width,
                             100 * limits.max_blanked_share) +
                         fix);
}

/// The body frame against the ground, where the config takes z_B = 0 as the ground under
/// the wheels (the below-ground check, the ground band): a body origin far from the
/// fitted ground, or z_B tilted from its normal beyond max_slope_deg, puts that plane
/// elsewhere.
void add_body_frame_problems(PreflightReport& r, const Config& config,
                             const std::vector<double>& body_h, const std::vector<double>& tilt_b,
                             const PreflightLimits& limits) {
  const bool uses_wheel_plane = config.stereo.max_below_ground_m > 0 ||
                                config.stereo.search == DisparitySearch::ground_band;
  if (!uses_wheel_plane) return;
  const std::string why = std::string("the config takes z_B = 0 as the ground under the wheels (") +
                          (config.stereo.max_below_ground_m > 0 ? "stereo.max_below_ground"
                                                                : "stereo.search: ground_band") +
                          ")";
  const double h = median(body_h), tilt = median(tilt_b);
  if (std::abs(h) > limits.max_body_height_m)
    r.problems.push_back(fmt("the body origin is %.2f m ", std::abs(h)) +
                         (h > 0 ? "above" : "below") +
                         fmt(" the ground fitted to the points (more than %.2f m), but ",
                             limits.max_body_height_m) +
                         why + ": put B's origin on the ground (T_body_left's z is the camera's "
                               "height), or for a body frame elsewhere (an IMU) set "
                               "stereo.max_below_ground: 0 and stereo.search: full "
                               "(docs/conventions.md)");
  if (tilt > config.hazard.max_slope_deg)
    r.problems.push_back(fmt("the ground fitted to the points is tilted %.1f deg from the body's "
                             "x-y plane (more than hazard.max_slope_deg %.1f), but ",
                             tilt, config.hazard.max_slope_deg) +
                         why + ": z_B is not up; check T_body_left's rotation and the poses' body "
                               "frame (docs/conventions.md)");
}

void add_problems(PreflightReport& r, const Config& config, const PreflightLimits& limits) {
  auto& out = r.problems;
  const CalibrationCheck& c = r.calibration;
  if (c.rectified_share < limits.min_rectified_share)
    out.push_back(fmt("rectification keeps %.0f %% of the image (< %.0f %%): check the "
                      "calibration's D and R, or stereo.alpha",
                      100 * c.rectified_share, 100 * limits.min_rectified_share));
  if (c.rows.found && c.rows.rms_px > limits.max_row_error_rms_px)
    out.push_back(fmt("rectified rows disagree by %.2f px RMS (max %.2f px) on the chessboard "
                      "(> %.2f px): the calibration's R, T or intrinsics do not fit these cameras",
                      c.rows.rms_px, c.rows.max_px, limits.max_row_error_rms_px));
  if (const std::string p = row_offset_problem(c.row_offset, limits.max_row_offset_px); !p.empty())
    out.push_back(p);
  if (r.frames.empty()) return;

  std::vector<double> valid, below, tilt_w, tilt_b, body_h, near_d, near_disp, near_pt;
  bool any_ground = false;
  for (const FrameCheck& f : r.frames) {
    valid.push_back(f.valid_disparity_share);
    const double all = static_cast<double>(f.points + f.points_below_ground);
    below.push_back(all > 0 ? static_cast<double>(f.points_below_ground) / all : 0.0);
    tilt_w.push_back(f.tilt_w_deg);
    tilt_b.push_back(f.tilt_body_deg);
    body_h.push_back(f.body_height_m);
    near_d.push_back(f.nearest_ground_depth_m);
    near_disp.push_back(f.nearest_ground_disparity_px);
    near_pt.push_back(f.nearest_point_distance_m);
    any_ground = any_ground || f.ground.found;
  }
  const double valid_m = median(valid);
  if (valid_m < limits.min_valid_disparity_share)
    out.push_back(fmt("only %.1f %% of the pixels get a disparity (< %.0f %%): too little "
                      "texture, or the search range misses the scene (stereo.num_disparities)",
                      100 * valid_m, 100 * limits.min_valid_disparity_share));
  const double below_m = median(below);
  if (below_m > limits.max_below_ground_share)
    out.push_back(fmt("%.0f %% of the points lie below the wheel plane z_B = 0 and are dropped "
                      "(stereo.max_below_ground): the body origin is not on the ground, or "
                      "T_body_left or the poses use another convention (docs/conventions.md)",
                      100 * below_m));
  if (!any_ground) {
    out.push_back("no plane holds enough of the points to be the ground: camera height and "
                  "tilt not measured");
  } else {
    const std::string tilt =
        ground_tilt_problem(median(tilt_w), median(tilt_b), config.hazard.max_slope_deg);
    std::string hint;
    for (const FrameCheck& f : r.frames)
      if (hint.empty()) hint = f.scalar_first_hint;
    if (!tilt.empty()) out.push_back(tilt + hint);
    add_body_frame_problems(r, config, body_h, tilt_b, limits);
  }

  // Ground nearer than the search reaches gives no points: a problem when that strip is
  // inside the finest layer's window, where the map wants it.
  const double d_max = r.search_min_disparity + r.search_num_disparities;
  const double z_near = std::max(r.z_min_m, r.calibration.focal_px * r.calibration.baseline_m / d_max);
  const double depth_m = median(near_d);
  if (!config.map.layers.empty() && depth_m < z_near) {
    const auto& l0 = config.map.layers[0];
    const bool by_z_min = r.z_min_m >= r.calibration.focal_px * r.calibration.baseline_m / d_max;
    out.push_back(fmt("the nearest ground in view is %.2f m deep (disparity %.0f px), but ",
                      depth_m, median(near_disp)) +
                  (by_z_min ? fmt("stereo.z_min is %.2f m", r.z_min_m)
                            : fmt("the search stops at %.0f px", d_max)) +
                  fmt(": ground nearer than %.2f m gives no points (layer 0's window reaches "
                      "%.2f m from the body; ",
                      z_near, 0.5 * l0.size * l0.resolution_m) +
                  (by_z_min ? "lower stereo.z_min)"
                            : "raise stereo.num_disparities or use stereo.search: ground_band)"));
  }

  for (size_t i = 0; i < config.map.layers.size(); ++i) {
    double best = 0.0;
    for (const FrameCheck& f : r.frames) best = std::max(best, f.layer_share[i]);
    if (best >= limits.min_layer_share) continue;
    const auto& l = config.map.layers[i];
    const double nearest = median(near_pt);
    out.push_back((best > 0 ? fmt("only %.3f %% of the points land in layer ", 100 * best)
                            : std::string("no point lands in layer ")) +
                  std::to_string(i) +
                  fmt(": its window is %.2f m (%.0f cells of %.3f m) around the body, ",
                      l.size * l.resolution_m, l.size, l.resolution_m) +
                  (std::isnan(nearest) ? std::string("and no frame gave a point")
                                       : fmt("the nearest points are %.2f m away", nearest)) +
                  " (map.layers." + std::to_string(i) + ".size)");
  }
}

}  // namespace

std::string ground_tilt_problem(double tilt_w_deg, double tilt_body_deg, double max_slope_deg) {
  if (!(tilt_w_deg > max_slope_deg)) return {};
  return fmt("the ground fitted to the points is tilted %.1f deg in W (%.1f deg in the body "
             "frame), more than hazard.max_slope_deg %.1f: level ground would map as slope; "
             "check the poses' and T_body_left's convention (docs/conventions.md)",
             tilt_w_deg, tilt_body_deg, max_slope_deg);
}

PreflightReport preflight_check(const Config& config, const Sequence& sequence,
                                const PreflightOptions& options, const PreflightLimits& limits) {
  PreflightReport report;
  report.sequence_dir = sequence.dir.string();
  const std::vector<SequenceFrame> selected =
      options.frames.empty() ? sequence.frames : select_frames(sequence.frames, options.frames);
  report.frames_selected = static_cast<int>(selected.size());
  std::vector<SequenceFrame> frames;
  const int n = static_cast<int>(selected.size());
  const int take = std::min(n, std::max(1, options.max_frames));
  for (int k = 0; k < take; ++k)
    frames.push_back(selected[static_cast<size_t>(take == 1 ? 0 : k * (n - 1) / (take - 1))]);
  check_frame_images(frames, sequence.calibration);
  // The geometry guards of `hazmap run`: here problems and warnings, not a stop.
  for (const RigFinding& f : check_rig_geometry(sequence, frames))
    (f.error ? report.problems : report.warnings).push_back(f.message);

  StereoFrontEnd front(config.stereo, config.sensor, sequence.calibration, /*keep_pixels=*/false);
  CalibrationCheck& c = report.calibration;
  c.image = front.rectifier().image_size();
  c.focal_px = front.rectifier().geometry().focal_px;
  c.baseline_m = front.rectifier().geometry().baseline_m;
  const cv::Rect both = front.rectifier().valid_roi() & front.rectifier().valid_roi_right();
  c.rectified_share = c.image.area() > 0 ? static_cast<double>(both.area()) / c.image.area() : 0;
  report.z_min_m = config.stereo.z_min_m;

  const std::vector<cv::Size> boards =
      options.boards.empty() ? std::vector<cv::Size>(std::begin(kCommonBoards), std::end(kCommonBoards))
                             : options.boards;
  std::vector<double> dv;
  std::vector<RowOffsetEstimate> row_offsets;
  for (const SequenceFrame& f : frames) {
    report.frames.push_back(check_frame(front, f, config, sequence.calibration));
    add_row_offset(front, row_offsets);
    // Looking for a board costs more than the frame's stereo: without a named board the
    // common ones are tried on the first frame only, later frames look for the one found.
    const bool first = report.frames.size() == 1;
    if (options.boards.empty() && !first && !c.rows.found) continue;
    for (const cv::Size& b : boards) {
      if (c.rows.found && b != c.rows.board) continue;  // one board per sequence
      if (add_row_errors(front.rectified_left(), front.rectified_right(), b, dv)) {
        c.rows.found = true;
        c.rows.board = b;
        ++c.rows.pairs;
        break;
      }
    }
  }
  c.row_offset = summarise_row_offsets(row_offsets, front, config);
  report.matches_left_border = matches_left_columns(config.stereo);
  report.search_min_disparity = front.matcher().min_disparity();
  report.search_num_disparities = front.matcher().num_disparities();
  if (!dv.empty()) {
    double ss = 0;
    for (double x : dv) {
      ss += x * x;
      c.rows.max_px = std::max(c.rows.max_px, std::abs(x));
    }
    c.rows.rms_px = std::sqrt(ss / static_cast<double>(dv.size()));
  }
  add_search_fit_problems(report, config, front.builder().region(), limits);
  add_problems(report, config, limits);
  return report;
}

std::string format_report(const PreflightReport& r) {
  std::string s;
  const CalibrationCheck& c = r.calibration;
  s += "sequence " + r.sequence_dir + ": " + std::to_string(r.frames.size()) + " of " +
       std::to_string(r.frames_selected) + " frames checked\n";
  s += fmt("calibration: %.0f x %.0f px, rectified f %.1f px, baseline %.4f m", c.image.width,
           c.image.height, c.focal_px, c.baseline_m) +
       fmt(", valid rectified region %.0f %% of the image\n", 100 * c.rectified_share);
  if (c.rows.found)
    s += fmt("rectification: chessboard %.0fx%.0f in %.0f pairs, row error %.2f px RMS", c.rows.board.width,
             c.rows.board.height, c.rows.pairs, c.rows.rms_px) +
         fmt(" (max %.2f px)\n", c.rows.max_px);
  else
    s += "rectification: no chessboard in view, row error not measured\n";
  s += format_row_offset(c.row_offset);
  s += fmt("disparity search: [%.0f, %.0f) px, ", r.search_min_disparity,
           r.search_min_disparity + r.search_num_disparities) +
       (r.matches_left_border
            ? std::string("the leftmost columns matched too (c2f or stereo.match_left_border)")
            : fmt("no disparity in the leftmost %.0f %% of the image", 100 * r.blanked_share)) +
       fmt("; z_min %.2f m\n", r.z_min_m);
  s += "frame         valid  points  below   ground  tilt W  tilt B  cam h   body h  "
       "near ground (m, px)  near pt  in layer windows\n";
  for (const FrameCheck& f : r.frames) {
    char line[512];
    const double all = static_cast<double>(f.points + f.points_below_ground);
    std::snprintf(line, sizeof line,
                  "%-12s %5.1f%% %7zu %5.1f%%  %5.1f%%  %5.1f   %5.1f   %6.3f  %6.3f  %5.2f %6.1f     %6.2f   ",
                  f.name.c_str(), 100 * f.valid_disparity_share, f.points,
                  all > 0 ? 100 * static_cast<double>(f.points_below_ground) / all : 0.0,
                  f.ground.found ? 100 * f.ground.inlier_share : 0.0, f.tilt_w_deg, f.tilt_body_deg,
                  f.camera_height_m, f.body_height_m, f.nearest_ground_distance_m,
                  f.nearest_ground_disparity_px, f.nearest_point_distance_m);
    // What was not measured (no ground plane, no point) reads "-", not "nan".
    std::string text = line;
    for (std::size_t at; (at = text.find("nan")) != std::string::npos;) text.replace(at, 3, "  -");
    s += text;
    for (size_t i = 0; i < f.layer_share.size(); ++i)
      s += (i ? " L" : "L") + std::to_string(i) + fmt(" %.1f%%", 100 * f.layer_share[i]);
    s += "\n";
  }
  s += "  (valid: pixels with a disparity; below: points under the wheel plane, dropped; "
       "ground: points on the fitted plane; cam h / body h: left camera and body origin above it)\n";
  for (const std::string& w : r.warnings) s += "warning: " + w + "\n";
  if (r.problems.empty()) {
    s += "verdict: OK\n";
  } else {
    s += "verdict: " + std::to_string(r.problems.size()) +
         (r.problems.size() == 1 ? " problem\n" : " problems\n");
    for (const std::string& p : r.problems) s += "  - " + p + "\n";
  }
  return s;
}

}  // namespace hazmap
