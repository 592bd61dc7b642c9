// hazmap import-euroc: convert an ASL/EuRoC sequence to our layout.

#include <cstdio>

#include "cli.hpp"

namespace hazmap::cli {

int cmd_import_euroc(int /*argc*/, char** argv) {
  std::fprintf(stderr, "hazmap: '%s' is not implemented yet\n", argv[1]);
  return kExitUsage;
}

}  // namespace hazmap::cli
