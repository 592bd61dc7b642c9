#pragma once
// `hazmap run`: a whole sequence through the pipeline, with progress, outputs and
// OUT/summary.json.

#include <filesystem>
#include <string>
#include <vector>

#include "hazmap/io/config.hpp"
#include "hazmap/io/sequence.hpp"

namespace hazmap {

struct RunOptions {
  std::filesystem::path config_path;   ///< for the summary only
  std::filesystem::path sequence_dir;
  std::filesystem::path out_dir;
  std::string frames;                  ///< "A:B" or "" for all
};

struct RunResult {
  int frames_processed = 0;
  int frames_written = 0;
  size_t points_total = 0;
  std::vector<std::filesystem::path> written;  ///< frame folders written
};

/// Runs the frames of a loaded sequence selected by options.frames. Logs one progress
/// line per frame through spdlog (level info). Throws Error on bad input; outputs
/// already written stay intact.
RunResult run_sequence(const Config& config, const Sequence& sequence, const RunOptions& options);

}  // namespace hazmap
