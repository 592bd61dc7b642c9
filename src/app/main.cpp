// hazmap: the command-line front end. Thin by design: it parses arguments, sets up
// logging and turns library errors into one line on stderr and a non-zero exit code.

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include "hazmap/core/error.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/pipeline/sequence_runner.hpp"
#include "hazmap/sim/simulate.hpp"

namespace {

constexpr int kExitError = 1;
constexpr int kExitUsage = 2;

const char* kUsage = R"(hazmap: stereo-to-hazard terrain mapping for small planetary rovers

usage:
  hazmap run      --config FILE --sequence DIR --out DIR [--frames A:B] [--set KEY=VALUE]... [--quiet]
  hazmap stereo   --config FILE --sequence DIR --out DIR [--frames A:B]
  hazmap simulate --scenario NAME --out DIR [--seed N] [--frames N] [--scale S] [--step M]
                  [--ramp-deg D] [--samples N] [--noise-sigma DN] [--no-sun]
                  [--ground-truth] [--gt-margin M]
  hazmap evaluate --run DIR --sequence DIR [--out DIR]
  hazmap --help | --version

run       maps a stereo sequence: writes OUT/frames/<frame>/L<i>_{hazard,height}.png,
          L<i>_{height,variance,hazard}.jdem, fused_hazard.{png,jdem}, OUT/summary.json
          and OUT/run.log
simulate  renders a synthetic sequence (scenarios: rocks, flat, ramp) in the SPEC 2
          layout: CADRE camera geometry at --scale (0.4: 640 x 520), --step metres per
          frame along +x, --samples rays per pixel and axis, optional ground truth
          (gt_height.jdem, gt_hazard.jdem) over the path +- --gt-margin metres
--set     overrides a YAML key by dotted path, e.g. --set stereo.matcher=sgbm
          --set map.layers.0.size=64
)";

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Flags of one subcommand: "--name value" pairs, repeated --set, and boolean switches.
struct Args {
  std::map<std::string, std::string> values;
  std::vector<std::string> sets;
  std::map<std::string, bool> switches;

  std::string get(const std::string& name, const std::string& fallback = "") const {
    const auto it = values.find(name);
    return it == values.end() ? fallback : it->second;
  }
  std::string required(const std::string& name) const {
    const auto it = values.find(name);
    if (it == values.end()) throw UsageError("missing required option --" + name);
    return it->second;
  }
};

Args parse_args(int argc, char** argv, const std::vector<std::string>& value_flags,
                const std::vector<std::string>& switch_flags) {
  Args args;
  for (int i = 2; i < argc; ++i) {
    std::string a = argv[i];
    if (a.rfind("--", 0) != 0) throw UsageError("unexpected argument '" + a + "'");
    std::string name = a.substr(2), value;
    const auto eq = name.find('=');
    const bool inline_value = eq != std::string::npos;
    if (inline_value) value = name.substr(eq + 1), name = name.substr(0, eq);
    const bool is_switch =
        std::find(switch_flags.begin(), switch_flags.end(), name) != switch_flags.end();
    const bool is_value = name == "set" || std::find(value_flags.begin(), value_flags.end(),
                                                     name) != value_flags.end();
    if (is_switch && !inline_value) {
      args.switches[name] = true;
      continue;
    }
    if (!is_value) throw UsageError("unknown option --" + name);
    if (!inline_value) {
      if (i + 1 >= argc) throw UsageError("option --" + name + " needs a value");
      value = argv[++i];
    }
    if (name == "set") args.sets.push_back(value);
    else args.values[name] = value;
  }
  return args;
}

double to_number(const std::string& flag, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') throw UsageError("--" + flag + ": '" + text + "' is not a number");
  return v;
}

std::shared_ptr<spdlog::sinks::basic_file_sink_mt> g_file_sink;

void setup_logging(const std::filesystem::path& log_path, bool quiet) {
  auto console = std::make_shared<spdlog::sinks::stderr_sink_mt>();
  console->set_pattern("%v");
  console->set_level(quiet ? spdlog::level::warn : spdlog::level::info);
  std::vector<spdlog::sink_ptr> sinks{console};
  if (!log_path.empty()) {
    std::filesystem::create_directories(log_path.parent_path());
    // Append: a failed run must not wipe the log of an earlier one.
    g_file_sink = std::make_shared<spdlog::sinks::basic_file_sink_mt>(log_path.string(), false);
    g_file_sink->set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%l] %v");
    g_file_sink->set_level(spdlog::level::debug);
    sinks.push_back(g_file_sink);
  }
  auto logger = std::make_shared<spdlog::logger>("hazmap", sinks.begin(), sinks.end());
  logger->set_level(spdlog::level::debug);
  logger->flush_on(spdlog::level::info);
  spdlog::set_default_logger(logger);
}

int cmd_run(int argc, char** argv) {
  const Args args = parse_args(argc, argv, {"config", "sequence", "out", "frames"}, {"quiet"});
  hazmap::RunOptions options;
  options.config_path = args.required("config");
  options.sequence_dir = args.required("sequence");
  options.out_dir = args.required("out");
  options.frames = args.get("frames");
  // Check every input before the first line is logged or written: a bad input gives
  // exactly one line on stderr and leaves OUT untouched.
  const hazmap::Config config = hazmap::load_config(options.config_path, args.sets);
  const hazmap::Sequence sequence = hazmap::load_sequence(options.sequence_dir);
  if (!options.frames.empty()) hazmap::select_frames(sequence.frames, options.frames);
  setup_logging(options.out_dir / "run.log", args.switches.count("quiet") > 0);
  spdlog::info("hazmap {} run: config {}, sequence {}, out {}", HAZMAP_VERSION,
               options.config_path.string(), options.sequence_dir.string(),
               options.out_dir.string());
  if (g_file_sink) {
    // The configuration as actually used goes to the log file, not the terminal.
    g_file_sink->log(spdlog::details::log_msg("hazmap", spdlog::level::debug,
                                              "configuration in use:\n" + hazmap::to_yaml(config)));
  }
  const hazmap::RunResult result = hazmap::run_sequence(config, sequence, options);
  spdlog::info("done: {} frames, {} points; wrote {} frame folders under {}",
               result.frames_processed, result.points_total, result.frames_written,
               (options.out_dir / "frames").string());
  return 0;
}

int cmd_simulate(int argc, char** argv) {
  const Args args = parse_args(argc, argv,
                               {"scenario", "out", "seed", "frames", "scale", "step", "ramp-deg",
                                "samples", "noise-sigma", "gt-margin"},
                               {"ground-truth", "no-sun", "quiet"});
  hazmap::sim::SimulationOptions options;
  options.scenario = args.get("scenario", options.scenario);
  const std::filesystem::path out = args.required("out");
  if (args.values.count("seed"))
    options.seed = static_cast<std::uint64_t>(to_number("seed", args.get("seed")));
  if (args.values.count("frames"))
    options.frames = static_cast<int>(to_number("frames", args.get("frames")));
  if (args.values.count("scale")) options.scale = to_number("scale", args.get("scale"));
  if (args.values.count("step")) options.step_m = to_number("step", args.get("step"));
  if (args.values.count("ramp-deg")) options.ramp_deg = to_number("ramp-deg", args.get("ramp-deg"));
  if (args.values.count("samples"))
    options.render.samples_per_axis = static_cast<int>(to_number("samples", args.get("samples")));
  if (args.values.count("noise-sigma"))
    options.render.noise_sigma_dn = to_number("noise-sigma", args.get("noise-sigma"));
  if (args.values.count("gt-margin"))
    options.ground_truth_margin_m = to_number("gt-margin", args.get("gt-margin"));
  options.render.sun_shading = args.switches.count("no-sun") == 0;
  options.write_ground_truth = args.switches.count("ground-truth") > 0;
  setup_logging({}, args.switches.count("quiet") > 0);
  spdlog::info("simulating scenario '{}' (seed {}, {} frames, scale {}) into {}", options.scenario,
               options.seed, options.frames, options.scale, out.string());
  hazmap::sim::simulate_sequence(options, out);
  spdlog::info("done: sequence written to {}", out.string());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fputs(kUsage, stderr);
    return kExitUsage;
  }
  const std::string command = argv[1];
  try {
    if (command == "--help" || command == "-h" || command == "help") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    if (command == "--version") {
      std::printf("hazmap %s\n", HAZMAP_VERSION);
      return 0;
    }
    if (command == "run") return cmd_run(argc, argv);
    if (command == "simulate") return cmd_simulate(argc, argv);
    if (command == "stereo" || command == "evaluate") {
      std::fprintf(stderr, "hazmap: '%s' is not implemented yet\n", command.c_str());
      return kExitUsage;
    }
    throw UsageError("unknown command '" + command + "'");
  } catch (const UsageError& e) {
    std::fprintf(stderr, "hazmap: %s (see hazmap --help)\n", e.what());
    return kExitUsage;
  } catch (const hazmap::Error& e) {
    if (g_file_sink) g_file_sink->log(spdlog::details::log_msg("hazmap", spdlog::level::err, e.what()));
    std::fprintf(stderr, "hazmap: error: %s\n", e.what());
    return kExitError;
  } catch (const std::exception& e) {
    if (g_file_sink) g_file_sink->log(spdlog::details::log_msg("hazmap", spdlog::level::err, e.what()));
    std::fprintf(stderr, "hazmap: error: %s\n", e.what());
    return kExitError;
  }
}
