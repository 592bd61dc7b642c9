#include "hazmap/pipeline/frame_writer.hpp"

#include <chrono>
#include <ctime>
#include <system_error>

#include "hazmap/core/error.hpp"
#include "hazmap/core/stopwatch.hpp"
#include "hazmap/io/atomic_file.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/io/run_layout.hpp"

namespace hazmap {
namespace {

using Clock = std::chrono::steady_clock;

/// CPU time of the calling thread, ms.
double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

}  // namespace

FrameWriter::FrameWriter(std::filesystem::path out_dir, const OutputConfig& output)
    : out_dir_(std::move(out_dir)), output_(output), threaded_(output.queue_frames > 0) {
  // Queued frames plus the one being written; synchronous: the one being filled.
  const int slots = threaded_ ? output.queue_frames + 1 : 1;
  slots_.resize(static_cast<size_t>(slots));
  ring_.assign(static_cast<size_t>(slots), -1);
  free_.reserve(static_cast<size_t>(slots));
  for (int i = slots - 1; i >= 0; --i) free_.push_back(i);
  if (threaded_) thread_ = std::thread([this] { run(); });
}

FrameWriter::~FrameWriter() {
  if (!threaded_) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closing_ = true;
  }
  work_.notify_all();
  thread_.join();
}

void FrameWriter::throw_if_failed() const {
  if (failed_) throw Error(error_);
}

FrameOutputs& FrameWriter::acquire() {
  std::unique_lock<std::mutex> lock(mutex_);
  check(current_ < 0, "FrameWriter: acquire() twice without submit()");
  throw_if_failed();
  if (free_.empty()) {
    const auto t = Clock::now();
    space_.wait(lock, [this] { return !free_.empty() || failed_; });
    stats_.wait_ms += ms_since(t);
    throw_if_failed();
  }
  current_ = free_.back();
  free_.pop_back();
  return slots_[static_cast<size_t>(current_)];
}

void FrameWriter::submit() {
  std::unique_lock<std::mutex> lock(mutex_);
  check(current_ >= 0, "FrameWriter: submit() without acquire()");
  const int slot = current_;
  current_ = -1;
  if (!threaded_) {
    lock.unlock();
    write_timed(slot);  // throws on failure, after recording it
    return;
  }
  ring_[(head_ + queued_) % ring_.size()] = slot;
  ++queued_;
  lock.unlock();
  work_.notify_one();
}

void FrameWriter::finish() {
  std::unique_lock<std::mutex> lock(mutex_);
  // Every slot free again (the loop holds none after submit): all written or dropped.
  space_.wait(lock, [this] { return free_.size() == slots_.size() || failed_; });
  throw_if_failed();
}

FrameWriter::Stats FrameWriter::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

void FrameWriter::write_timed(int slot) {
  const FrameOutputs& frame = slots_[static_cast<size_t>(slot)];
  const auto t = Clock::now();
  const double cpu = thread_cpu_ms();
  std::string error;
  try {
    write_frame(out_dir_, output_, frame);
  } catch (const std::exception& e) {
    error = "frame " + frame.frame_name + ": output not written: " + e.what();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  free_.push_back(slot);
  if (error.empty()) {
    stats_.write_ms += ms_since(t);
    stats_.write_cpu_ms += thread_cpu_ms() - cpu;
    ++stats_.frames_written;
  } else if (!failed_) {
    failed_ = true;
    error_ = error;
  }
  if (!threaded_) throw_if_failed();
}

void FrameWriter::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    work_.wait(lock, [this] { return queued_ > 0 || closing_; });
    if (queued_ == 0) return;  // closing, nothing left
    const int slot = ring_[head_];
    head_ = (head_ + 1) % ring_.size();
    --queued_;
    if (failed_) {  // after a failure the rest is dropped: the run stops anyway
      free_.push_back(slot);
    } else {
      lock.unlock();
      write_timed(slot);
      lock.lock();
    }
    space_.notify_all();
  }
}

void FrameWriter::write_frame(const std::filesystem::path& out_dir, const OutputConfig& output,
                              const FrameOutputs& frame) {
  const std::filesystem::path dir = run_layout::frame_dir(out_dir, frame.frame_name);
  const std::filesystem::path staging = staging_folder_name(dir);
  try {
    write_frame_outputs(staging, frame, output);
    // Nothing to write (png and grids off) leaves no folder, as before the writer thread.
    if (std::filesystem::exists(staging)) publish_folder(staging, dir);
  } catch (const std::exception& e) {
    std::error_code ec;
    std::filesystem::remove_all(staging, ec);
    // Name files as the user will look for them, not by the hidden staging folder.
    std::string message = e.what();
    const std::string from = staging.string(), to = dir.string();
    for (size_t at = message.find(from); at != std::string::npos; at = message.find(from, at))
      message.replace(at, from.size(), to), at += to.size();
    throw Error(message);
  }
  if (output.mosaic)
    write_png(run_layout::mosaic_png(out_dir, frame.frame_name),
              render_mosaic(frame, output.png_height_clip_pct));
}

}  // namespace hazmap
