#pragma once
// `hazmap run`: a whole sequence through the pipeline, with progress, outputs and
// OUT/summary.json.

#include <atomic>
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
  /// Set (to the signal's number) by a SIGINT/SIGTERM handler: the run stops after the
  /// frame in flight, writes it, flushes the writer queue and returns. May be null.
  const std::atomic<int>* stop_signal = nullptr;
};

struct RunResult {
  int frames_processed = 0;
  int frames_written = 0;
  size_t points_total = 0;
  std::vector<std::filesystem::path> written;  ///< frame folders written
  int stop_signal = 0;        ///< non-zero: stopped early by this signal
  std::string stopped_after;  ///< then: the last frame processed (and written)
};

/// Runs the frames of a loaded sequence selected by options.frames. Logs one progress
/// line per frame through spdlog (level info). Outputs are written by a FrameWriter
/// (output.queue_frames). Throws Error on bad input or a failed write; outputs already
/// written stay intact and no frame folder is partial.
RunResult run_sequence(const Config& config, const Sequence& sequence, const RunOptions& options);

}  // namespace hazmap
