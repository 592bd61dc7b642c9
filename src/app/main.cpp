// hazmap: the command-line front end. Thin by design: it dispatches to a subcommand
// (cmd_<name>.cpp) and turns library errors into one line on stderr and an exit code.

#include <cstdio>
#include <cstring>
#include <new>
#include <string>

#include <opencv2/core.hpp>

#include "cli.hpp"
#include "hazmap/core/error.hpp"

namespace {

using hazmap::cli::kExitError;
using hazmap::cli::kExitUsage;

struct Command {
  const char* name;
  int (*run)(int, char**);
  const char* synopsis;
};

const Command kCommands[] = {
    {"run", hazmap::cli::cmd_run,
     "--config FILE --sequence DIR --out DIR [--frames A:B] [--set KEY=VALUE]... [--overwrite]\n"
     "                      [--quiet]"},
    {"check", hazmap::cli::cmd_check,
     "--config FILE --sequence DIR [--frames A:B] [--count N]   pre-flight report, no map"},
    {"stereo", hazmap::cli::cmd_stereo,
     "--config FILE --sequence DIR --out DIR [--frames A:B]   rectified PNGs, disparity, PLY"},
    {"simulate", hazmap::cli::cmd_simulate,
     "--scenario NAME --out DIR [--seed N] [--frames N] [...]   synthetic sequence + ground truth"},
    {"evaluate", hazmap::cli::cmd_evaluate,
     "--run DIR --sequence DIR [--out DIR]   metrics against ground truth"},
    {"calibrate", hazmap::cli::cmd_calibrate,
     "--images DIR --board 9x6 --square 0.025 --out calibration.yaml"},
    {"import-euroc", hazmap::cli::cmd_import_euroc, "SRC DST   ASL/EuRoC folder to our layout"},
    {"ground-truth", hazmap::cli::cmd_ground_truth,
     "--cloud FILE --out DIR [--resolution R]   laser scan -> gt_height/gt_hazard"},
    {"view", hazmap::cli::cmd_view, "RUN [--out FILE]   static HTML page to look at a run (RUN/view.html)"},
    {"bench", hazmap::cli::cmd_bench,
     "[--config FILE] [--sequence DIR] [--frames N] [--repetitions R]   frame timing vs StereoBM"},
};

void print_usage(FILE* out) {
  std::fputs("hazmap: stereo-to-hazard terrain mapping for small planetary rovers\n\nusage:\n", out);
  for (const Command& c : kCommands) std::fprintf(out, "  hazmap %-12s %s\n", c.name, c.synopsis);
  std::fputs("  hazmap --help | --version\n\n'hazmap COMMAND --help' describes a command.\n", out);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    print_usage(stderr);
    return kExitUsage;
  }
  const std::string command = argv[1];
  try {
    if (command == "--help" || command == "-h" || command == "help") {
      print_usage(stdout);
      return 0;
    }
    if (command == "--version") {
      std::printf("hazmap %s\n", HAZMAP_VERSION);
      return 0;
    }
    for (const Command& c : kCommands)
      if (command == c.name) return c.run(argc, argv);
    throw hazmap::cli::UsageError("unknown command '" + command + "'");
  } catch (const hazmap::cli::UsageError& e) {
    std::fprintf(stderr, "hazmap: %s (see hazmap --help)\n", e.what());
    return kExitUsage;
  } catch (const std::bad_alloc&) {
    // Inputs are checked for plausible sizes before allocating; this is the backstop.
    const char* what = "out of memory (an input asks for more than this machine holds)";
    hazmap::cli::log_to_file_only(what, true);
    std::fprintf(stderr, "hazmap: error: %s\n", what);
    return kExitError;
  } catch (const cv::Exception& e) {
    // cv::Exception::what() spans lines; its err field is the one-line reason.
    const std::string what = "OpenCV: " + e.err + " (in " + e.func + ")";
    hazmap::cli::log_to_file_only(what, true);
    std::fprintf(stderr, "hazmap: error: %s\n", what.c_str());
    return kExitError;
  } catch (const std::exception& e) {
    hazmap::cli::log_to_file_only(e.what(), true);
    std::fprintf(stderr, "hazmap: error: %s\n", e.what());
    return kExitError;
  }
}
