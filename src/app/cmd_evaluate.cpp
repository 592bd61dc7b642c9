// hazmap evaluate: score a run against ground truth.

#include <cstdio>

#include "cli.hpp"

namespace hazmap::cli {

int cmd_evaluate(int /*argc*/, char** argv) {
  std::fprintf(stderr, "hazmap: '%s' is not implemented yet\n", argv[1]);
  return kExitUsage;
}

}  // namespace hazmap::cli
