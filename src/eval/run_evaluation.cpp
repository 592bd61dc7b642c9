#include "hazmap/eval/run_evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

#include "hazmap/core/progress.hpp"
#include <yaml-cpp/yaml.h>

#include "io/json_writer.hpp"
#include "hazmap/camera/stereo_calibration.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/core/number_text.hpp"
#include "hazmap/eval/html_report.hpp"
#include "hazmap/eval/grid_checks.hpp"
#include "hazmap/eval/plot.hpp"
#include "hazmap/hazard/hazard_params.hpp"
#include "hazmap/hazard/wheel_ring.hpp"
#include "hazmap/io/atomic_file.hpp"
#include "hazmap/io/calibration_file.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/io/jdem.hpp"
#include "hazmap/io/run_layout.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/map/layer_stack.hpp"
#include "hazmap/rules/rule_registry.hpp"

namespace hazmap::eval {

namespace fs = std::filesystem;

std::vector<EvaluatedLayer> evaluated_layers(const Config& config, bool with_footprint) {
  const HazardParams params = resolve_hazard_params(config);
  std::vector<EvaluatedLayer> layers;
  for (size_t i = 0; i < config.map.layers.size(); ++i) {
    const LayerConfig& lc = config.map.layers[i];
    EvaluatedLayer l;
    l.name = run_layout::layer_id(i);
    l.index = static_cast<int>(i);
    l.resolution_m = lc.resolution_m;
    l.rule = rule_name(lc.rule);
    l.h_min_m = params.layers[i].h_min_m;
    l.h_min_source = params.layers[i].h_min_source;
    layers.push_back(l);
  }
  if (config.map.layers.empty()) return layers;
  // SPEC 8.4, 10: both maps are at the finest resolution and must show every obstacle of
  // the critical height.
  const std::pair<const char*, std::string> maps[] = {
      {"fused", run_layout::jdem_file(run_layout::kFusedHazard)},
      {"footprint", run_layout::jdem_file(run_layout::kFootprintHazard)}};
  for (const auto& [name, file] : maps) {
    if (std::string(name) == "footprint" && !with_footprint) continue;
    EvaluatedLayer l;
    l.name = name;
    l.rule = name;
    l.resolution_m = config.map.layers.front().resolution_m;
    l.h_min_m = params.critical_height_m;
    l.h_min_source = params.critical_height_source;
    l.hazard_file = file;
    if (std::string(name) == "footprint") l.gt_dilation_m = params.footprint_radius_m;
    layers.push_back(l);
  }
  return layers;
}

namespace {

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot read");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

namespace {

/// RUN/summary.json, which is JSON, read as YAML (a superset).
YAML::Node load_summary(const fs::path& run_dir) {
  const fs::path summary = run_dir / run_layout::kSummaryJson;
  if (!fs::exists(summary))
    throw Error(summary.string() + ": missing (is " + run_dir.string() + " the OUT of hazmap run?)");
  try {
    return YAML::LoadFile(summary.string());
  } catch (const YAML::Exception& e) {
    throw Error(summary.string() + ": " + e.what());
  }
}

/// A string-valued key of summary.json; "" when absent.
std::string summary_string(const YAML::Node& root, const char* key, const fs::path& run_dir) {
  try {
    return root[key] ? root[key].as<std::string>() : std::string();
  } catch (const YAML::Exception& e) {
    throw Error((run_dir / run_layout::kSummaryJson).string() + ": \"" + key + "\": " + e.what());
  }
}

Config config_from_summary(const YAML::Node& root, const fs::path& run_dir) {
  // settings_yaml is the full configuration as used, parsed by the same strict loader as
  // a config file.
  const std::string summary = (run_dir / run_layout::kSummaryJson).string();
  if (!root["settings_yaml"]) throw Error(summary + ": no \"settings_yaml\" key");
  return parse_config(summary_string(root, "settings_yaml", run_dir), summary + " settings_yaml");
}

RunSource source_from_summary(const YAML::Node& root, const fs::path& run_dir) {
  RunSource source;
  source.sequence = summary_string(root, "sequence", run_dir);
  const std::string hex = summary_string(root, "poses_fingerprint", run_dir);
  if (!hex.empty()) {
    source.poses_fingerprint = parse_fingerprint_hex(hex);
    if (!source.poses_fingerprint)
      throw Error((run_dir / run_layout::kSummaryJson).string() + ": \"poses_fingerprint\" '" +
                  hex + "' is not 16 hexadecimal digits");
  }
  return source;
}

void check_source(const RunSource& source, const fs::path& run_dir, const fs::path& sequence_dir) {
  if (!source.poses_fingerprint) {
    spdlog::warn("{}: records no poses fingerprint (a run made before hazmap recorded one): "
                 "cannot check that it was made from {}",
                 (run_dir / run_layout::kSummaryJson).string(), sequence_dir.string());
    return;
  }
  const std::uint64_t given = read_poses_fingerprint(sequence_dir);
  if (given == *source.poses_fingerprint) return;
  const std::string given_abs = absolute_folder(sequence_dir).string();
  if (given_abs == source.sequence)
    throw Error("run " + run_dir.string() + " was made from " + source.sequence +
                " (poses fingerprint " + fingerprint_hex(*source.poses_fingerprint) +
                "), whose poses.txt has changed since (now " + fingerprint_hex(given) +
                "): run it again on the sequence as it is");
  throw Error("run " + run_dir.string() + " was made from sequence " +
              (source.sequence.empty() ? std::string("(not recorded)") : source.sequence) +
              " (poses fingerprint " + fingerprint_hex(*source.poses_fingerprint) + "), not from " +
              given_abs + " (" + fingerprint_hex(given) +
              "): evaluate it against the sequence it was run on");
}

}  // namespace

Config read_run_config(const fs::path& run_dir) {
  return config_from_summary(load_summary(run_dir), run_dir);
}

RunSource read_run_source(const fs::path& run_dir) {
  return source_from_summary(load_summary(run_dir), run_dir);
}

void check_run_sequence(const fs::path& run_dir, const fs::path& sequence_dir) {
  check_source(read_run_source(run_dir), run_dir, sequence_dir);
}

DenseGrid read_dense_grid(const fs::path& path) {
  const JdemGrid j = read_jdem(path);
  if (j.yaw_rad != 0.0) throw Error(path.string() + ": rotated grids (yaw != 0) are not supported");
  return static_cast<const DenseGrid&>(j);
}

GroundTruth read_ground_truth(const fs::path& sequence_dir) {
  GroundTruth gt;
  for (const char* name : {"gt_height.jdem", "gt_hazard.jdem"})
    if (!fs::exists(sequence_dir / name))
      throw Error((sequence_dir / name).string() +
                  ": missing ground truth (simulate with --ground-truth)");
  gt.height = read_dense_grid(sequence_dir / "gt_height.jdem");
  gt.hazard = read_dense_grid(sequence_dir / "gt_hazard.jdem");
  check_same_geometry(gt.hazard, (sequence_dir / "gt_hazard.jdem").string(), gt.height,
                      (sequence_dir / "gt_height.jdem").string());
  return gt;
}

namespace {

std::map<std::string, Pose3d> read_pose_map(const fs::path& path) {
  std::map<std::string, Pose3d> poses;
  for (const auto& [name, pose] : parse_poses(read_text(path), path.string()))
    poses[name] = pose.T_W_B;
  return poses;
}

std::string fmt(double v, const char* format = "%.6g") {
  return printf_finite(v, format, "nan");
}

// Percent / centimetre cells for people ("-" when undefined).
std::string pct(double fraction) {
  return std::isfinite(fraction) ? fmt(100.0 * fraction, "%.2f") : "-";
}
std::string cm(double metres, const char* format = "%.2f") {
  return std::isfinite(metres) ? fmt(100.0 * metres, format) : "-";
}

const char* kCsvHeader =
    "frame,frame_number,layer,resolution_m,rule,h_min_m,extent_m2,known_m2,unknown_fraction,"
    "height_rms_m,height_samples,gt_hazard_m2,gt_hazard_known_m2,missed_m2,missed_fraction,"
    "missed_of_hazard,false_alarm_m2,false_alarm_fraction,variance_violation,hazard_recall,"
    "hazard_unknown,height_rms_all_m,height_samples_all,variance_violation_all,max_below_m";

// The --near columns: the hazard metrics over the GT pixels near the rover (no heights).
const char* kNearFields[] = {"near_extent_m2",      "near_known_m2",       "near_gt_hazard_m2",
                             "near_hazard_recall",  "near_hazard_unknown", "near_missed_m2",
                             "near_missed_fraction", "near_missed_of_hazard",
                             "near_false_alarm_m2", "near_false_alarm_fraction"};

std::vector<double> near_values(const LayerMetrics& m) {
  return {m.extent_area_m2,    m.known_area_m2,    m.gt_hazard_area_m2,    m.hazard_recall,
          m.hazard_unknown,    m.missed_area_m2,   m.missed_fraction,      m.missed_of_hazard,
          m.false_alarm_area_m2, m.false_alarm_fraction};
}

std::string csv_header(bool with_frame, bool with_near) {
  std::string h = kCsvHeader;
  if (!with_frame) h = h.substr(std::string("frame,frame_number,").size());
  if (with_near)
    for (const char* f : kNearFields) h += std::string(",") + f;
  return h;
}

std::string csv_metrics(const LayerMetrics& m, const LayerMetrics* near) {
  std::ostringstream o;
  o << fmt(m.extent_area_m2) << ',' << fmt(m.known_area_m2) << ',' << fmt(m.unknown_fraction)
    << ',' << fmt(m.height_rms_m) << ',' << m.height_samples << ',' << fmt(m.gt_hazard_area_m2)
    << ',' << fmt(m.gt_hazard_known_area_m2) << ',' << fmt(m.missed_area_m2) << ','
    << fmt(m.missed_fraction) << ',' << fmt(m.missed_of_hazard) << ','
    << fmt(m.false_alarm_area_m2) << ',' << fmt(m.false_alarm_fraction) << ','
    << fmt(m.variance_violation) << ',' << fmt(m.hazard_recall) << ',' << fmt(m.hazard_unknown)
    << ',' << fmt(m.height_rms_all_m) << ',' << m.height_samples_all << ','
    << fmt(m.variance_violation_all) << ',' << fmt(m.max_below_m);
  if (near)
    for (double v : near_values(*near)) o << ',' << fmt(v);
  return o.str();
}

std::string csv_layer(const EvaluatedLayer& l) {
  return l.name + ',' + fmt(l.resolution_m) + ',' + l.rule + ',' + fmt(l.h_min_m);
}

// Frame stems are usually frame numbers ("000012"); fall back to the position.
double frame_number(const std::string& name, size_t position) {
  char* end = nullptr;
  const double v = std::strtod(name.c_str(), &end);
  return (!name.empty() && *end == '\0') ? v : static_cast<double>(position);
}

cv::Vec3b outcome_colour(PixelOutcome o) {
  switch (o) {
    case PixelOutcome::outside: return {255, 255, 255};
    case PixelOutcome::unknown: return {150, 150, 150};
    case PixelOutcome::free_ok: return {190, 225, 190};
    case PixelOutcome::hazard_ok: return {40, 40, 170};
    case PixelOutcome::missed: return {255, 0, 255};
    case PixelOutcome::false_alarm: return {0, 150, 255};
    case PixelOutcome::below_h_min: return {170, 200, 235};
  }
  return {0, 0, 0};
}

// Which outcome a reduced display pixel shows when its block mixes several: errors first,
// so that a thin missed sliver survives the reduction.
int outcome_priority(PixelOutcome o) {
  switch (o) {
    case PixelOutcome::missed: return 6;
    case PixelOutcome::false_alarm: return 5;
    case PixelOutcome::hazard_ok: return 4;
    case PixelOutcome::below_h_min: return 3;
    case PixelOutcome::free_ok: return 2;
    case PixelOutcome::unknown: return 1;
    case PixelOutcome::outside: return 0;
  }
  return 0;
}

// Block-reduces a GT-resolution picture to at most max_px per side: mean of the finite
// values (error maps) or the highest-priority outcome.
DenseGrid reduce(const DenseGrid& g, int max_px, bool outcomes) {
  const int step = std::max(1, (std::max(g.rows, g.cols) + max_px - 1) / max_px);
  if (step == 1) return g;
  DenseGrid out;
  const int rows = (g.rows + step - 1) / step, cols = (g.cols + step - 1) / step;
  out.reset(rows, cols, g.resolution_m * step, g.center_x_m, g.center_y_m, NAN);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      double sum = 0;
      int n = 0, best = -1;
      float best_v = 0;
      for (int rr = r * step; rr < std::min(g.rows, (r + 1) * step); ++rr)
        for (int cc = c * step; cc < std::min(g.cols, (c + 1) * step); ++cc) {
          const float v = g.at(rr, cc);
          if (outcomes) {
            const int p = outcome_priority(static_cast<PixelOutcome>(static_cast<int>(v)));
            if (p > best) best = p, best_v = v;
          } else if (std::isfinite(v)) {
            sum += v;
            ++n;
          }
        }
      out.at(r, c) = outcomes ? best_v : (n ? static_cast<float>(sum / n) : NAN);
    }
  return out;
}

cv::Mat render_outcomes(const DenseGrid& outcome, const std::string& title, int scale) {
  scale = std::max(1, scale);
  const int top = 24;
  cv::Mat img(outcome.rows * scale + top + 6, std::max(outcome.cols * scale, 200) + 4, CV_8UC3,
              cv::Scalar(255, 255, 255));
  for (int r = 0; r < outcome.rows; ++r)
    for (int c = 0; c < outcome.cols; ++c)
      img(cv::Rect(c * scale, top + r * scale, scale, scale))
          .setTo(outcome_colour(static_cast<PixelOutcome>(static_cast<int>(outcome.at(r, c)))));
  put_label(img, title, 2, 16, 0.42, cv::Scalar(0, 0, 0));
  return img;
}

cv::Mat outcome_legend() {
  const std::pair<PixelOutcome, const char*> items[] = {
      {PixelOutcome::free_ok, "free, traversable"}, {PixelOutcome::hazard_ok, "obstacle found"},
      {PixelOutcome::missed, "MISSED obstacle"},    {PixelOutcome::false_alarm, "false alarm"},
      {PixelOutcome::below_h_min, "obstacle < h_min"}, {PixelOutcome::unknown, "unknown"}};
  cv::Mat img(28, 6 * 150, CV_8UC3, cv::Scalar(255, 255, 255));
  int x = 6;
  for (const auto& [o, text] : items) {
    const cv::Vec3b c = outcome_colour(o);
    cv::rectangle(img, cv::Rect(x, 8, 14, 14), cv::Scalar(c[0], c[1], c[2]), cv::FILLED);
    cv::rectangle(img, cv::Rect(x, 8, 14, 14), cv::Scalar(90, 90, 90), 1);
    put_label(img, text, x + 18, 20, 0.4);
    x += 150;
  }
  return img;
}

/// A layer's grids of one frame, each checked as read: hazard classes, and every other
/// grid on the hazard grid's geometry (errors name the files).
LayerMaps read_layer(const fs::path& frame_dir, const EvaluatedLayer& layer) {
  LayerMaps maps;
  const std::size_t i = layer.index < 0 ? 0 : static_cast<std::size_t>(layer.index);
  const fs::path hazard_file =
      frame_dir / (layer.index < 0 ? layer.hazard_file
                                   : run_layout::jdem_file(run_layout::layer_stem(i, "hazard")));
  maps.hazard = read_dense_grid(hazard_file);
  check_hazard_classes(maps.hazard, hazard_file.string());
  if (layer.index < 0) return maps;
  const auto file = [&](const char* quantity) {
    return frame_dir / run_layout::jdem_file(run_layout::layer_stem(i, quantity));
  };
  const auto read_beside = [&](const char* quantity, DenseGrid& into) {
    into = read_dense_grid(file(quantity));
    check_same_geometry(into, file(quantity).string(), maps.hazard, hazard_file.string());
  };
  read_beside("height", maps.height);
  if (fs::exists(file("variance"))) read_beside("variance", maps.variance);
  if (rule_has_plane(layer.rule)) {
    read_beside("slope_x", maps.slope_x);
    read_beside("slope_y", maps.slope_y);
  }
  return maps;
}

// Seen-cell columns (seen_confusion.hpp): seen_<field> and, with --near, near_seen_<field>.
std::string seen_header(bool with_near) {
  std::string h;
  for (const char* prefix : {"seen_", "near_seen_"}) {
    if (!with_near && std::string(prefix) == "near_seen_") continue;
    for (const auto& [name, v] : seen_fields(SeenSums{})) h += std::string(",") + prefix + name;
  }
  return h;
}
std::string seen_row(const SeenSums& all, const SeenSums* near) {
  std::string o;
  for (const auto& [name, v] : seen_fields(all)) o += "," + fmt(v);
  if (near)
    for (const auto& [name, v] : seen_fields(*near)) o += "," + fmt(v);
  return o;
}

/// The seen map of the run's frames (seen_confusion.hpp) from SEQ/depth/<name>.tiff, with
/// the left camera of SEQ/calibration.yaml at the true poses; `frame_index[f]`: the index
/// of the last depth frame at or before written frame f (-1: none).
SeenMap read_seen_map(const fs::path& sequence_dir, const GroundTruth& gt, const Config& config,
                      const std::map<std::string, Pose3d>& true_poses, const fs::path& pose_file,
                      const std::vector<std::string>& frames, std::vector<int>* frame_index,
                      const LateralGate& gate_in, SeenMap* gated) {
  const fs::path depth_dir = sequence_dir / "depth";
  std::vector<std::string> stems;
  for (const auto& entry : fs::directory_iterator(depth_dir))
    if (entry.is_regular_file() && entry.path().extension() == ".tiff" &&
        entry.path().stem().string() >= frames.front())  // from the run's first frame
      stems.push_back(entry.path().stem().string());
  std::sort(stems.begin(), stems.end());
  const StereoCalibration calib = load_stereo_calibration(sequence_dir / "calibration.yaml");
  LateralGate gate = gate_in;
  gate.baseline_m = calib.T.norm();
  DepthCamera camera;
  camera.fx = calib.left.K(0, 0);
  camera.fy = calib.left.K(1, 1);
  camera.cx = calib.left.K(0, 2);
  camera.cy = calib.left.K(1, 2);
  camera.distortion = calib.left.D;
  SeenMap seen(gt.height);
  for (size_t k = 0; k < stems.size(); ++k) {
    const fs::path file = depth_dir / (stems[k] + ".tiff");
    const auto pose = true_poses.find(stems[k]);
    if (pose == true_poses.end())
      throw Error(pose_file.string() + ": no pose for depth image " + file.string());
    const cv::Mat depth = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
    if (depth.empty() || depth.type() != CV_32FC1)
      throw Error(file.string() + ": not a float32 one-channel depth image (simulate --depth)");
    seen.add_depth(depth, camera, pose->second * calib.T_B_C, config.stereo.z_max_m,
                   static_cast<int>(k));
    gated->add_depth(depth, camera, pose->second * calib.T_B_C, config.stereo.z_max_m,
                     static_cast<int>(k), &gate);
  }
  frame_index->clear();
  for (const std::string& f : frames)
    frame_index->push_back(
        static_cast<int>(std::upper_bound(stems.begin(), stems.end(), f) - stems.begin()) - 1);
  return seen;
}

/// The columns metrics.csv and summary.csv share, after their frame columns: the layer,
/// its metrics (and the near ones when `near`), its seen-cell sums when `seen` (and the
/// near ones when `near_seen`).
std::string layer_columns(const EvaluatedLayer& layer, const MetricSums& sums,
                          const MetricSums* near, const SeenSums* seen, const SeenSums* near_seen) {
  const LayerMetrics nm = near ? derive_metrics(*near) : LayerMetrics{};
  return csv_layer(layer) + ',' + csv_metrics(derive_metrics(sums), near ? &nm : nullptr) +
         (seen ? seen_row(*seen, near_seen) : "");
}

/// metrics.csv: every frame x layer.
void write_metrics_csv(const RunEvaluation& ev) {
  const fs::path& out = ev.out_dir;
  const bool near = ev.near_radius_m >= 0.0;
  const bool seen = ev.seen_enabled;
  std::ostringstream csv;
  csv << csv_header(true, near) << (seen ? seen_header(near) : "") << '\n';
  for (size_t f = 0; f < ev.frames.size(); ++f)
    for (size_t l = 0; l < ev.layers.size(); ++l)
      csv << ev.frames[f] << ',' << fmt(frame_number(ev.frames[f], f)) << ','
          << layer_columns(ev.layers[l], ev.sums[f][l], near ? &ev.near_sums[f][l] : nullptr,
                           seen ? &ev.seen_sums[f][l] : nullptr,
                           seen && near ? &ev.near_seen_sums[f][l] : nullptr)
          << '\n';
  write_file_atomically(out / "metrics.csv", csv.str());
}

/// summary.csv: pooled per layer; frame columns hold the count of frames.
void write_summary_csv(const RunEvaluation& ev) {
  const fs::path& out = ev.out_dir;
  const bool near = ev.near_radius_m >= 0.0;
  const bool seen = ev.seen_enabled;
  std::ostringstream sum;
  // Seen within the vouching layers' lateral gate (LateralGate), near only: free cells.
  const bool gated = seen && near;
  const char* gated_fields[] = {"free_m2", "free_traversable", "free_unknown", "free_hazard"};
  const auto gated_row = [&](const SeenSums& p) {
    return "," + fmt(p.area_m2(kTruthFree)) + "," + fmt(p.fraction(kTruthFree, 1)) + "," +
           fmt(p.fraction(kTruthFree, 0)) + "," + fmt(p.fraction(kTruthFree, 2));
  };
  sum << "frames," << csv_header(false, near) << (seen ? seen_header(near) : "");
  if (gated) {
    for (const char* name : gated_fields) sum << ",near_gated_" << name;
    for (const char* name : gated_fields) sum << ",near_ring_gated_" << name;
  }
  sum << '\n';
  for (size_t l = 0; l < ev.layers.size(); ++l)
    sum << ev.frames.size() << ','
        << layer_columns(ev.layers[l], ev.pooled[l], near ? &ev.near_pooled[l] : nullptr,
                         seen ? &ev.seen_pooled[l] : nullptr,
                         seen && near ? &ev.near_seen_pooled[l] : nullptr)
        << (gated ? gated_row(ev.near_gated_pooled[l]) + gated_row(ev.near_ring_gated_pooled[l]) : "")
        << '\n';
  write_file_atomically(out / "summary.csv", sum.str());
}

/// metrics.json: the pooled and per-frame metrics with the settings used.
void write_metrics_json(const EvaluationOptions& options, const RunEvaluation& ev,
                        const Config& config) {
  const fs::path& out = ev.out_dir;
  const bool near = ev.near_radius_m >= 0.0;
  const bool seen = ev.seen_enabled;
  JsonWriter j;
  j.begin_object();
  j.key("hazmap_version").value(HAZMAP_VERSION);
  j.key("run").value(options.run_dir.string());
  j.key("sequence").value(options.sequence_dir.string());
  j.key("frames").value(ev.frames.size());
  j.key("true_poses").value(ev.used_true_poses ? std::string("poses_true.txt")
                                               : std::string("poses.txt (no drift)"));
  if (near) j.key("near_radius_m").value(ev.near_radius_m);
  j.key("pooling").value(
      "sums over all frames: areas add up, RMS over all pixels, fractions of the pooled areas");
  j.key("layers").begin_array();
  for (size_t l = 0; l < ev.layers.size(); ++l) {
    const EvaluatedLayer& L = ev.layers[l];
    const LayerMetrics m = derive_metrics(ev.pooled[l]);
    j.begin_object();
    j.key("layer").value(L.name);
    j.key("resolution_m").value(L.resolution_m);
    j.key("rule").value(L.rule);
    j.key("h_min_m").value(L.h_min_m);
    j.key("h_min_source").value(L.h_min_source);
    j.key("extent_m2").value(m.extent_area_m2);
    j.key("known_m2").value(m.known_area_m2);
    j.key("unknown_fraction").value(m.unknown_fraction);
    j.key("height_rms_m").value(m.height_rms_m);
    j.key("height_samples").value(m.height_samples);
    j.key("gt_hazard_m2").value(m.gt_hazard_area_m2);
    j.key("gt_hazard_known_m2").value(m.gt_hazard_known_area_m2);
    j.key("missed_m2").value(m.missed_area_m2);
    j.key("missed_fraction").value(m.missed_fraction);
    j.key("missed_of_hazard").value(m.missed_of_hazard);
    j.key("false_alarm_m2").value(m.false_alarm_area_m2);
    j.key("false_alarm_fraction").value(m.false_alarm_fraction);
    j.key("variance_violation").value(m.variance_violation);
    j.key("hazard_recall").value(m.hazard_recall);
    j.key("hazard_unknown").value(m.hazard_unknown);
    j.key("height_rms_all_m").value(m.height_rms_all_m);
    j.key("height_samples_all").value(m.height_samples_all);
    j.key("variance_violation_all").value(m.variance_violation_all);
    j.key("max_below_m").value(m.max_below_m);
    if (near) {
      const std::vector<double> v = near_values(derive_metrics(ev.near_pooled[l]));
      for (size_t k = 0; k < v.size(); ++k) j.key(kNearFields[k]).value(v[k]);
    }
    if (seen) {
      j.key("seen").begin_object();
      for (const auto& [name, v] : seen_fields(ev.seen_pooled[l])) j.key(name).value(v);
      j.end_object();
      if (near) {
        j.key("near_seen").begin_object();
        for (const auto& [name, v] : seen_fields(ev.near_seen_pooled[l])) j.key(name).value(v);
        j.end_object();
        for (const auto& [key, g] : {std::pair<const char*, const SeenSums&>{"near_gated", ev.near_gated_pooled[l]},
                                     {"near_ring_gated", ev.near_ring_gated_pooled[l]}}) {
          j.key(key).begin_object();
          j.key("free_m2").value(g.area_m2(kTruthFree));
          j.key("free_traversable").value(g.fraction(kTruthFree, 1));
          j.key("free_unknown").value(g.fraction(kTruthFree, 0));
          j.key("free_hazard").value(g.fraction(kTruthFree, 2));
          j.end_object();
        }
      }
    }
    const LayerMetrics last = derive_metrics(ev.sums.back()[l]);
    j.key("last_frame").begin_object();
    j.key("height_rms_m").value(last.height_rms_m);
    j.key("missed_m2").value(last.missed_area_m2);
    j.key("false_alarm_m2").value(last.false_alarm_area_m2);
    j.key("unknown_fraction").value(last.unknown_fraction);
    j.key("hazard_recall").value(last.hazard_recall);
    j.end_object();
    j.end_object();
  }
  j.end_array();
  j.key("settings_yaml").value(to_yaml(config));
  j.end_object();
  write_file_atomically(out / "metrics.json", j.str());
}

/// metrics_over_time.png: each metric per written frame and layer.
void write_metrics_plot(const RunEvaluation& ev) {
  const fs::path& out = ev.out_dir;
  const bool near = ev.near_radius_m >= 0.0;
  struct Panel {
    const char* title;
    const char* y_label;
    double scale;
    double LayerMetrics::*field;
  };
  const Panel panels[] = {
      {"height RMS", "cm", 100.0, &LayerMetrics::height_rms_m},
      {"missed obstacle area / known obstacle area", "%", 100.0, &LayerMetrics::missed_of_hazard},
      {"false alarm area / known area", "%", 100.0, &LayerMetrics::false_alarm_fraction},
      {"unknown fraction of the window", "%", 100.0, &LayerMetrics::unknown_fraction},
      {"variance violations (|e| > 3 sigma)", "%", 100.0, &LayerMetrics::variance_violation},
      {"missed obstacle area", "cm^2", 1e4, &LayerMetrics::missed_area_m2},
      {"hazard recall (obstacles labelled hazard)", "%", 100.0, &LayerMetrics::hazard_recall},
      {"obstacles labelled unknown", "%", 100.0, &LayerMetrics::hazard_unknown},
      {"height RMS, every published height", "cm", 100.0, &LayerMetrics::height_rms_all_m},
      {"variance violations, every published height", "%", 100.0,
       &LayerMetrics::variance_violation_all},
      {"deepest cell below the terrain", "cm", 100.0, &LayerMetrics::max_below_m},
  };
  std::vector<cv::Mat> charts;
  const auto add_chart = [&](const Panel& p, const std::vector<std::vector<MetricSums>>& sums) {
    LineChart chart;
    chart.title = p.title;
    chart.x_label = "frame";
    chart.y_label = p.y_label;
    for (size_t l = 0; l < ev.layers.size(); ++l) {
      // Hazard-only maps have no heights.
      if (ev.layers[l].index < 0 &&
          (p.field == &LayerMetrics::height_rms_m || p.field == &LayerMetrics::variance_violation ||
           p.field == &LayerMetrics::height_rms_all_m ||
           p.field == &LayerMetrics::variance_violation_all ||
           p.field == &LayerMetrics::max_below_m))
        continue;
      Series s;
      s.name = ev.layers[l].name + " " + fmt(ev.layers[l].resolution_m * 100, "%g") + " cm";
      for (size_t f = 0; f < ev.frames.size(); ++f) {
        s.x.push_back(frame_number(ev.frames[f], f));
        s.y.push_back(derive_metrics(sums[f][l]).*(p.field) * p.scale);
      }
      chart.series.push_back(std::move(s));
    }
    charts.push_back(plot_lines(chart));
  };
  for (const Panel& p : panels) add_chart(p, ev.sums);
  std::string near_title_recall, near_title_missed;
  if (near) {
    near_title_recall = "hazard recall within " + fmt(ev.near_radius_m, "%g") + " m of the rover";
    near_title_missed = "missed obstacle area within " + fmt(ev.near_radius_m, "%g") + " m";
    add_chart({near_title_recall.c_str(), "%", 100.0, &LayerMetrics::hazard_recall}, ev.near_sums);
    add_chart({near_title_missed.c_str(), "cm^2", 1e4, &LayerMetrics::missed_area_m2},
              ev.near_sums);
  }
  write_png(out / "metrics_over_time.png", tile_images(charts, 2));
}

/// The report's pooled summary table, one row per layer.
HtmlSection summary_section(const RunEvaluation& ev) {
  const bool near = ev.near_radius_m >= 0.0;
  HtmlSection summary;
  summary.heading = "Summary per layer (SPEC 10, pooled over frames)";
  summary.text =
      "Known = the layer gives a class other than unknown. Height RMS over known pixels "
      "without obstacle (CCM layers queried on their cell planes). Missed = obstacle at least "
      "h_min high that the layer calls traversable; false alarm = obstacle-free ground the "
      "layer calls a hazard. Recall = share of the obstacle pixels (>= h_min) in the window "
      "labelled hazard; obstacles unknown = share labelled unknown. \"All heights\" columns "
      "count every published height, cells of unknown class included; \"deepest below "
      "terrain\" is the largest amount by which a cell's published height lies below the "
      "ground truth at its centre (any class; negative: none below). The fused and "
      "footprint maps are scored with the critical height as h_min; the footprint map "
      "against obstacles dilated by the footprint radius (where the rover's centre may be).";
  if (near)
    summary.text += " Near = ground-truth pixels within " + fmt(ev.near_radius_m, "%g") +
                    " m of the rover's true position in each frame.";
  HtmlTable table;
  table.id = "summary";
  table.header = {"layer", "cell [cm]", "rule", "h_min [cm]", "h_min from", "height RMS [cm]", "unknown [%]",
                  "obstacles known [m2]", "missed [m2]", "missed [% of known]",
                  "missed [% of obstacles]", "false alarm [m2]", "false alarm [% of known]",
                  "variance violations [%]", "recall [%]", "obstacles unknown [%]",
                  "height RMS, all heights [cm]", "variance violations, all heights [%]",
                  "deepest below terrain [cm]"};
  if (near)
    for (const char* h : {"near recall [%]", "near obstacles unknown [%]", "near missed [m2]",
                          "near false alarm [% of known]"})
      table.header.push_back(h);
  for (size_t l = 0; l < ev.layers.size(); ++l) {
    const EvaluatedLayer& L = ev.layers[l];
    const LayerMetrics m = derive_metrics(ev.pooled[l]);
    table.rows.push_back({L.name, fmt(L.resolution_m * 100, "%g"), L.rule,
                          cm(L.h_min_m, "%.1f"), L.h_min_source,
                          cm(m.height_rms_m, "%.3f"), pct(m.unknown_fraction),
                          fmt(m.gt_hazard_known_area_m2, "%.4f"), fmt(m.missed_area_m2, "%.4f"),
                          pct(m.missed_fraction), pct(m.missed_of_hazard),
                          fmt(m.false_alarm_area_m2, "%.4f"), pct(m.false_alarm_fraction),
                          pct(m.variance_violation), pct(m.hazard_recall),
                          pct(m.hazard_unknown), cm(m.height_rms_all_m, "%.3f"),
                          pct(m.variance_violation_all), cm(m.max_below_m, "%.1f")});
    if (near) {
      const LayerMetrics n = derive_metrics(ev.near_pooled[l]);
      for (const std::string& v : {pct(n.hazard_recall), pct(n.hazard_unknown),
                                   fmt(n.missed_area_m2, "%.4f"), pct(n.false_alarm_fraction)})
        table.rows.back().push_back(v);
    }
  }
  summary.tables.push_back(table);
  return summary;
}

/// The report's seen-cells section: what the map calls the pixels the camera has seen.
HtmlSection seen_section(const RunEvaluation& ev) {
  const bool near = ev.near_radius_m >= 0.0;
  HtmlSection section;
  section.heading = "Seen cells: does the map see? (pooled over frames)";
  section.text =
      "Over the ground-truth pixels the left camera has seen so far (a depth pixel within "
      "stereo.z_max fell in them, in this or an earlier frame)" +
      std::string(near ? ", within " + fmt(ev.near_radius_m, "%g") + " m of the rover" : "") +
      ", inside each map's window: what the map calls them. Free = no obstacle; obstacle = "
      "at least h_min high; tall = at least 2 h_min. The footprint map is scored against "
      "obstacles dilated by the footprint radius, over pixels whose whole footprint disc "
      "was seen. Reasons: of the free pixels left unknown, the share for which each reason "
      "held (any) and was the only one (sole); \"unrecorded\": the run wrote no "
      "L<i>_unknown_reason grids (output.unknown_reasons).";
  const std::vector<SeenSums>& pooled = near ? ev.near_seen_pooled : ev.seen_pooled;
  HtmlTable t;
  t.id = "seen";
  t.header = {"layer", "free seen [m2]", "free -> traversable [%]", "free -> unknown [%]",
              "free -> hazard [%]", "obstacle seen [m2]", "obstacle -> hazard [%]",
              "obstacle -> unknown [%]", "obstacle -> traversable [%]",
              "tall obstacle -> hazard [%]"};
  HtmlTable r;
  r.id = "unknown_reasons";
  r.header = {"layer"};
  for (const char* name : kUnknownReasonNames)
    r.header.push_back(std::string(name) + " any / sole [%]");
  r.header.push_back("unrecorded [%]");
  for (size_t l = 0; l < ev.layers.size(); ++l) {
    const SeenSums& p = pooled[l];
    t.rows.push_back({ev.layers[l].name, fmt(p.area_m2(kTruthFree), "%.3f"),
                      pct(p.fraction(kTruthFree, 1)), pct(p.fraction(kTruthFree, 0)),
                      pct(p.fraction(kTruthFree, 2)), fmt(p.area_m2(kTruthHazard), "%.4f"),
                      pct(p.fraction(kTruthHazard, 2)), pct(p.fraction(kTruthHazard, 0)),
                      pct(p.fraction(kTruthHazard, 1)), pct(p.fraction(kTruthTall, 2))});
    const std::size_t unknown = p.count[kTruthFree][0];
    const auto share = [&](std::size_t n) {
      return unknown == 0 ? std::string("-") : pct(static_cast<double>(n) / static_cast<double>(unknown));
    };
    r.rows.push_back({ev.layers[l].name});
    for (int b = 0; b < kUnknownReasonCount; ++b)
      r.rows.back().push_back(share(p.reason_any[kTruthFree][b]) + " / " +
                              share(p.reason_sole[kTruthFree][b]));
    r.rows.back().push_back(share(p.reason_unrecorded[kTruthFree]));
  }
  section.tables.push_back(t);
  section.tables.push_back(r);
  return section;
}

/// report.html: the tables, the plot, the error maps and the frame viewer.
void write_report(const EvaluationOptions& options, const RunEvaluation& ev,
                  const std::vector<std::pair<std::string, fs::path>>& error_pngs) {
  const fs::path& out = ev.out_dir;
  HtmlPage page;
  const fs::path run_name = options.run_dir.lexically_normal().filename().empty()
                                ? options.run_dir.lexically_normal().parent_path().filename()
                                : options.run_dir.lexically_normal().filename();
  page.title = "hazmap evaluation: " + run_name.string();
  page.subtitle = "run " + options.run_dir.string() + " | sequence " +
                  options.sequence_dir.string() + " | " + std::to_string(ev.frames.size()) +
                  " frames | map frame: " +
                  (ev.used_true_poses ? "drifted poses, ground truth placed with poses_true.txt"
                                      : "true poses");
  page.sections.push_back(summary_section(ev));
  if (ev.seen_enabled) page.sections.push_back(seen_section(ev));
  HtmlSection over_time;
  over_time.heading = "Metrics over time";
  over_time.figures.push_back({"metrics_over_time.png", "each metric per written frame and layer"});
  page.sections.push_back(over_time);
  HtmlSection errors;
  errors.heading = "Error maps";
  errors.text = "Per layer: |h - h_gt| over the layer's window (left) and what happened at each "
                "ground-truth pixel (right).";
  for (const auto& [frame, png] : error_pngs)
    errors.figures.push_back({png.filename().string(), "frame " + frame});
  page.sections.push_back(errors);
  // Frame viewer: the mosaics of `hazmap run --mosaic`, else the fused hazard maps.
  for (size_t f = 0; f < ev.frames.size(); ++f) {
    fs::path image = run_layout::mosaic_png(options.run_dir, ev.frames[f]);
    if (!fs::exists(image))
      image = run_layout::frame_dir(options.run_dir, ev.frames[f]) /
              run_layout::png_file(run_layout::kFusedHazard);
    if (!fs::exists(image)) continue;
    page.viewer_images.push_back(fs::relative(image, out).generic_string());
    page.viewer_labels.push_back("frame " + ev.frames[f]);
  }
  page.viewer_heading = fs::exists(options.run_dir / run_layout::kMosaicDir)
                            ? "Frame by frame (mosaic of every layer)"
                            : "Frame by frame (fused hazard map; run with --mosaic for all layers)";
  write_file_atomically(out / "report.html", render_html(page));
}

void write_outputs(const EvaluationOptions& options, const RunEvaluation& ev,
                   const std::vector<std::pair<std::string, fs::path>>& error_pngs,
                   const Config& config) {
  write_metrics_csv(ev);
  write_summary_csv(ev);
  write_metrics_json(options, ev, config);
  write_metrics_plot(ev);
  if (options.write_report) write_report(options, ev, error_pngs);
}

/// The run's frame folders, sorted by name.
std::vector<std::string> run_frames(const fs::path& frames_dir) {
  if (!fs::is_directory(frames_dir)) throw Error(frames_dir.string() + ": missing");
  std::vector<std::string> frames;
  for (const auto& entry : fs::directory_iterator(frames_dir))
    if (entry.is_directory()) frames.push_back(entry.path().filename().string());
  std::sort(frames.begin(), frames.end());
  if (frames.empty()) throw Error(frames_dir.string() + ": no frame folders");
  return frames;
}

/// The footprint map is newer than the others: a run without it is scored without it (and
/// one with it in some frames only, too, with a warning).
bool footprint_in_every_frame(const fs::path& frames_dir, const std::vector<std::string>& frames) {
  size_t footprint_frames = 0;
  for (const std::string& f : frames)
    footprint_frames +=
        fs::exists(frames_dir / f / run_layout::jdem_file(run_layout::kFootprintHazard));
  if (footprint_frames == frames.size()) return true;
  if (footprint_frames > 0)
    spdlog::warn("footprint_hazard.jdem is in {} of {} frames only: footprint not scored",
                 footprint_frames, frames.size());
  return false;
}

/// The sequence's poses: poses.txt (those the run used) and, when the run drove on
/// drifted poses, poses_true.txt.
struct SequencePoses {
  fs::path used_file, true_file;
  std::map<std::string, Pose3d> used, truth;
  bool drifted = false;  ///< poses_true.txt is there

  explicit SequencePoses(const fs::path& sequence_dir)
      : used_file(sequence_dir / "poses.txt"), true_file(sequence_dir / "poses_true.txt") {
    used = read_pose_map(used_file);
    drifted = fs::exists(true_file);
    if (drifted) truth = read_pose_map(true_file);
  }
  /// Where the rover truly was, and the file that says so.
  const std::map<std::string, Pose3d>& true_poses() const { return drifted ? truth : used; }
  const fs::path& true_pose_file() const { return drifted ? true_file : used_file; }

  /// Ground truth (W) to the run's map frame: the identity, or used * true^-1 for a run on
  /// drifted poses.
  Pose3d T_map_W(const std::string& frame) const {
    if (!drifted) return Pose3d::Identity();
    const auto u = used.find(frame);
    const auto t = truth.find(frame);
    if (u == used.end()) throw Error(used_file.string() + ": no pose for frame " + frame);
    if (t == truth.end()) throw Error(true_file.string() + ": no pose for frame " + frame);
    return u->second * t->second.inverse();
  }
};

/// The vouching layers' most permissive lateral gate (none if one has no gate).
LateralGate vouching_gate(const Config& config, const HazardParams& hazard_params) {
  LateralGate gate;
  gate.ray_model = config.sensor.model == SensorModel::ray;
  gate.pointing_px = config.sensor.pointing_error_px;
  gate.matching_px = config.sensor.disparity_error_px;
  gate.edge_margin_px = right_border_drop_px(config.stereo);
  gate.blank_columns = blank_left_columns(config.stereo);
  for (size_t i = 0; i < config.map.layers.size(); ++i) {
    if (hazard_params.layers[i].h_min_m > hazard_params.critical_height_m) continue;
    const double g = gate_std_m(config.map.layers[i], config.rules);
    gate.max_std_m = g > 0.0 ? std::max(gate.max_std_m, g) : std::numeric_limits<double>::infinity();
  }
  return gate;
}

/// Seen cells (issue 34), from the sequence's depth images: all seen, and seen within the
/// vouching layers' lateral gate; each also as "whole footprint disc seen".
struct SeenCells {
  std::vector<int> index;  ///< per written frame: its last depth frame
  std::optional<SeenMap> seen, footprint, gated, gated_footprint;
  /// Gated, and so are the wheel ring's samples about it (SPEC 8.2-8.3: a cell's proof
  /// reads the terrain under the wheels); for the footprint map the whole disc of the
  /// footprint's radius plus the ring's (every cell under the body, and its ring).
  std::optional<SeenMap> ring_gated, ring_gated_footprint;

  const SeenMap& seen_for(const EvaluatedLayer& L) const {
    return L.gt_dilation_m > 0.0 ? *footprint : *seen;
  }
  const SeenMap& gated_for(const EvaluatedLayer& L) const {
    return L.gt_dilation_m > 0.0 ? *gated_footprint : *gated;
  }
  const SeenMap& ring_gated_for(const EvaluatedLayer& L) const {
    return L.gt_dilation_m > 0.0 ? *ring_gated_footprint : *ring_gated;
  }
};

SeenCells read_seen_cells(const fs::path& sequence_dir, const GroundTruth& gt,
                          const Config& config, const SequencePoses& poses,
                          const std::vector<std::string>& frames, bool with_footprint) {
  const HazardParams hazard_params = resolve_hazard_params(config);
  const LateralGate gate = vouching_gate(config, hazard_params);
  SeenCells s;
  s.gated.emplace(gt.height);
  s.seen.emplace(read_seen_map(sequence_dir, gt, config, poses.true_poses(),
                               poses.true_pose_file(), frames, &s.index, gate, &*s.gated));
  const double ring_m = config.hazard.wheelbase_m / 2.0;  // the classifiers' WheelRing
  s.ring_gated.emplace(s.gated->with_ring(ring_m, WheelRing::kSamples));
  if (with_footprint) {
    s.footprint.emplace(s.seen->whole_disc(hazard_params.footprint_radius_m));
    s.gated_footprint.emplace(s.gated->whole_disc(hazard_params.footprint_radius_m));
    s.ring_gated_footprint.emplace(s.gated->whole_disc(hazard_params.footprint_radius_m + ring_m));
  }
  return s;
}

/// --error-maps: the frames to draw (default: the last one; "all": every one).
struct ErrorMapFrames {
  std::set<std::string> names;
  bool all = false;
  bool wanted(const std::string& frame) const { return all || names.count(frame) > 0; }
};

ErrorMapFrames error_map_frames(const EvaluationOptions& options,
                                const std::vector<std::string>& frames) {
  ErrorMapFrames e;
  e.names.insert(options.error_map_frames.begin(), options.error_map_frames.end());
  if (e.names.empty()) e.names.insert(frames.back());
  e.all = e.names.count("all") > 0;
  for (const std::string& f : e.names)
    if (f != "all" && !std::binary_search(frames.begin(), frames.end(), f))
      throw Error("--error-maps: frame '" + f + "' was not written by the run");
  return e;
}

/// The ground truth each layer is scored against: the footprint map's has its obstacles
/// dilated by the footprint radius (one per radius in use, made once).
class LayerTruths {
 public:
  LayerTruths(const GroundTruth& gt, const std::vector<EvaluatedLayer>& layers) : gt_(gt) {
    for (const EvaluatedLayer& L : layers)
      if (L.gt_dilation_m > 0.0 && !dilated_.count(L.gt_dilation_m))
        dilated_.emplace(L.gt_dilation_m, dilate_obstacles(gt, L.gt_dilation_m));
  }
  const GroundTruth& operator()(const EvaluatedLayer& L) const {
    return L.gt_dilation_m > 0.0 ? dilated_.at(L.gt_dilation_m) : gt_;
  }

 private:
  const GroundTruth& gt_;
  std::map<double, GroundTruth> dilated_;
};

/// The --near disc of a frame: around where the rover truly is (poses_true.txt when the
/// run drove on drifted poses).
NearRegion near_region(const SequencePoses& poses, const std::string& frame, double radius_m) {
  const auto p = poses.true_poses().find(frame);
  if (p == poses.true_poses().end())
    throw Error(poses.true_pose_file().string() + ": no pose for frame " + frame + " (--near)");
  NearRegion near;
  near.x_m = p->second.translation().x();
  near.y_m = p->second.translation().y();
  near.radius_m = radius_m;
  return near;
}

/// The unknown-reason grid a seen-cell score reads for layer l of a frame: L<i>'s from
/// the run (when it wrote them), the fused map's made from the layers' (frame_layers and
/// frame_reasons: this frame's layers before l). Empty: none recorded.
DenseGrid unknown_reasons(const fs::path& frame_dir, const std::vector<EvaluatedLayer>& layers,
                          size_t l, const std::vector<LayerMaps>& frame_layers,
                          const std::vector<DenseGrid>& frame_reasons) {
  const EvaluatedLayer& L = layers[l];
  DenseGrid reasons;
  if (L.index >= 0) {
    const fs::path file = frame_dir / (L.name + "_unknown_reason.jdem");
    if (fs::exists(file)) reasons = read_dense_grid(file);
  } else if (L.name == "fused") {
    std::vector<ReasonLayer> inputs;
    for (size_t k = 0; k < l; ++k)
      if (layers[k].index >= 0)
        inputs.push_back({&frame_layers[k].hazard,
                          frame_reasons[k].rows > 0 ? &frame_reasons[k] : nullptr,
                          layers[k].h_min_m});
    const bool recorded = std::any_of(inputs.begin(), inputs.end(),
                                      [](const ReasonLayer& r) { return r.reasons; });
    if (recorded) reasons = fused_unknown_reasons(inputs, L.h_min_m, frame_layers[l].hazard);
  }
  return reasons;
}

/// A layer's two error-map tiles: |h - h_gt| (a blank square for the hazard-only maps)
/// and each ground-truth pixel's outcome.
void add_error_tiles(const EvaluatedLayer& L, const ErrorMaps& maps, std::vector<cv::Mat>& tiles) {
  const std::string label = L.name + " " + fmt(L.resolution_m * 100, "%g") + " cm " + L.rule;
  const DenseGrid err = reduce(maps.abs_error_m, 300, false);
  const DenseGrid out = reduce(maps.outcome, 300, true);
  const int scale = std::max(
      1, static_cast<int>(std::lround(300.0 / std::max(1, std::max(err.rows, err.cols)))));
  if (L.index >= 0)
    tiles.push_back(render_scalar_grid(err, 0.0, 0.05, label + ": |h - h_gt| (clamped)", "m", scale));
  else
    tiles.push_back(cv::Mat(24, 24, CV_8UC3, cv::Scalar(255, 255, 255)));
  tiles.push_back(render_outcomes(out, label + ": h_min " + cm(L.h_min_m, "%.1f") + " cm", scale));
}

/// A frame's error-map page, PNG-encoded: the tiles two by two over the outcome legend.
std::vector<unsigned char> error_page_png(const std::vector<cv::Mat>& tiles, const fs::path& file) {
  cv::Mat grid = tile_images(tiles, 2);
  const cv::Mat legend = outcome_legend();
  cv::Mat page(grid.rows + legend.rows, std::max(grid.cols, legend.cols), CV_8UC3,
               cv::Scalar(255, 255, 255));
  grid.copyTo(page(cv::Rect(0, 0, grid.cols, grid.rows)));
  legend.copyTo(page(cv::Rect(0, grid.rows, legend.cols, legend.rows)));
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", page, png)) throw Error(file.string() + ": PNG encoding failed");
  return png;
}

/// What every frame is scored with: the run's frames folder, the truths, the poses and
/// the seen cells (when the sequence has depth images).
struct FrameScorer {
  const EvaluationOptions& options;
  fs::path frames_dir;
  const LayerTruths& truth_for;
  const SequencePoses& poses;
  const SeenCells* seen;  ///< null: no depth images

  /// Scores frame f's every layer into ev (its rows and the pooled sums); its error-map
  /// page, when wanted, into error_pages.
  void score(RunEvaluation& ev, size_t f, bool maps_wanted,
             std::vector<std::pair<std::string, std::vector<unsigned char>>>& error_pages) const;

  /// One layer's metrics; an error names the frame's layer files.
  MetricSums score_metrics(const std::string& frame, const EvaluatedLayer& L,
                           const LayerMaps& layer, const Pose3d& T_map_W, ErrorMaps* maps,
                           const NearRegion* near, MetricSums* near_sums) const {
    try {
      return score_layer(layer, truth_for(L), T_map_W, L.h_min_m, maps, near, near_sums);
    } catch (const Error& e) {
      // The grids' own check knows no file: name the frame's layer files here.
      throw Error((frames_dir / frame / (L.name + "_*.jdem")).string() + " (frame " + frame +
                  "): " + e.what());
    }
  }
};

void FrameScorer::score(
    RunEvaluation& ev, size_t f, bool maps_wanted,
    std::vector<std::pair<std::string, std::vector<unsigned char>>>& error_pages) const {
  const std::string& name = ev.frames[f];
  const Pose3d T_map_W = poses.T_map_W(name);
  const bool with_near = options.near_enabled();
  NearRegion near;
  if (with_near) near = near_region(poses, name, options.near_radius_m);
  std::vector<cv::Mat> tiles;
  std::vector<MetricSums> row, near_row;
  std::vector<SeenSums> seen_row, near_seen_row;
  std::vector<LayerMaps> frame_layers;  // this frame's layers, for the fused map's reasons
  std::vector<DenseGrid> frame_reasons;
  for (size_t l = 0; l < ev.layers.size(); ++l) {
    const EvaluatedLayer& L = ev.layers[l];
    frame_layers.push_back(read_layer(frames_dir / name, L));
    const LayerMaps& layer = frame_layers.back();
    ErrorMaps maps;
    MetricSums near_sums;
    const MetricSums s = score_metrics(name, L, layer, T_map_W, maps_wanted ? &maps : nullptr,
                                       with_near ? &near : nullptr, &near_sums);
    ev.pooled[l] += s;
    row.push_back(s);
    if (with_near) {
      ev.near_pooled[l] += near_sums;
      near_row.push_back(near_sums);
    }
    if (seen) {
      DenseGrid reasons = unknown_reasons(frames_dir / name, ev.layers, l, frame_layers,
                                          frame_reasons);
      const int k = seen->index[f];
      SeenSums ss, ns;
      try {
        ss = score_seen(layer.hazard, &reasons, truth_for(L), seen->seen_for(L), k, T_map_W,
                        L.h_min_m);
        if (with_near) {
          ns = score_seen(layer.hazard, &reasons, truth_for(L), seen->seen_for(L), k, T_map_W,
                          L.h_min_m, &near);
          ev.near_gated_pooled[l] += score_seen(layer.hazard, &reasons, truth_for(L),
                                                seen->gated_for(L), k, T_map_W, L.h_min_m, &near);
          ev.near_ring_gated_pooled[l] += score_seen(layer.hazard, &reasons, truth_for(L),
                                                     seen->ring_gated_for(L), k, T_map_W,
                                                     L.h_min_m, &near);
        }
      } catch (const Error& e) {
        throw Error((frames_dir / name / (L.name + "_*.jdem")).string() + " (frame " + name +
                    "): " + e.what());
      }
      ev.seen_pooled[l] += ss;
      seen_row.push_back(ss);
      if (with_near) {
        ev.near_seen_pooled[l] += ns;
        near_seen_row.push_back(ns);
      }
      frame_reasons.push_back(std::move(reasons));
    }
    if (maps_wanted) add_error_tiles(L, maps, tiles);
  }
  ev.sums.push_back(std::move(row));
  if (with_near) ev.near_sums.push_back(std::move(near_row));
  if (seen) {
    ev.seen_sums.push_back(std::move(seen_row));
    if (with_near) ev.near_seen_sums.push_back(std::move(near_seen_row));
  }
  if (maps_wanted)
    error_pages.emplace_back(name, error_page_png(tiles, ev.out_dir / ("errors_" + name + ".png")));
}

}  // namespace

RunEvaluation evaluate_run(const EvaluationOptions& options) {
  RunEvaluation ev;
  ev.out_dir = options.out_dir.empty() ? options.run_dir / run_layout::kEvalDir : options.out_dir;
  const YAML::Node summary = load_summary(options.run_dir);
  const Config config = config_from_summary(summary, options.run_dir);
  // Before anything else of the sequence is read: scoring one sequence's frames against
  // another's ground truth gives numbers without meaning and no error.
  check_source(source_from_summary(summary, options.run_dir), options.run_dir,
               options.sequence_dir);
  const GroundTruth gt = read_ground_truth(options.sequence_dir);

  const fs::path frames_dir = options.run_dir / run_layout::kFramesDir;
  ev.frames = run_frames(frames_dir);
  const bool with_footprint = footprint_in_every_frame(frames_dir, ev.frames);
  ev.layers = evaluated_layers(config, with_footprint);
  ev.near_radius_m = options.near_enabled() ? options.near_radius_m : -1.0;
  if (options.near_enabled())
    check(std::isfinite(options.near_radius_m), "--near: the radius must be a finite number");

  const SequencePoses poses(options.sequence_dir);
  ev.used_true_poses = poses.drifted;
  std::optional<SeenCells> seen;
  if (fs::is_directory(options.sequence_dir / "depth")) {
    seen = read_seen_cells(options.sequence_dir, gt, config, poses, ev.frames, with_footprint);
    ev.seen_enabled = true;
    ev.seen_pooled.assign(ev.layers.size(), SeenSums{});
    if (options.near_enabled()) {
      ev.near_seen_pooled.assign(ev.layers.size(), SeenSums{});
      ev.near_gated_pooled.assign(ev.layers.size(), SeenSums{});
      ev.near_ring_gated_pooled.assign(ev.layers.size(), SeenSums{});
    }
  }
  const ErrorMapFrames error_frames = error_map_frames(options, ev.frames);

  // Every frame is read and scored before anything is written: a corrupt frame leaves OUT
  // as it was. The error-map pages wait in memory till then, PNG-encoded (tens of kB each).
  std::vector<std::pair<std::string, std::vector<unsigned char>>> error_pages;
  ev.pooled.assign(ev.layers.size(), MetricSums{});
  if (options.near_enabled()) ev.near_pooled.assign(ev.layers.size(), MetricSums{});
  const LayerTruths truths(gt, ev.layers);
  const FrameScorer scorer{options, frames_dir, truths, poses, seen ? &*seen : nullptr};
  const Progress progress(static_cast<int>(ev.frames.size()));
  for (size_t f = 0; f < ev.frames.size(); ++f) {
    scorer.score(ev, f, error_frames.wanted(ev.frames[f]), error_pages);
    spdlog::info("evaluated frame {} {}", ev.frames[f], progress.step(static_cast<int>(f) + 1));
  }
  fs::create_directories(ev.out_dir);
  std::vector<std::pair<std::string, fs::path>> error_pngs;
  for (const auto& [name, bytes] : error_pages) {
    const fs::path png = ev.out_dir / ("errors_" + name + ".png");
    write_file_atomically(png, bytes);
    error_pngs.emplace_back(name, png);
  }
  write_outputs(options, ev, error_pngs, config);
  return ev;
}

}  // namespace hazmap::eval
