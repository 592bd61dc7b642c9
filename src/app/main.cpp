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

// Every option of every command (the commands' own --help says what each does): option
// errors send the user here.
const Command kCommands[] = {
    {"run", hazmap::cli::cmd_run,
     "--config FILE --sequence DIR --out DIR [--frames A:B] [--set KEY=VALUE]...\n"
     "                      [--mosaic] [--overwrite] [--quiet] [--poses CSV]\n"
     "                      [--pose-frame body|left_camera] [--max-pose-gap SECONDS]\n"
     "                      map a sequence"},
    {"check", hazmap::cli::cmd_check,
     "--config FILE --sequence DIR [--frames A:B] [--count N] [--board WxH]\n"
     "                      [--set KEY=VALUE]... [--quiet] [--poses CSV]\n"
     "                      [--pose-frame body|left_camera] [--max-pose-gap SECONDS]\n"
     "                      pre-flight report, no map"},
    {"stereo", hazmap::cli::cmd_stereo,
     "--config FILE --sequence DIR --out DIR [--frames A:B] [--set KEY=VALUE]...\n"
     "                      [--overwrite] [--quiet] [--poses CSV]\n"
     "                      [--pose-frame body|left_camera] [--max-pose-gap SECONDS]\n"
     "                      rectified PNGs, disparity, PLY"},
    {"simulate", hazmap::cli::cmd_simulate,
     "--scenario NAME --out DIR [--seed N] [--frames N] [--scale S] [--step M]\n"
     "                      [--terrain-size M] [--ramp-deg D] [--sine-amplitude M]\n"
     "                      [--sine-wavelength M] [--sine-direction-deg D] [--noise-amplitude M]\n"
     "                      [--rock-count N|A:B] [--rock-density D] [--rock-radius R|A:B]\n"
     "                      [--rock-sizes S] [--rock-exponent Q] [--rock-box X0,X1,Y]\n"
     "                      [--rock-buried F] [--rock-clearance M] [--scatter-rocks]\n"
     "                      [--crater-count N|A:B] [--crater-density D] [--crater-radius R|A:B]\n"
     "                      [--crater-sizes S] [--crater-exponent Q] [--crater-box X0,X1,Y]\n"
     "                      [--crater-depth F] [--crater-rim F] [--path straight|spline]\n"
     "                      [--waypoint-spacing M] [--max-turn-deg D] [--wheelbase M] [--track M]\n"
     "                      [--drift F] [--drift-direction-deg D] [--distort]\n"
     "                      [--distortion K1,K2,P1,P2,K3] [--misalign] [--misalignment R,P,Y,X,Y,Z]\n"
     "                      [--samples N] [--noise-sigma DN] [--no-sun] [--ground-truth]\n"
     "                      [--sun-elevation-deg D] [--sun-azimuth-deg D] [--terrain-shadows]\n"
     "                      [--ambient A] [--opposition-surge S] [--opposition-width-deg D]\n"
     "                      [--lunar-polar-light] [--albedo regolith|value_noise]\n"
     "                      [--albedo-contrast C] [--albedo-correlation M] [--noise-octaves N]\n"
     "                      [--noise-gain G] [--noise-wavelength M] [--terrain-resolution M]\n"
     "                      [--gain V|L,R] [--exposure V|L,R] [--offset-dn V|L,R]\n"
     "                      [--electrons-per-dn E] [--vignetting V] [--bits 8|12]\n"
     "                      [--row-offset-px P] [--rig cadre|polar]\n"
     "                      [--gt-margin M] [--depth] [--overwrite] [--quiet]\n"
     "                      synthetic sequence + ground truth"},
    {"evaluate", hazmap::cli::cmd_evaluate,
     "--run DIR --sequence DIR [--out DIR] [--near R] [--error-maps NAME,...|all] [--quiet]\n"
     "                      | --sweep DIR [--out DIR] [--quiet]   metrics against ground truth"},
    {"calibrate", hazmap::cli::cmd_calibrate,
     "--images DIR --board WxH --square METRES --out FILE [--alpha A] [--quiet]\n"
     "                      chessboard stereo calibration"},
    {"import-euroc", hazmap::cli::cmd_import_euroc,
     "SRC DST [--poses CSV] [--pose-frame body|left_camera] [--identity-poses]\n"
     "                      [--max-pose-gap SECONDS] [--overwrite] [--quiet]\n"
     "                      ASL/EuRoC folder to our layout"},
    {"ground-truth", hazmap::cli::cmd_ground_truth,
     "--cloud FILE --out DIR [--resolution R] [--fill-radius M] [--ground-radius M]\n"
     "                      [--ground-tolerance M] [--crop X0,Y0,X1,Y1] [--quiet]\n"
     "                      laser scan -> gt_height/gt_hazard"},
    {"view", hazmap::cli::cmd_view,
     "RUN [--out FILE] [--quiet]   static HTML page to look at a run (RUN/view.html)"},
    {"bench", hazmap::cli::cmd_bench,
     "[--config FILE] [--sequence DIR] [--frames N] [--repetitions R] [--set KEY=VALUE]...\n"
     "                      [--quiet]   frame timing vs StereoBM"},
};

void print_usage(FILE* out) {
  std::fputs("hazmap: stereo-to-hazard terrain mapping for small planetary rovers\n\nusage:\n", out);
  for (const Command& c : kCommands) std::fprintf(out, "  hazmap %-12s %s\n", c.name, c.synopsis);
  std::fputs("  hazmap --help | --version\n\n'hazmap COMMAND --help' describes a command and each of "
             "its options.\nErrors: one line 'hazmap: error: ...' on stderr; exit 1 for bad "
             "input or a failed run,\n2 for a bad command line (with the command's --help "
             "named), 0 otherwise.\n", out);
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
    // One prefix for every error; usage errors point at the command's own help.
    bool known = false;
    for (const Command& c : kCommands) known = known || command == c.name;
    std::fprintf(stderr, "hazmap: error: %s (see hazmap %s--help)\n", e.what(),
                 known ? (command + " ").c_str() : "");
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
