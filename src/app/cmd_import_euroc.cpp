// hazmap import-euroc: convert an ASL/EuRoC sequence to our layout.

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <vector>

#include <spdlog/spdlog.h>

#include "cli.hpp"
#include "hazmap/io/euroc.hpp"
#include "hazmap/io/output_folder.hpp"

namespace hazmap::cli {

namespace {
const char* kImportUsage =
    R"(usage: hazmap import-euroc SRC DST [--poses CSV] [--pose-frame body|left_camera]
                           [--identity-poses] [--max-pose-gap SECONDS] [--overwrite]
                           [--quiet]

Converts an ASL/EuRoC folder (SRC/mav0/cam0|cam1/data/*.png with Kalibr-style
sensor.yaml) into hazmap's sequence layout in DST: left/, right/ (images copied as they
are: raw, distorted), calibration.yaml (from the sensor.yaml intrinsics, distortion and
T_BS; the body frame is EuRoC's IMU frame) and poses.txt. Frames without a pose are
left out. ('hazmap stereo' also reads EuRoC folders directly.) DST must be absent or
empty, so that the frames of two imports never mix.
  --poses CSV        "t_ns, x, y, z, qw, qx, qy, qz[, ...]" poses; default
                     SRC/mav0/state_groundtruth_estimate0/data.csv
  --pose-frame F     what the CSV poses are: body (default) or left_camera (cam0)
  --identity-poses   no pose file: put every frame at the identity
  --max-pose-gap S   interpolate between pose samples at most S seconds apart (0.1)
  --overwrite        DST may hold an earlier import: left/, right/, calibration.yaml and
                     a poses.txt saying "imported from EuRoC". They are removed (after SRC
                     is read and checked) before the first file is written. A folder
                     holding anything else is refused, with or without --overwrite, and
                     left untouched.
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
                               {"identity-poses", "overwrite", "quiet"}, &positional);
  if (positional.size() != 2) throw UsageError("import-euroc needs SRC and DST");
  hazmap::EurocOptions options = euroc_options(args);
  options.identity_poses = args.on("identity-poses");
  // The rule of hazmap run's OUT, for what import-euroc writes: a stale frame of an
  // earlier import would become a frame of this one (left/ and right/ are listed).
  const hazmap::OutputFolder dst =
      hazmap::inspect_output_folder(positional[1], hazmap::OutputOwner::import_euroc);
  const std::string refusal = hazmap::output_folder_refusal(dst, args.on("overwrite"));
  if (!refusal.empty()) throw UsageError(refusal);
  setup_logging("", args.on("quiet"));
  const size_t frames = hazmap::import_euroc(
      positional[0], positional[1], options,
      [&] { hazmap::clear_output_folder(dst); });  // SRC read and checked
  spdlog::info("imported {} frames into {}", frames, positional[1]);
  return kExitOk;
}

}  // namespace hazmap::cli
