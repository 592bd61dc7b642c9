// hazmap calibrate: stereo calibration from chessboard pairs.

#include <cstdio>

#include "cli.hpp"

namespace hazmap::cli {

int cmd_calibrate(int /*argc*/, char** argv) {
  std::fprintf(stderr, "hazmap: '%s' is not implemented yet\n", argv[1]);
  return kExitUsage;
}

}  // namespace hazmap::cli
