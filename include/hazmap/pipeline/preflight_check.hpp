#pragma once
// `hazmap check`: a pre-flight report on a few frames of a sequence, without writing a
// map. It answers what a first run on new data usually gets wrong: a calibration that
// does not rectify (row error on a chessboard, if one is in view), a disparity search
// that misses the nearest ground, poses or T_body_left in the wrong convention (the
// ground fitted in W tilted, the body origin far from it), and layer windows the points
// never reach. Each problem becomes one line of the verdict.
// The same ground-tilt line is what `hazmap run` warns with (ground_tilt_problem()).

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "hazmap/io/config.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/stereo/ground_plane_fit.hpp"

namespace hazmap {

struct PreflightOptions {
  std::string frames;  ///< "A:B" of the sorted frames, "" for all
  int max_frames = 5;  ///< frames checked, spread evenly over the selection
  /// Inner-corner counts (columns x rows) of a chessboard to look for in the rectified
  /// pairs of every frame checked; empty: try the common boards (kCommonBoards in the
  /// .cpp) on the first frame, and later frames only for the board found there.
  std::vector<cv::Size> boards;
};

/// Thresholds of the verdict: what the report calls a problem.
struct PreflightLimits {
  /// Rectification: rows of the same chessboard corner in the two rectified images.
  double max_row_error_rms_px = 0.5;
  /// Share of the rectified image with valid source pixels in both cameras.
  double min_rectified_share = 0.5;
  /// Rectification: rows of the same feature in the two rectified images (median of
  /// y_left - y_right over feature matches, stereo/row_offset.hpp).
  double max_row_offset_px = 0.5;
  /// Share of pixels of the matched region with a valid disparity.
  double min_valid_disparity_share = 0.05;
  /// Share of points dropped as below the wheel plane (SPEC 3.3).
  double max_below_ground_share = 0.5;
  /// Share of the matched region's width the search leaves blank: block matchers give
  /// no disparity in the leftmost min_disparity + num_disparities columns.
  double max_blanked_share = 0.3;
  /// Body origin above (or below) the ground fitted to the points, when the config
  /// takes z_B = 0 as the ground (stereo.max_below_ground, search: ground_band).
  double max_body_height_m = 0.1;
  /// A layer whose window (and lateral gate) takes less than this share of a frame's
  /// points, in its best frame, maps nothing useful: a few points in a window's corner
  /// (measured: default.yaml on EuRoC, 0.01 %) may miss the run's cell-aligned window.
  double min_layer_share = 0.001;
};

struct RowErrorCheck {
  bool found = false;       ///< a chessboard was found in both images of some frame
  cv::Size board;           ///< its inner corners
  int pairs = 0;            ///< frames it was found in
  double rms_px = 0.0;      ///< RMS of v_left - v_right over all its corners
  double max_px = 0.0;
};

/// The rows of the rectified pairs compared through feature matches (no board needed),
/// after the configured stereo.row_offset_px has been applied.
struct RowOffsetCheck {
  int frames = 0;            ///< frames with an estimate
  int matches = 0;           ///< feature matches, summed over the frames
  int inliers = 0;           ///< of those, consistent with one offset per frame
  double offset_px = 0.0;    ///< median over the frames of y_left - y_right
  double spread_px = 0.0;    ///< median over the frames of the matches' robust spread
  double applied_px = 0.0;   ///< the offset the rectifier already applies
  bool automatic = false;    ///< applied_px was measured (`auto`)
};

struct CalibrationCheck {
  cv::Size image;
  double focal_px = 0.0;     ///< of the rectified pair
  double baseline_m = 0.0;
  double rectified_share = 1.0;  ///< valid rectified region / image area
  RowErrorCheck rows;
  RowOffsetCheck row_offset;
};

struct FrameCheck {
  std::string name;
  double valid_disparity_share = 0.0;  ///< of the pixels that may give points
  std::size_t points = 0;
  std::size_t points_below_ground = 0;  ///< dropped (SPEC 3.3), not in `points`
  GroundPlane ground;                   ///< fitted in W
  double tilt_w_deg = 0.0;       ///< ground normal against W's z
  double tilt_body_deg = 0.0;    ///< ground normal against the body's z
  double camera_height_m = 0.0;  ///< rectified left camera centre above the ground
  double body_height_m = 0.0;    ///< body origin above the ground (0 when B is on it)
  /// The nearest ground the left camera sees (its lowest valid row meeting the fitted
  /// plane, else the wheel plane): depth [m], disparity [px] and horizontal distance from
  /// the body origin [m]. NaN when no ray of that row meets it.
  double nearest_ground_depth_m = 0.0;
  double nearest_ground_disparity_px = 0.0;
  double nearest_ground_distance_m = 0.0;
  double nearest_point_distance_m = 0.0;  ///< horizontal, from the body origin; NaN: none
  std::vector<double> layer_share;  ///< share of points inside each layer's window
  std::string scalar_first_hint;    ///< scalar_first_hint() of the ground, "" if none
};

struct PreflightReport {
  std::string config_path, sequence_dir;
  int frames_selected = 0;
  CalibrationCheck calibration;
  int search_min_disparity = 0;  ///< the matcher's range [min, min + num)
  int search_num_disparities = 0;
  double z_min_m = 0.0;
  double blanked_share = 0.0;     ///< of the matched region's width, left blank by the search
  /// The matcher searches the leftmost columns too (c2f, or stereo.match_left_border):
  /// no band is blank by construction, but the search's span still costs time.
  bool matches_left_border = false;
  std::vector<FrameCheck> frames;
  std::vector<std::string> problems;  ///< one line each; empty: the verdict is OK
  std::vector<std::string> warnings;  ///< doubtful but possible (check_rig_geometry's)
};

/// Runs the stereo front end on up to options.max_frames frames and fills the report.
/// Throws Error on bad input (as `hazmap run` would).
PreflightReport preflight_check(const Config& config, const Sequence& sequence,
                                const PreflightOptions& options,
                                const PreflightLimits& limits = {});

/// The report as text: a calibration block, one line per frame, and the verdict.
std::string format_report(const PreflightReport& report);

/// The ground-tilt problem line (empty when fine): the ground fitted in W more than
/// hazard.max_slope_deg from level means a map whose level ground reads as slope.
std::string ground_tilt_problem(double tilt_w_deg, double tilt_body_deg, double max_slope_deg);

}  // namespace hazmap
