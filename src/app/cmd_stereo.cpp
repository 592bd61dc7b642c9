// hazmap stereo: rectified images, disparity and point clouds per frame.

#include <cstdio>

#include "cli.hpp"

namespace hazmap::cli {

int cmd_stereo(int /*argc*/, char** argv) {
  std::fprintf(stderr, "hazmap: '%s' is not implemented yet\n", argv[1]);
  return kExitUsage;
}

}  // namespace hazmap::cli
