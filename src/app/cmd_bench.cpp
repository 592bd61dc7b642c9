// hazmap bench: the whole-frame benchmark of issue 20 (frame_bench.hpp) on a sequence
// folder, or on full-resolution frames it renders for the purpose.

#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <system_error>

#include <spdlog/spdlog.h>

#include "cli.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/pipeline/frame_bench.hpp"
#include "hazmap/sim/simulate.hpp"

namespace hazmap::cli {

namespace {
/// What the benchmark renders when it is given no sequence: the `rocks` scenario at
/// `scale` (1.0: full CADRE resolution), `frames` frames, into `out_dir`.
/// Returns the seconds spent rendering.
double render_bench_sequence(const std::filesystem::path& out_dir, int frames, double scale,
                             std::uint64_t seed) {
  sim::SimulationOptions options;
  options.scenario = "rocks";
  options.frames = frames;
  options.scale = scale;
  options.seed = seed;
  // The images are read once and decoded, never timed: fast PNG encoding saves seconds
  // of rendering at full resolution.
  options.png_compression = 1;
  return sim::simulate_sequence(options, out_dir).render_seconds;
}

const char* kBenchUsage =
    R"(usage: hazmap bench [--config FILE] [--sequence DIR] [--frames N] [--repetitions R]
                    [--set KEY=VALUE]... [--quiet]

Times the real per-frame pipeline (Pipeline::process: rectify, disparity, points, map,
hazard; images read into memory first, no file output) on the first N frames of a
sequence, R timed passes after one warm-up pass, and after each frame a bare full-range
cv::StereoBM (the config's num_disparities and block_size, OpenCV's defaults otherwise)
on the same rectified pair. Prints per-stage medians [ms], the frame's median and the
median ratio frame / StereoBM.
  --config FILE     default config/cadre_full_res.yaml
  --sequence DIR    a sequence folder (SPEC 2); default $HAZMAP_BENCH_SEQUENCE, else
                    N frames of the rocks scenario rendered at full CADRE resolution
                    (1600 x 1300) into a temporary folder, removed afterwards
  --frames N        frames to use (default 2)
  --repetitions R   timed passes over them (default 5)
  --set K=V         override a YAML key, e.g. --set stereo.search=ground_band
  --quiet           no progress lines; the table still prints (stdout)
)";

constexpr int kDefaultFrames = 2;
constexpr int kDefaultRepetitions = 5;
constexpr double kFullResolution = 1.0;  ///< CADRE's 1600 x 1300 (make_cadre_rig)
constexpr std::uint64_t kRenderSeed = 913;

int positive_int(const Args& args, const std::string& name, int fallback) {
  return args.has(name) ? static_cast<int>(args.whole(name, 1, 1000000)) : fallback;
}

/// A folder that removes itself.
struct ScratchDir {
  std::filesystem::path path;
  ~ScratchDir() {
    std::error_code ec;
    if (!path.empty()) std::filesystem::remove_all(path, ec);
  }
};

}  // namespace

int cmd_bench(int argc, char** argv) {
  if (wants_help(argc, argv)) {
    std::fputs(kBenchUsage, stdout);
    return kExitOk;
  }
  const Args args =
      parse_args(argc, argv, {"config", "sequence", "frames", "repetitions"}, {"quiet"});
  setup_logging("", args.on("quiet"));
  const std::filesystem::path config_path = args.get("config", "config/cadre_full_res.yaml");
  const int frames = positive_int(args, "frames", kDefaultFrames);
  FrameBenchOptions options;
  options.repetitions = positive_int(args, "repetitions", kDefaultRepetitions);
  const Config config = load_config(config_path, args.sets);

  std::filesystem::path sequence_dir = args.get("sequence");
  if (sequence_dir.empty()) {
    const char* env = std::getenv("HAZMAP_BENCH_SEQUENCE");
    if (env != nullptr) sequence_dir = env;
  }
  ScratchDir scratch;
  if (sequence_dir.empty()) {
    scratch.path = std::filesystem::temp_directory_path() /
                   ("hazmap_bench_" + std::to_string(std::random_device{}()));
    spdlog::info("rendering {} full-resolution frames into {} ...", frames, scratch.path.string());
    const double seconds = render_bench_sequence(scratch.path, frames, kFullResolution, kRenderSeed);
    spdlog::info("rendered in {:.1f} s", seconds);
    sequence_dir = scratch.path;
  }
  const Sequence sequence = load_sequence(sequence_dir);
  const std::vector<BenchFrame> images = read_bench_frames(sequence, frames);
  std::printf("config %s, sequence %s\n", config_path.string().c_str(),
              sequence_dir.string().c_str());
  const FrameBenchResult result = run_frame_bench(config, sequence.calibration, images, options);
  std::fputs(format_frame_bench(result).c_str(), stdout);
  return kExitOk;
}

}  // namespace hazmap::cli
