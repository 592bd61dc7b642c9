#pragma once
// Shared plumbing of the hazmap subcommands (private to the executable): flag parsing,
// logging set-up, usage errors. Each subcommand lives in its own cmd_<name>.cpp.

#include "hazmap/io/euroc.hpp"
#include "hazmap/io/sequence.hpp"
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <spdlog/sinks/basic_file_sink.h>

namespace hazmap::cli {

constexpr int kExitOk = 0;
constexpr int kExitError = 1;  ///< bad input or failed run (hazmap::Error)
constexpr int kExitUsage = 2;  ///< bad command line, or a command not implemented yet

/// A bad command line; main prints it with a pointer to --help and exits 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Flags of one subcommand: "--name value" (or --name=value) pairs, repeated --set, and
/// boolean switches.
struct Args {
  std::map<std::string, std::string> values;
  std::vector<std::string> sets;
  std::map<std::string, bool> switches;

  bool has(const std::string& name) const { return values.count(name) > 0; }
  bool on(const std::string& name) const { return switches.count(name) > 0; }
  std::string get(const std::string& name, const std::string& fallback = "") const;
  std::string required(const std::string& name) const;
  double number(const std::string& name) const;  ///< throws UsageError if not a number
  /// A whole number in [lo, hi], range-checked before any integer conversion (a double
  /// outside the target type's range is undefined to convert); UsageError otherwise.
  long long whole(const std::string& name, long long lo, long long hi) const;
};

/// Parses argv[2..]. `value_flags` take a value ("set" always does and may repeat);
/// `switch_flags` take none. Unknown flags are UsageErrors. Arguments that are not flags
/// (nor a flag's value) go to `positional` in order, or are UsageErrors without it.
Args parse_args(int argc, char** argv, const std::vector<std::string>& value_flags,
                const std::vector<std::string>& switch_flags,
                std::vector<std::string>* positional = nullptr);

/// True when argv holds --help or -h after the command name.
bool wants_help(int argc, char** argv);

/// Console (stderr, bare messages; warnings only when quiet) plus, if log_path is not
/// empty, an appending file sink with timestamps. Becomes spdlog's default logger.
void setup_logging(const std::filesystem::path& log_path, bool quiet);

/// Writes a line to the run log only (not the terminal); no-op without a log file.
void log_to_file_only(const std::string& message, bool error = false);

// The subcommands; each returns the process exit code.
int cmd_run(int argc, char** argv);
int cmd_stereo(int argc, char** argv);
int cmd_simulate(int argc, char** argv);
int cmd_evaluate(int argc, char** argv);
int cmd_calibrate(int argc, char** argv);
int cmd_import_euroc(int argc, char** argv);
int cmd_ground_truth(int argc, char** argv);
int cmd_bench(int argc, char** argv);
int cmd_check(int argc, char** argv);
int cmd_view(int argc, char** argv);

/// --poses, --pose-frame and --max-pose-gap of an ASL/EuRoC folder (run, import-euroc).
hazmap::EurocOptions euroc_options(const Args& args);

/// Our sequence layout, or an ASL/EuRoC folder read in place with euroc_options(args)
/// (run, check); the EuRoC flags on our layout are a UsageError.
/// `identity_fallback`: an EuRoC folder without any pose source maps at the identity
/// (stereo), said once as a warning, rather than being an error (run, check).
hazmap::Sequence load_any_sequence(const std::filesystem::path& dir, const Args& args,
                                   bool identity_fallback = false);

}  // namespace hazmap::cli
