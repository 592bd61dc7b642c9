#pragma once
// `hazmap run`: a whole sequence through the pipeline, with progress, outputs and
// OUT/summary.json.

#include <atomic>
#include <filesystem>
#include <memory>
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
  /// Not empty when no frame processed gave a point: why, and the setting most likely
  /// wrong (no_points_message); `hazmap run` then exits non-zero.
  std::string no_points;
};

class Pipeline;

/// A run in two steps, so that every check comes before the first byte is written or
/// logged: the constructor selects the frames, checks every frame's image headers
/// (check_frame_images) and builds the pipeline (its constructors' checks, the map's
/// allocation); run() then logs, maps and writes.
class SequenceRun {
 public:
  /// Logs and writes nothing. Throws Error on bad input. `config` and `sequence` must
  /// outlive the object.
  SequenceRun(const Config& config, const Sequence& sequence, const RunOptions& options);
  ~SequenceRun();

  /// Runs the selected frames. Logs one progress line per frame through spdlog (level
  /// info). Outputs go through a FrameWriter (output.queue_frames); no frame folder is
  /// ever partial. OUT/summary.json is written once, after the last frame: a run that stops
  /// leaves an earlier run's summary.json as it was. A frame that fails (an image damaged
  /// after the up-front check) throws one Error naming it; the frames written before it
  /// stay complete.
  RunResult run();

 private:
  const Config& config_;
  const Sequence& sequence_;
  RunOptions options_;
  std::vector<SequenceFrame> frames_;
  std::unique_ptr<Pipeline> pipeline_;
  std::vector<std::string> rig_warnings_;  ///< check_rig_geometry's, logged by run()
};

/// SequenceRun(config, sequence, options).run().
RunResult run_sequence(const Config& config, const Sequence& sequence, const RunOptions& options);

}  // namespace hazmap
