#include "cli.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

namespace hazmap::cli {
namespace {

std::shared_ptr<spdlog::sinks::basic_file_sink_mt> g_file_sink;

}  // namespace

std::string Args::get(const std::string& name, const std::string& fallback) const {
  const auto it = values.find(name);
  return it == values.end() ? fallback : it->second;
}

std::string Args::required(const std::string& name) const {
  const auto it = values.find(name);
  if (it == values.end()) throw UsageError("missing required option --" + name);
  // An empty path would mean the current folder (measured: --out '' wrote there).
  if (it->second.empty()) throw UsageError("--" + name + ": empty value");
  return it->second;
}

double Args::number(const std::string& name) const {
  const std::string text = required(name);
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') throw UsageError("--" + name + ": '" + text + "' is not a number");
  return v;
}

long long Args::whole(const std::string& name, long long lo, long long hi) const {
  const double v = number(name);
  if (!(v >= static_cast<double>(lo) && v <= static_cast<double>(hi)) || v != std::floor(v))
    throw UsageError("--" + name + ": '" + required(name) + "' is not a whole number in [" +
                     std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return static_cast<long long>(v);
}

Args parse_args(int argc, char** argv, const std::vector<std::string>& value_flags,
                const std::vector<std::string>& switch_flags,
                std::vector<std::string>* positional) {
  Args args;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--", 0) != 0) {
      if (positional == nullptr) throw UsageError("unexpected argument '" + a + "'");
      positional->push_back(a);
      continue;
    }
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

bool wants_help(int argc, char** argv) {
  for (int i = 2; i < argc; ++i)
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) return true;
  return false;
}

void setup_logging(const std::filesystem::path& log_path, bool quiet) {
  auto console = std::make_shared<spdlog::sinks::stderr_sink_mt>();
  console->set_pattern("%v");
  console->set_level(quiet ? spdlog::level::warn : spdlog::level::info);
  std::vector<spdlog::sink_ptr> sinks{console};
  if (!log_path.empty()) {
    if (log_path.has_parent_path()) std::filesystem::create_directories(log_path.parent_path());
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

void log_to_file_only(const std::string& message, bool error) {
  if (!g_file_sink) return;
  g_file_sink->log(spdlog::details::log_msg("hazmap", error ? spdlog::level::err : spdlog::level::debug,
                                            message));
  g_file_sink->flush();
}

hazmap::EurocOptions euroc_options(const Args& args) {
  hazmap::EurocOptions options;
  options.poses_csv = args.get("poses");
  const std::string frame = args.get("pose-frame", "body");
  if (frame == "body") options.poses_frame = hazmap::EurocPoseFrame::body;
  else if (frame == "left_camera") options.poses_frame = hazmap::EurocPoseFrame::left_camera;
  else throw UsageError("--pose-frame " + frame + ": expected body or left_camera");
  if (args.has("max-pose-gap")) {
    const double gap_s = args.number("max-pose-gap");
    // An hour bounds the nanosecond count far inside int64.
    if (!(gap_s >= 0 && gap_s <= 3600)) throw UsageError("--max-pose-gap must be in [0, 3600] s");
    options.max_pose_gap_ns = static_cast<std::int64_t>(gap_s * 1e9);
  }
  return options;
}

hazmap::Sequence load_any_sequence(const std::filesystem::path& dir, const Args& args,
                                   bool identity_fallback) {
  const bool euroc = !hazmap::find_euroc_mav0(dir).empty();
  if (!euroc) {
    for (const char* flag : {"poses", "pose-frame", "max-pose-gap"})
      if (args.has(flag))
        throw UsageError(std::string("--") + flag + " applies to ASL/EuRoC folders; " +
                         dir.string() + " is not one (no mav0/cam0 and mav0/cam1)");
    return hazmap::load_sequence(dir);
  }
  hazmap::EurocOptions options = euroc_options(args);
  options.identity_poses = identity_fallback;
  return hazmap::load_euroc_sequence(dir, options);
}

}  // namespace hazmap::cli
