// hazmap run: map a stereo sequence.

#include <atomic>
#include <csignal>
#include <cstdio>

#include <signal.h>

#include <spdlog/spdlog.h>

#include "cli.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/io/euroc.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/io/output_folder.hpp"
#include "hazmap/io/run_layout.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/pipeline/sequence_runner.hpp"

namespace hazmap::cli {

namespace {
const char* kRunUsage = R"(usage: hazmap run --config FILE --sequence DIR --out DIR [--frames A:B]
                  [--set KEY=VALUE]... [--mosaic] [--overwrite] [--quiet]
                  [--poses CSV] [--pose-frame body|left_camera] [--max-pose-gap SECONDS]

Maps a stereo sequence (SEQ/left, SEQ/right, calibration.yaml, poses.txt) frame by frame.
DIR may also be an ASL/EuRoC folder (mav0/cam0, mav0/cam1), read directly as
`hazmap import-euroc` reads it: poses from --poses (EuRoC's CSV layout, of the body or of
the left camera per --pose-frame) or else mav0/state_groundtruth_estimate0; images
without a pose within --max-pose-gap (0.1 s) are left out.
Writes OUT/frames/<frame>/L<i>_{hazard,height}.png, L<i>_{height,variance,hazard}.jdem
(.tif with --set output.format=geotiff), fused_hazard.{png,jdem}, OUT/summary.json (once,
after the last frame; it records the sequence and a fingerprint of its poses, which
`hazmap evaluate` checks) and OUT/run.log. A writer thread writes the frames
(output.queue_frames); each frame folder appears complete or not at all. OUT must be
absent or empty, so that two runs' frames never mix. Every input, every frame's image
header included, is checked before anything is written or removed; a frame damaged
later stops the run with one line naming it, frames written before it stay complete and
no summary.json is written. SIGINT/SIGTERM stop the run after the frame in flight,
which is written.
  --frames A:B   frame indices [A, B) of the sorted frames (Python-like, negatives count
                 from the end)
  --set K=V      override a YAML key by dotted path, e.g. --set map.layers.0.size=64
  --mosaic       also write OUT/mosaic/<frame>.png: every layer side by side (a film)
  --overwrite    OUT may hold an earlier hazmap output: frames/, mosaic/, eval/,
                 summary.json, stereo_summary.json, run.log. They are removed (after every
                 input is checked) before the run starts. A folder holding anything else
                 is refused, with or without --overwrite, and left untouched.
  --quiet        no per-frame progress on the terminal

SIGINT or SIGTERM stops the run after the frame in flight: that frame is written, the
writer's queue flushed, one line says after which frame it stopped, and the exit code is
128 + the signal (130, 143). A second signal ends the process at once.
)";

/// Shell convention: a process ended by signal N exits with 128 + N.
constexpr int kExitSignalBase = 128;

std::atomic<int> g_stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "set from a signal handler");

extern "C" void request_stop(int signal_number) {
  g_stop_signal.store(signal_number);
  std::signal(signal_number, SIG_DFL);  // the second Ctrl-C is not ignored
}

void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = request_stop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // file writes in progress go on rather than fail with EINTR
  for (int s : {SIGINT, SIGTERM}) sigaction(s, &action, nullptr);
}

const char* signal_name(int s) { return s == SIGINT ? "SIGINT" : s == SIGTERM ? "SIGTERM" : "a signal"; }

}  // namespace

int cmd_run(int argc, char** argv) {
  if (wants_help(argc, argv)) {
    std::fputs(kRunUsage, stdout);
    return kExitOk;
  }
  const Args args = parse_args(argc, argv,
                               {"config", "sequence", "out", "frames", "poses", "pose-frame",
                                "max-pose-gap"},
                               {"quiet", "mosaic", "overwrite"});
  hazmap::RunOptions options;
  options.config_path = args.required("config");
  options.sequence_dir = args.required("sequence");
  options.out_dir = args.required("out");
  options.frames = args.get("frames");
  // A wrong OUT is a command-line mistake: said at once, before the inputs are loaded.
  const hazmap::OutputFolder out = hazmap::inspect_output_folder(options.out_dir);
  const std::string refusal = hazmap::output_folder_refusal(out, args.on("overwrite"));
  if (!refusal.empty()) throw UsageError(refusal);
  // Check every input before the first line is logged or written: a bad input gives
  // exactly one line on stderr and leaves OUT untouched.
  std::vector<std::string> sets = args.sets;
  if (args.on("mosaic")) sets.push_back("output.mosaic=true");
  const hazmap::Config config = hazmap::load_config(options.config_path, sets);
  setup_logging("", args.on("quiet"));  // the terminal only, until every check has passed
  const hazmap::Sequence sequence = load_any_sequence(options.sequence_dir, args);
  // Frame selection, every frame's image headers and the pipeline's constructors
  // (including the map's allocation) are checked here, still before run.log exists.
  install_stop_handlers();
  options.stop_signal = &g_stop_signal;
  hazmap::SequenceRun run(config, sequence, options);
  // Every check has passed: only now may an earlier output go (--overwrite).
  hazmap::clear_output_folder(out);
  setup_logging(options.out_dir / hazmap::run_layout::kRunLog, args.on("quiet"));
  spdlog::info("hazmap {} run: config {}, sequence {}, out {}", HAZMAP_VERSION,
               options.config_path.string(), options.sequence_dir.string(),
               options.out_dir.string());
  // The configuration as actually used goes to the log file, not the terminal.
  log_to_file_only("configuration in use:\n" + hazmap::to_yaml(config));
  const hazmap::RunResult result = run.run();
  if (result.stop_signal != 0) {
    const std::string line =
        std::string("stopped by ") + signal_name(result.stop_signal) +
        (result.stopped_after.empty() ? std::string(" before the first frame")
                                      : " after frame " + result.stopped_after) +
        " (" + std::to_string(result.frames_processed) + " frames processed, " +
        std::to_string(result.frames_written) + " written, all complete)";
    log_to_file_only(line, true);
    std::fprintf(stderr, "hazmap: %s\n", line.c_str());
    return kExitSignalBase + result.stop_signal;
  }
  spdlog::info("done: {} frames, {} points; wrote {} frame folders under {}",
               result.frames_processed, result.points_total, result.frames_written,
               (options.out_dir / hazmap::run_layout::kFramesDir).string());
  // The frames are written (all unknown), but a map without a point is a failed run.
  if (!result.no_points.empty()) throw hazmap::Error(result.no_points);
  return 0;
}

}  // namespace hazmap::cli
