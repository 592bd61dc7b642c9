// hazmap calibrate: stereo calibration from chessboard pairs.

#include <cstdio>
#include <cstdlib>

#include <spdlog/spdlog.h>

#include "cli.hpp"
#include "hazmap/camera/chessboard_calibration.hpp"
#include "hazmap/camera/rectifier.hpp"
#include "hazmap/io/calibration_file.hpp"
#include "hazmap/io/chessboard_pairs.hpp"

namespace hazmap::cli {

namespace {
const char* kCalibrateUsage =
    R"(usage: hazmap calibrate --images DIR --board WxH --square METRES --out FILE
                        [--alpha A] [--quiet]

Stereo calibration from chessboard image pairs: DIR/left/<name>.<ext> with
DIR/right/<name>.<ext>, or DIR/left<tag>.<ext> with DIR/right<tag>.<ext> (png, jpg, ...).
Detects the board (cv::findChessboardCorners + cv::cornerSubPix), calibrates each camera,
then both together (cv::stereoCalibrate, 5-parameter distortion), and writes FILE in
hazmap's calibration.yaml format (T_body_left = identity: edit it for your rover).
Prints the RMS reprojection error, the baseline, and how well the calibration puts
the detected corners of each pair on one row after rectification.
  --board WxH    inner corners per row x per column, e.g. 9x6
  --square M     side of a square in metres, e.g. 0.025 (sets the unit of T)
  --alpha A      cv::stereoRectify alpha for the row check (default 0)
  --quiet        only the result lines
)";

cv::Size parse_board(const std::string& text) {
  const auto x = text.find('x');
  // Each part is kept in a named string: strtol's end pointer must point into storage
  // that is still alive when *end is read (a temporary's c_str() was dead by then).
  const std::string w_text = x == std::string::npos ? std::string() : text.substr(0, x);
  const std::string h_text = x == std::string::npos ? std::string() : text.substr(x + 1);
  char* end1 = nullptr;
  char* end2 = nullptr;
  const long w = std::strtol(w_text.c_str(), &end1, 10);
  const long h = std::strtol(h_text.c_str(), &end2, 10);
  if (x == std::string::npos || w_text.empty() || h_text.empty() || *end1 != '\0' ||
      *end2 != '\0' || w < 2 || h < 2 || w > 100 || h > 100)
    throw UsageError("--board " + text + ": expected inner corners as WxH, e.g. 9x6");
  return {static_cast<int>(w), static_cast<int>(h)};
}

}  // namespace

int cmd_calibrate(int argc, char** argv) {
  if (wants_help(argc, argv)) {
    std::fputs(kCalibrateUsage, stdout);
    return kExitOk;
  }
  const Args args = parse_args(argc, argv, {"images", "board", "square", "out", "alpha"}, {"quiet"});
  hazmap::ChessboardOptions options;
  options.inner_corners = parse_board(args.required("board"));
  options.square_m = args.number("square");
  if (!(options.square_m > 0)) throw UsageError("--square must be > 0 (metres)");
  const double alpha = args.has("alpha") ? args.number("alpha") : 0.0;
  const std::filesystem::path images = args.required("images");
  const std::filesystem::path out = args.required("out");
  setup_logging("", args.on("quiet"));

  const hazmap::ChessboardCalibration result = hazmap::calibrate_chessboard_pairs(images, options);
  const hazmap::StereoCalibration& c = result.calibration;
  const hazmap::Rectifier rectifier(c, alpha);
  const hazmap::RowAlignment rows = hazmap::measure_row_alignment(rectifier, result.views);
  for (size_t i = 0; i < result.views.size(); ++i)
    spdlog::info("pair {}: RMS {:.3f} px", result.views[i].name, result.view_rms_px[i]);
  for (const auto& name : result.rejected) spdlog::info("pair {}: board not found, not used", name);

  char summary[512];
  std::snprintf(summary, sizeof summary,
                "pairs used: %zu of %zu\n"
                "RMS reprojection error: %.3f px\n"
                "baseline: %.5f m (T = [%.5f, %.5f, %.5f] m)\n"
                "rectified (alpha %g): f = %.2f px; corner rows |dy|: mean %.3f px, "
                "99th percentile %.3f px, max %.3f px over %zu corners\n",
                result.views.size(), result.views.size() + result.rejected.size(), result.rms_px,
                c.T.norm(), c.T.x(), c.T.y(), c.T.z(), alpha, rectifier.geometry().focal_px,
                rows.mean_abs_dy_px, rows.p99_abs_dy_px, rows.max_abs_dy_px, rows.points);
  hazmap::save_stereo_calibration(
      out, c,
      std::string("hazmap calibrate --images ") + images.string() + " --board " +
          args.get("board") + " --square " + args.get("square") + "\n" + summary);
  std::fputs(summary, stdout);
  std::printf("wrote %s\n", out.string().c_str());
  return kExitOk;
}

}  // namespace hazmap::cli
