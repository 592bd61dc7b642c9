// hazmap import-euroc: convert an ASL/EuRoC sequence to our layout.

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <vector>

#include <spdlog/spdlog.h>

#include "cli.hpp"
#include "hazmap/io/euroc.hpp"

namespace hazmap::cli {

namespace {
const char* kImportUsage =
    R"(usage: hazmap import-euroc SRC DST [--poses CSV] [--pose-frame body|left_camera]
                           [--identity-poses] [--max-pose-gap SECONDS] [--quiet]

Converts an ASL/EuRoC folder (SRC/mav0/cam0|cam1/data/*.png with Kalibr-style
sensor.yaml) into hazmap's sequence layout in DST: left/, right/ (images copied as they
are: raw, distorted), calibration.yaml (from the sensor.yaml intrinsics, distortion and
T_BS; the body frame is EuRoC's IMU frame) and poses.txt. Frames without a pose are
left out. ('hazmap stereo' also reads EuRoC folders directly.)
  --poses CSV        "t_ns, x, y, z, qw, qx, qy, qz[, ...]" poses; default
                     SRC/mav0/state_groundtruth_estimate0/data.csv
  --pose-frame F     what the CSV poses are: body (default) or left_camera (cam0)
  --identity-poses   no pose file: put every frame at the identity
  --max-pose-gap S   interpolate between pose samples at most S seconds apart (0.1)
  --quiet            no summary line (errors and warnings still print)
)";
}  // namespace

int cmd_import_euroc(int argc, char** argv) {
  if (wants_help(argc, argv)) {
    std::fputs(kImportUsage, stdout);
    return kExitOk;
  }
  std::vector<std::string> positional;
  const Args args = parse_args(argc, argv, {"poses", "pose-frame", "max-pose-gap"},
                               {"identity-poses", "quiet"}, &positional);
  if (positional.size() != 2) throw UsageError("import-euroc needs SRC and DST");
  hazmap::EurocOptions options = euroc_options(args);
  options.identity_poses = args.on("identity-poses");
  setup_logging("", args.on("quiet"));
  const size_t frames = hazmap::import_euroc(positional[0], positional[1], options);
  spdlog::info("imported {} frames into {}", frames, positional[1]);
  return kExitOk;
}

}  // namespace hazmap::cli
