#pragma once
// SPEC 9: writing must not stall the frame loop. The loop copies a finished frame's
// outputs into one of a few preallocated FrameOutputs (acquire, fill, submit) and goes
// on; one writer thread renders and writes them in order. The loop waits only when
// `output.queue_frames` frames are already waiting. Each frame folder is filled under
// a hidden staging name and renamed into place: OUT/frames/<frame> is absent or
// complete, never partial. A write error (disk full, permission) stops the writer; the
// loop's next acquire() or finish() throws it as one line naming frame and file.

#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "hazmap/io/config.hpp"
#include "hazmap/pipeline/output_writer.hpp"

namespace hazmap {

class FrameWriter {
 public:
  /// `output.queue_frames` 0: no thread, submit() writes at once on the caller's thread.
  FrameWriter(std::filesystem::path out_dir, const OutputConfig& output);
  /// Writes what is still queued (an early exit through an exception keeps the frames
  /// already finished), then joins. Errors at this point are dropped: call finish().
  ~FrameWriter();
  FrameWriter(const FrameWriter&) = delete;
  FrameWriter& operator=(const FrameWriter&) = delete;

  /// A free slot to fill with capture_frame_outputs; waits while the queue is full.
  /// Throws the writer's Error once it has failed.
  FrameOutputs& acquire();
  /// Queues the slot returned by the last acquire() (synchronous: writes it now).
  void submit();
  /// Waits until every submitted frame is on disk; throws the writer's Error.
  void finish();

  struct Stats {
    int frames_written = 0;
    double write_ms = 0;  ///< writer's time rendering and writing, summed
    /// The CPU time of that (the writer thread's own): the work writing costs whatever
    /// else runs; write_ms also holds the time the thread waited for a core.
    double write_cpu_ms = 0;
    double wait_ms = 0;   ///< frame loop's time waiting for a free slot, summed
  };
  Stats stats() const;

  /// Writes one frame's folder (and mosaic) under `out_dir`, staged and renamed.
  static void write_frame(const std::filesystem::path& out_dir, const OutputConfig& output,
                          const FrameOutputs& frame);

 private:
  void run();
  void write_timed(int slot);
  void throw_if_failed() const;  // with mutex_ held

  const std::filesystem::path out_dir_;
  const OutputConfig output_;
  const bool threaded_;
  std::vector<FrameOutputs> slots_;
  // Fixed-capacity bookkeeping (reserved up front, so the loop allocates nothing):
  std::vector<int> free_;   ///< slots neither queued nor being written
  std::vector<int> ring_;   ///< queued slots, oldest at head_
  size_t head_ = 0, queued_ = 0;
  int current_ = -1;        ///< the slot the loop is filling
  bool closing_ = false;
  bool failed_ = false;
  std::string error_;
  Stats stats_;
  mutable std::mutex mutex_;
  std::condition_variable work_;   ///< writer: a frame was queued, or closing
  std::condition_variable space_;  ///< loop: a slot came free, or the writer failed
  std::thread thread_;
};

}  // namespace hazmap
