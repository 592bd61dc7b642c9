#include "hazmap/pipeline/sequence_runner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <spdlog/spdlog.h>

#include "hazmap/core/error.hpp"
#include "hazmap/core/stopwatch.hpp"
#include "hazmap/core/progress.hpp"
#include "hazmap/io/atomic_file.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/io/run_layout.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/pipeline/frame_writer.hpp"
#include "hazmap/pipeline/output_writer.hpp"
#include "hazmap/pipeline/pipeline.hpp"
#include "hazmap/pipeline/empty_run.hpp"
#include "hazmap/pipeline/preflight_check.hpp"
#include "hazmap/pipeline/rig_geometry.hpp"
#include "hazmap/rules/rule_registry.hpp"
#include "hazmap/stereo/ground_plane_fit.hpp"
#include "hazmap/stereo/band_matcher.hpp"
#include "io/json_writer.hpp"

namespace hazmap {
namespace {

using Clock = std::chrono::steady_clock;

struct FrameRecord {
  std::string name;
  size_t points = 0;
  size_t points_below_ground = 0;  ///< SPEC 3.3, not in `points`
  size_t points_occluded = 0;      ///< seen through known terrain, not in `points`
  size_t disparities_unsupported = 0;
  double read_ms = 0;
  double write_ms = 0;  ///< the loop's share: copying out the grids (+ waiting for a slot)
  StageTimes ms;
  bool written = false;
  std::vector<HazardAreas> areas;  ///< per layer, then fused, footprint (written frames only)
  std::vector<double> layer_map_ms;  ///< each layer's share of the insertion
  std::vector<GateCounts> layer_gates;  ///< each layer's SPEC 4 gate drops
  Pose3d T_W_B = Pose3d::Identity();  ///< the pose the frame was mapped with
};

/// How the run ended, for the summary.
struct RunState {
  bool finished = false;
  int stop_signal = 0;
  FrameWriter::Stats writer;
};

/// The frames' counts and stage times, summed.
struct RunTotals {
  size_t points = 0, below_ground = 0, occluded = 0, unsupported = 0;
  StageTimes sum;
  double read = 0, write = 0;
};

RunTotals totals_of(const std::vector<FrameRecord>& frames) {
  RunTotals t;
  for (const auto& f : frames) {
    t.points += f.points;
    t.below_ground += f.points_below_ground;
    t.occluded += f.points_occluded;
    t.unsupported += f.disparities_unsupported;
    t.sum.rectify_ms += f.ms.rectify_ms;
    t.sum.disparity_ms += f.ms.disparity_ms;
    t.sum.points_ms += f.ms.points_ms;
    t.sum.map_ms += f.ms.map_ms;
    t.sum.hazard_ms += f.ms.hazard_ms;
    t.read += f.read_ms;
    t.write += f.write_ms;
  }
  return t;
}

/// "mean_ms_per_frame": each stage's mean over `n` frames.
void write_mean_times(JsonWriter& j, const RunTotals& t, double n) {
  j.key("mean_ms_per_frame").begin_object();
  j.key("read").value(t.read / n);
  j.key("rectify").value(t.sum.rectify_ms / n);
  j.key("disparity").value(t.sum.disparity_ms / n);
  j.key("points").value(t.sum.points_ms / n);
  j.key("map").value(t.sum.map_ms / n);
  j.key("hazard").value(t.sum.hazard_ms / n);
  j.key("write").value(t.write / n);
  j.key("total").value((t.read + t.sum.total() + t.write) / n);
  j.end_object();
}

/// "output": the format and the writer thread's own times (the loop's share is "write" in
/// mean_ms_per_frame).
void write_output_stats(JsonWriter& j, const Config& config, const FrameWriter::Stats& writer) {
  j.key("output").begin_object();
  j.key("format").value(std::string(enum_name(config.output.format)));
  j.key("queue_frames").value(config.output.queue_frames);
  j.key("frames_written").value(writer.frames_written);
  j.key("writer_ms_per_written_frame")
      .value(writer.frames_written ? writer.write_ms / writer.frames_written : 0.0);
  j.key("writer_cpu_ms_per_written_frame")
      .value(writer.frames_written ? writer.write_cpu_ms / writer.frames_written : 0.0);
  j.key("loop_wait_ms_total").value(writer.wait_ms);
  j.end_object();
}

/// "layers": each layer's settings, insertion time and SPEC 4 gate drops over the run.
void write_layer_totals(JsonWriter& j, const Config& config,
                        const std::vector<FrameRecord>& frames, size_t points, double n) {
  j.key("layers").begin_array();
  for (size_t i = 0; i < config.map.layers.size(); ++i) {
    const LayerConfig& l = config.map.layers[i];
    double layer_ms = 0;
    GateCounts gated;
    for (const auto& f : frames) {
      layer_ms += i < f.layer_map_ms.size() ? f.layer_map_ms[i] : 0.0;
      if (i < f.layer_gates.size()) gated += f.layer_gates[i];
    }
    j.begin_object();
    j.key("resolution_m").value(l.resolution_m);
    j.key("size").value(l.size);
    j.key("rule").value(rule_name(l.rule));
    j.key("insert_ms_per_frame").value(layer_ms / n);
    j.key("insert_ns_per_point").value(points ? layer_ms * 1e6 / static_cast<double>(points) : 0.0);
    j.key("gated_std_total").value(gated.std_gate);
    j.key("gated_consistency_total").value(gated.consistency_gate);
    j.end_object();
  }
  j.end_array();
}

/// One element of "frames".
void write_frame_record(JsonWriter& j, const FrameRecord& f) {
  j.begin_object();
  j.key("name").value(f.name);
  j.key("points").value(f.points);
  j.key("points_below_ground").value(f.points_below_ground);
  j.key("points_occluded").value(f.points_occluded);
  j.key("disparities_unsupported").value(f.disparities_unsupported);
  // The pose as given (poses.txt's order: x y z qx qy qz qw), so that the run alone
  // shows where the rover was (hazmap view draws its path), every frame processed.
  const Eigen::Quaterniond q(f.T_W_B.linear());
  const Eigen::Vector3d& t = f.T_W_B.translation();
  j.key("T_W_B").begin_array();
  for (double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) j.value(v);
  j.end_array();
  j.key("gated").begin_array();  // per layer, SPEC 4
  for (size_t i = 0; i < f.layer_gates.size(); ++i) {
    j.begin_object();
    j.key("layer").value(run_layout::layer_id(i));
    j.key("std").value(f.layer_gates[i].std_gate);
    j.key("consistency").value(f.layer_gates[i].consistency_gate);
    j.end_object();
  }
  j.end_array();
  j.key("written").value(f.written);
  j.key("ms").begin_object();
  j.key("read").value(f.read_ms);
  j.key("rectify").value(f.ms.rectify_ms);
  j.key("disparity").value(f.ms.disparity_ms);
  j.key("points").value(f.ms.points_ms);
  j.key("map").value(f.ms.map_ms);
  j.key("hazard").value(f.ms.hazard_ms);
  j.key("write").value(f.write_ms);
  j.end_object();
  if (f.written) {
    j.key("areas_m2").begin_array();
    for (size_t i = 0; i < f.areas.size(); ++i) {
      j.begin_object();
      const size_t layers = f.areas.size() - 2;  // then the fused and footprint maps
      j.key("layer").value(i < layers        ? run_layout::layer_id(i)
                           : i == layers ? std::string("fused")
                                         : std::string("footprint"));
      j.key("hazard").value(f.areas[i].hazard_m2);
      j.key("traversable").value(f.areas[i].traversable_m2);
      j.key("unknown").value(f.areas[i].unknown_m2);
      j.end_object();
    }
    j.end_array();
  }
  j.end_object();
}

void write_summary(const std::filesystem::path& path, const Config& config,
                   const Sequence& sequence, const RunOptions& options,
                   const std::vector<FrameRecord>& frames,
                   int frames_total, const RunState& state) {
  JsonWriter j;
  j.begin_object();
  j.key("hazmap_version").value(HAZMAP_VERSION);
  j.key("finished").value(state.finished);
  if (state.stop_signal != 0) {
    j.key("stopped_by_signal").value(state.stop_signal);
    j.key("stopped_after_frame").value(frames.empty() ? std::string() : frames.back().name);
  }
  // Which sequence made these frames, for `hazmap evaluate` to check (issue 22): its
  // folder, absolute, and the fingerprint of all its poses, not only the frames
  // selected, so that a run of --frames A:B still matches its sequence.
  j.key("sequence").value(absolute_folder(options.sequence_dir).string());
  j.key("poses_fingerprint").value(fingerprint_hex(fingerprint_of(sequence)));
  j.key("config").value(options.config_path.string());
  j.key("frames_selected").value(frames_total);
  j.key("frames_processed").value(frames.size());
  const RunTotals t = totals_of(frames);
  j.key("points_total").value(t.points);
  j.key("points_below_ground_total").value(t.below_ground);
  j.key("points_occluded_total").value(t.occluded);
  j.key("disparities_unsupported_total").value(t.unsupported);
  const double n = frames.empty() ? 1.0 : static_cast<double>(frames.size());
  write_mean_times(j, t, n);
  write_output_stats(j, config, state.writer);
  j.key("map_ns_per_point")
      .value(t.points ? t.sum.map_ms * 1e6 / static_cast<double>(t.points) : 0.0);
  write_layer_totals(j, config, frames, t.points, n);
  j.key("frames").begin_array();
  for (const auto& f : frames) write_frame_record(j, f);
  j.end_array();
  j.key("settings_yaml").value(to_yaml(config));
  j.end_object();
  write_file_atomically(path, j.str());
}

bool stop_requested(const RunOptions& options) {
  return options.stop_signal != nullptr && options.stop_signal->load() != 0;
}

/// Warns once (the first frame with points) when the ground those points lie on is tilted
/// beyond hazard.max_slope_deg in W: the usual sign of poses or T_body_left in another
/// convention, which otherwise shows only as slopes everywhere in the map.
void warn_if_ground_tilted(const PointCloud& cloud, const SequenceFrame& frame,
                           const StereoCalibration& calibration, const Config& config) {
  const Pose3d& T_W_B = frame.pose.T_W_B;
  const GroundPlane ground = fit_ground_plane(cloud, T_W_B * calibration.T_B_C.translation());
  if (!ground.found) return;
  const std::string problem =
      ground_tilt_problem(ground.tilt_deg(Eigen::Vector3d::UnitZ()),
                          ground.tilt_deg(T_W_B.linear().col(2)), config.hazard.max_slope_deg);
  if (!problem.empty())
    spdlog::warn("frame {}: {}{} (a rover really standing on such a slope may ignore this)",
                 frame.name, problem,
                 scalar_first_hint(calibration, T_W_B, ground.normal, config.hazard.max_slope_deg));
}

/// The run's first lines: frames, image size, rectified geometry, ground band, and the
/// rig's doubtful geometry found by the constructor.
void log_run_start(const RunOptions& options, size_t frames, const Sequence& sequence,
                   const Pipeline& pipeline, const std::vector<std::string>& rig_warnings) {
  spdlog::info("sequence {}: {} frames selected of {}, images {}x{}", options.sequence_dir.string(),
               frames, sequence.frames.size(), sequence.calibration.image_width,
               sequence.calibration.image_height);
  const StereoGeometry& g = pipeline.rectifier().geometry();
  spdlog::info("rectified: f = {:.2f} px, B = {:.4f} m, c = ({:.1f}, {:.1f}) px", g.focal_px,
               g.baseline_m, g.cx_px, g.cy_px);
  if (const BandMatcher* band = pipeline.matcher().band())
    spdlog::info("ground band: {}", describe_strips(band->strips()));
  for (const std::string& w : rig_warnings) spdlog::warn("{}", w);
}

/// Reads the frame's images; the record starts with its name, pose and reading time.
FrameRecord read_frame(const SequenceFrame& frame, cv::Mat& left, cv::Mat& right) {
  FrameRecord rec;
  rec.name = frame.name;
  rec.T_W_B = frame.pose.T_W_B;
  const auto t = Clock::now();
  left = read_image(frame.left_path);
  right = read_image(frame.right_path);
  rec.read_ms = ms_since(t);
  return rec;
}

/// Pipeline::process on the frame's pair; an error names the frame's left image.
FrameReport process_frame(Pipeline& pipeline, const SequenceFrame& frame, const cv::Mat& left,
                          const cv::Mat& right) {
  try {
    return pipeline.process(left, right, frame.pose.T_W_B, frame.pose.noise);
  } catch (const Error& e) {
    throw Error(frame.left_path.string() + ": " + e.what());
  }
}

/// Hands the pipeline's current outputs to the writer and books them in `rec` and
/// `result`.
void hand_to_writer(const Pipeline& pipeline, const SequenceFrame& frame,
                    const std::filesystem::path& out_dir, FrameWriter& writer, FrameRecord& rec,
                    RunResult& result) {
  const auto t = Clock::now();
  capture_frame_outputs(pipeline, frame.name, frame.pose.T_W_B, writer.acquire());
  writer.submit();
  for (const auto& view : pipeline.layers()) rec.areas.push_back(hazard_areas(view.hazard));
  rec.areas.push_back(hazard_areas(pipeline.planner_maps().fused));
  rec.areas.push_back(hazard_areas(pipeline.planner_maps().footprint));
  rec.write_ms = ms_since(t);
  rec.written = true;
  result.written.push_back(run_layout::frame_dir(out_dir, frame.name));
  ++result.frames_written;
}

/// A frame without a point: why (disparities out of range, unsupported, below the
/// ground, occluded), added to `drops`.
void count_empty_frame(const Pipeline& pipeline, const FrameReport& report, const Config& config,
                       EmptyRunCounts& drops) {
  const StereoGeometry& g = pipeline.rectifier().geometry();
  const double fb = g.focal_px * g.baseline_m;
  count_disparity_drops(pipeline.disparity_x16(), pipeline.builder().region(),
                        pipeline.matcher().invalid_below(), fb / config.stereo.z_max_m,
                        fb / config.stereo.z_min_m, drops);
  drops.unsupported += report.disparities_unsupported;
  drops.below_ground += report.points_below_ground;
  drops.occluded += report.points_occluded;
}

/// The frame's report and the pipeline's per-layer figures, booked in `rec`.
void record_report(const FrameReport& report, const Pipeline& pipeline, FrameRecord& rec) {
  rec.points = report.points;
  rec.ms = report.ms;
  rec.layer_map_ms = pipeline.layer_map_ms();
  rec.points_below_ground = report.points_below_ground;
  rec.points_occluded = report.points_occluded;
  rec.disparities_unsupported = report.disparities_unsupported;
  rec.layer_gates = pipeline.layer_gates();
}

void log_frame(int i, int n, const FrameReport& report, const FrameRecord& rec,
               const Progress& progress) {
  spdlog::info("frame {}/{} {}: {} points, {:.1f} ms (read {:.1f}, rectify {:.1f}, disparity "
               "{:.1f}, points {:.1f}, map {:.1f}, hazard {:.1f}, write {:.1f}); {}",
               i + 1, n, rec.name, report.points, rec.read_ms + report.ms.total() + rec.write_ms,
               rec.read_ms, report.ms.rectify_ms, report.ms.disparity_ms, report.ms.points_ms,
               report.ms.map_ms, report.ms.hazard_ms, rec.write_ms, progress.rate(i + 1));
}

/// A frame that failed stops the run: the frames handed to the writer before it are
/// written whole first, and the error says so (or that writing them failed too).
Error frame_failure(const Error& e, FrameWriter& writer, const std::string& frame, int i, int n,
                    int frames_written) {
  std::string written =
      std::to_string(frames_written) + " frame folders written before it are complete";
  try {
    writer.finish();
  } catch (const Error& w) {
    written = std::string("writing the earlier frames failed too: ") + w.what();
  }
  return Error(std::string(e.what()) + " (frame " + frame + ", " + std::to_string(i + 1) +
               " of " + std::to_string(n) + ", stopped the run; " + written + ")");
}

/// A layer no point reached is all unknown, which looks like a map: say so (measured:
/// default.yaml on EuRoC's room left its 1.28 m layer empty in every frame, silently).
void warn_empty_layers(const Pipeline& pipeline, const Config& config, int frames_processed) {
  const auto& views = pipeline.layers();
  for (size_t i = 0; i < views.size(); ++i) {
    const DenseGrid& h = views[i].map.height;
    if (std::any_of(h.values.begin(), h.values.end(), [](float v) { return !std::isnan(v); }))
      continue;
    const LayerConfig& l = config.map.layers[i];
    spdlog::warn("layer {} ({} m cells, a {} m window around the body) received no point in "
                 "{} frames: every cell is unknown; see docs/conventions.md for where the "
                 "window lies and check map.layers.{}.size against where the cameras see "
                 "the ground",
                 i, l.resolution_m, l.resolution_m * l.size, frames_processed, i);
  }
}

}  // namespace

SequenceRun::SequenceRun(const Config& config, const Sequence& sequence, const RunOptions& options)
    : config_(config),
      sequence_(sequence),
      options_(options),
      frames_(options.frames.empty() ? sequence.frames
                                     : select_frames(sequence.frames, options.frames)) {
  check_frame_images(frames_, sequence.calibration);
  // Geometry that cannot be right stops the run here; doubtful geometry is said in run().
  rig_warnings_ = enforce_rig_geometry(check_rig_geometry(sequence, frames_));
  pipeline_ = std::make_unique<Pipeline>(config, sequence.calibration);
}

SequenceRun::~SequenceRun() = default;

RunResult run_sequence(const Config& config, const Sequence& sequence, const RunOptions& options) {
  return SequenceRun(config, sequence, options).run();
}

RunResult SequenceRun::run() {
  const Config& config = config_;
  const RunOptions& options = options_;
  const std::vector<SequenceFrame>& frames = frames_;
  Pipeline& pipeline = *pipeline_;
  log_run_start(options, frames.size(), sequence_, pipeline, rig_warnings_);

  RunResult result;
  RunState state;
  std::vector<FrameRecord> records;
  records.reserve(frames.size());
  FrameWriter writer(options.out_dir, config.output);
  auto write_frame = [&](const SequenceFrame& frame, FrameRecord& rec) {
    hand_to_writer(pipeline, frame, options.out_dir, writer, rec, result);
  };

  const int n = static_cast<int>(frames.size());
  const Progress progress(n);
  int last = -1;  // index of the last frame processed
  bool ground_checked = false;  // the first frame with points is checked for tilt
  EmptyRunCounts drops;  // frames without a point: why (said if no frame has one)
  for (int i = 0; i < n; ++i) {
    // A stop request ends the run between frames: the frame in flight was finished.
    if (stop_requested(options)) break;
    const SequenceFrame& frame = frames[static_cast<size_t>(i)];
    try {
      cv::Mat left, right;
      FrameRecord rec = read_frame(frame, left, right);
      const FrameReport report = process_frame(pipeline, frame, left, right);
      last = i;
      if (!ground_checked && report.points > 0) {
        warn_if_ground_tilted(pipeline.cloud(), frame, sequence_.calibration, config);
        ground_checked = true;
      }
      if (report.points == 0) count_empty_frame(pipeline, report, config, drops);
      record_report(report, pipeline, rec);

      if (i % config.output.every_n == 0 || i == n - 1) write_frame(frame, rec);
      result.points_total += report.points;
      ++result.frames_processed;
      log_frame(i, n, report, rec, progress);
      records.push_back(std::move(rec));
    } catch (const Error& e) {
      throw frame_failure(e, writer, frame.name, i, n, result.frames_written);
    }
  }
  if (last < n - 1 && stop_requested(options)) {  // stopped early
    result.stop_signal = options.stop_signal->load();
    if (last >= 0) {
      result.stopped_after = frames[static_cast<size_t>(last)].name;
      // Like the last frame of a whole run, the last one processed is always written.
      if (!records.back().written) write_frame(frames[static_cast<size_t>(last)], records.back());
    }
  }
  writer.finish();
  if (result.frames_processed > 0 && result.points_total > 0)  // else one line says why
    warn_empty_layers(pipeline, config, result.frames_processed);
  if (result.frames_processed > 0 && result.points_total == 0)
    result.no_points = no_points_message(drops);
  // Once, complete, after the last frame (or a requested stop, marked unfinished): a run
  // that fails must not replace an earlier run's summary.json with a partial one.
  state.finished = result.stop_signal == 0;
  state.stop_signal = result.stop_signal;
  state.writer = writer.stats();
  write_summary(options.out_dir / run_layout::kSummaryJson, config, sequence_, options, records, n,
                state);
  return result;
}

}  // namespace hazmap
