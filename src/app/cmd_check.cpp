// hazmap check: a pre-flight report on a few frames, no map written.

#include <cstdio>

#include "cli.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/pipeline/preflight_check.hpp"

namespace hazmap::cli {

namespace {
const char* kCheckUsage = R"(usage: hazmap check --config FILE --sequence DIR [--frames A:B] [--count N]
                    [--board WxH] [--set KEY=VALUE]... [--quiet]
                    [--poses CSV] [--pose-frame body|left_camera] [--max-pose-gap SECONDS]

A pre-flight report on new data: runs the stereo front end of `hazmap run` on --count
frames (5) spread over --frames and writes nothing. It reports the calibration (rectified
focal length, baseline, valid region, and the row error of a chessboard if one is in
view), the disparity search against the nearest ground in view, the share of pixels with
a disparity, the ground plane fitted to each frame's points (its tilt in W and in the
body frame, the camera's and the body origin's height above it) and the share of points
inside each layer's window. It ends with a verdict: OK, or one line per problem.
DIR may be an ASL/EuRoC folder, read as `hazmap run` reads it.
  --frames A:B   frames [A, B) of the sorted frames (as in run)
  --count N      frames checked, spread evenly over the selection (1..1000, default 5)
  --board WxH    inner corners of a chessboard to look for in every frame (default: the
                 common boards 9x6, 8x6, 7x6, ... in the first frame checked)
  --set K=V      override a YAML key, as in run
  --quiet        no log lines (the report itself is still printed)
Before the frames it applies the geometry guards of `hazmap run` (baseline, focal length,
the camera's mounting and the first pose): what would stop a run is a problem here,
what a run would warn about a warning line.
Exit code: 0 when the verdict is OK, 1 when it lists problems (or on bad input).
)";

cv::Size parse_board(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') ||
      w < 2 || h < 2 || w > 100 || h > 100)
    throw UsageError("--board " + text + ": expected inner corners as WxH, e.g. 9x6");
  return {w, h};
}
}  // namespace

int cmd_check(int argc, char** argv) {
  if (wants_help(argc, argv)) {
    std::fputs(kCheckUsage, stdout);
    return kExitOk;
  }
  const Args args = parse_args(argc, argv,
                               {"config", "sequence", "frames", "count", "board", "poses",
                                "pose-frame", "max-pose-gap"},
                               {"quiet"});
  hazmap::PreflightOptions options;
  options.frames = args.get("frames");
  if (args.has("count")) options.max_frames = static_cast<int>(args.whole("count", 1, 1000));
  if (args.has("board")) options.boards.push_back(parse_board(args.get("board")));
  const hazmap::Config config = hazmap::load_config(args.required("config"), args.sets);
  setup_logging("", args.on("quiet"));
  const hazmap::Sequence sequence = load_any_sequence(args.required("sequence"), args);
  hazmap::PreflightReport report = hazmap::preflight_check(config, sequence, options);
  report.config_path = args.required("config");
  std::printf("hazmap check: config %s\n%s", report.config_path.c_str(),
              hazmap::format_report(report).c_str());
  return report.problems.empty() ? kExitOk : kExitError;
}

}  // namespace hazmap::cli
