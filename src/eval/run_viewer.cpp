#include "hazmap/eval/run_viewer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include <opencv2/imgproc.hpp>
#include <yaml-cpp/yaml.h>

#include "io/json_writer.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/core/number_text.hpp"
#include "hazmap/eval/embedded_grids.hpp"
#include "hazmap/eval/html_report.hpp"
#include "hazmap/eval/run_evaluation.hpp"
#include "hazmap/hazard/hazard_params.hpp"
#include "hazmap/io/atomic_file.hpp"
#include "hazmap/io/geotiff.hpp"
#include "hazmap/io/jdem.hpp"
#include "hazmap/io/run_layout.hpp"
#include "hazmap/io/sequence.hpp"
#include "hazmap/map/height_range.hpp"
#include "hazmap/rules/rule_registry.hpp"
#include "viewer/viewer_assets.hpp"

namespace hazmap::eval {

namespace fs = std::filesystem;

namespace {

/// One grid file of a map and how it is packed.
struct GridFile {
  std::string quantity;  ///< the page's name: hazard, height, variance, slope_x, ...
  std::string stem;      ///< file name without extension, e.g. L0_height
  bool classes = false;
  bool required = true;  ///< optional files join the page only when every frame has them
};

/// One map panel of the page: a layer, the fused or the footprint map.
struct MapSpec {
  std::string id;     ///< L<i>, fused, footprint
  std::string title;
  std::string kind;   ///< layer | fused | footprint
  std::string rule;
  double resolution_m = 0;
  double h_min_m = 0;
  std::vector<GridFile> files;
};

/// A map's grids in one frame, packed.
struct PackedMap {
  int rows = 0, cols = 0;
  double resolution_m = 0, center_x_m = 0, center_y_m = 0;
  std::vector<std::pair<std::string, PackedArray>> arrays;
  std::optional<std::pair<double, double>> height_range, sigma_range;
};

struct PackedFrame {
  std::string name;
  std::vector<PackedMap> maps;  ///< as MapSpec
  std::string base64;
};

struct Pose2 {
  double x_m = 0, y_m = 0, yaw_rad = 0;
};

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot read");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string fmt(double v, const char* format) { return printf_finite(v, format, "-"); }

std::string run_name(const fs::path& run_dir) {
  const fs::path n = run_dir.lexically_normal();
  return (n.filename().empty() ? n.parent_path().filename() : n.filename()).string();
}

YAML::Node load_yaml(const fs::path& path) {
  try {
    return YAML::LoadFile(path.string());
  } catch (const YAML::Exception& e) {
    throw Error(path.string() + ": " + e.what());
  }
}

/// The maps a run of `config` writes per frame, in page order.
std::vector<MapSpec> map_specs(const Config& config) {
  const HazardParams params = resolve_hazard_params(config);
  std::vector<MapSpec> maps;
  for (size_t i = 0; i < config.map.layers.size(); ++i) {
    const LayerConfig& l = config.map.layers[i];
    MapSpec m;
    m.id = run_layout::layer_id(i);
    m.kind = "layer";
    m.rule = rule_name(l.rule);
    m.resolution_m = l.resolution_m;
    m.h_min_m = params.layers[i].h_min_m;
    m.title = m.id + "  " + fmt(l.resolution_m * 100, "%g") + " cm  " + m.rule;
    m.files = {{"hazard", run_layout::layer_stem(i, "hazard"), true, true},
               {"height", run_layout::layer_stem(i, "height"), false, true},
               {"variance", run_layout::layer_stem(i, "variance"), false, true}};
    if (rule_info(l.rule).has_plane)  // the cell planes (SPEC 6): sub-cell heights on hover
      for (const char* q : {"slope_x", "slope_y"})
        m.files.push_back({q, run_layout::layer_stem(i, q), false, false});
    maps.push_back(m);
  }
  if (maps.empty()) return maps;
  const double finest = config.map.layers.front().resolution_m;
  MapSpec fused;
  fused.id = fused.kind = fused.rule = "fused";
  fused.resolution_m = finest;
  fused.h_min_m = params.critical_height_m;
  fused.title = "fused hazard  " + fmt(finest * 100, "%g") + " cm";
  fused.files = {{"hazard", run_layout::kFusedHazard, true, true},
                 {"clearance", run_layout::kFusedClearance, false, false}};
  maps.push_back(fused);
  MapSpec footprint;
  footprint.id = footprint.kind = footprint.rule = "footprint";
  footprint.resolution_m = finest;
  footprint.h_min_m = params.critical_height_m;
  footprint.title = "footprint  " + fmt(params.footprint_radius_m * 100, "%g") + " cm radius";
  footprint.files = {{"hazard", run_layout::kFootprintHazard, true, false}};
  maps.push_back(footprint);
  return maps;
}

/// A frame's grid in either format the run may have written (output.format), and the
/// file it came from.
struct FoundGrid {
  JdemGrid grid;
  fs::path file;
};

std::optional<FoundGrid> read_grid(const fs::path& dir, const std::string& stem) {
  const fs::path jdem = dir / (stem + ".jdem"), tif = dir / (stem + ".tif");
  FoundGrid g;
  if (fs::exists(jdem)) {
    g.grid = read_jdem(jdem);
    g.file = jdem;
  } else if (fs::exists(tif)) {
    g.grid = read_geotiff(tif);
    g.file = tif;
  } else {
    return std::nullopt;
  }
  if (g.grid.yaw_rad != 0.0)
    throw Error(g.file.string() + ": rotated grids (yaw != 0) are not supported");
  return g;
}

bool grid_exists(const fs::path& dir, const std::string& stem) {
  return fs::exists(dir / (stem + ".jdem")) || fs::exists(dir / (stem + ".tif"));
}

/// The colour range of a height (or sigma) grid, as the run's height PNGs colour theirs
/// (map_render.hpp, output.png_height_clip_pct cut from each end); nullopt when no cell
/// is known.
std::optional<std::pair<double, double>> colour_range(const JdemGrid& grid, double clip_pct) {
  DenseGrid g;
  g.rows = grid.rows;
  g.cols = grid.cols;
  g.values = grid.values;
  const HeightRange r = robust_height_range(g, clip_pct);
  if (!r.any) return std::nullopt;
  return std::make_pair(r.lo, r.hi);
}

/// The run-wide range: the widest of the frames' robust ranges (pooling every frame's
/// values would hold the whole run in memory).
void widen(std::optional<std::pair<double, double>>& run,
           const std::optional<std::pair<double, double>>& frame) {
  if (!frame) return;
  if (!run) run = frame;
  run->first = std::min(run->first, frame->first);
  run->second = std::max(run->second, frame->second);
}

PackedFrame pack_frame(const fs::path& frame_dir, const std::string& name,
                       const std::vector<MapSpec>& maps, double clip_pct) {
  PackedFrame frame;
  frame.name = name;
  GridPacker packer;
  for (const MapSpec& spec : maps) {
    PackedMap packed;
    fs::path first_file;
    for (const GridFile& f : spec.files) {
      const std::optional<FoundGrid> found = read_grid(frame_dir, f.stem);
      if (!found) {
        if (f.required) throw Error((frame_dir / (f.stem + ".jdem")).string() + ": missing");
        continue;
      }
      const JdemGrid* g = &found->grid;
      const fs::path& file = found->file;
      if (first_file.empty()) {
        first_file = file;
        packed.rows = g->rows;
        packed.cols = g->cols;
        packed.resolution_m = g->resolution_m;
        packed.center_x_m = g->center_x_m;
        packed.center_y_m = g->center_y_m;
      } else if (g->rows != packed.rows || g->cols != packed.cols ||
                 g->resolution_m != packed.resolution_m || g->center_x_m != packed.center_x_m ||
                 g->center_y_m != packed.center_y_m) {
        throw Error(file.string() + ": " + std::to_string(g->rows) + " x " +
                    std::to_string(g->cols) + " cells of " + fmt(g->resolution_m, "%g") +
                    " m centred at (" + fmt(g->center_x_m, "%g") + ", " +
                    fmt(g->center_y_m, "%g") + "), unlike " + first_file.filename().string() +
                    " of the same map");
      }
      try {
        packed.arrays.emplace_back(f.quantity, f.classes ? packer.add_classes(g->values)
                                                         : packer.add_float32(g->values));
      } catch (const Error& e) {
        throw Error(file.string() + ": " + e.what());
      }
      if (f.quantity == "height") packed.height_range = colour_range(*g, clip_pct);
      if (f.quantity == "variance") {
        JdemGrid sigma = *g;
        for (float& v : sigma.values) v = v >= 0 ? std::sqrt(v) : NAN;
        packed.sigma_range = colour_range(sigma, clip_pct);
      }
    }
    frame.maps.push_back(std::move(packed));
  }
  frame.base64 = packer.packed_base64();
  return frame;
}

/// The colour map's 256 entries as "rrggbb..." (OpenCV's, as the run's PNGs use).
std::string colour_map_hex(int map) {
  cv::Mat ramp(1, 256, CV_8UC1), colours;
  for (int i = 0; i < 256; ++i) ramp.at<uchar>(0, i) = static_cast<uchar>(i);
  cv::applyColorMap(ramp, colours, map);
  std::string hex;
  char buf[8];
  for (int i = 0; i < 256; ++i) {
    const cv::Vec3b bgr = colours.at<cv::Vec3b>(0, i);
    std::snprintf(buf, sizeof buf, "%02x%02x%02x", bgr[2], bgr[1], bgr[0]);
    hex += buf;
  }
  return hex;
}

void range_value(JsonWriter& j, const std::optional<std::pair<double, double>>& r) {
  if (!r) {
    j.value(std::nan(""));  // null
    return;
  }
  j.begin_array().value(r->first).value(r->second).end_array();
}

/// summary.json's per-frame numbers, a column per quantity.
struct FrameSeries {
  std::vector<std::string> names;
  std::vector<bool> written;
  std::vector<double> points, points_below_ground, disparities_unsupported;
  std::map<std::string, std::vector<double>> ms;  ///< stage -> per frame
  /// map id -> {hazard, traversable, unknown} -> per frame (NaN: not written)
  std::map<std::string, std::map<std::string, std::vector<double>>> areas;
  std::vector<std::optional<std::vector<double>>> T_W_B;  ///< x y z qx qy qz qw
};

const char* const kStages[] = {"read", "rectify", "disparity", "points", "map", "hazard", "write"};
const char* const kAreaKinds[] = {"hazard", "traversable", "unknown"};

FrameSeries read_frame_series(const YAML::Node& summary, const fs::path& file,
                              const std::vector<MapSpec>& maps) {
  FrameSeries s;
  for (const char* stage : kStages) s.ms[stage];  // every column present, if empty
  for (const MapSpec& m : maps)
    for (const char* kind : kAreaKinds) s.areas[m.id][kind];
  const YAML::Node frames = summary["frames"];
  if (!frames) return s;  // nothing per frame to plot: the maps are still worth a look
  if (!frames.IsSequence()) throw Error(file.string() + ": \"frames\" is not a list");
  const auto number = [&](const YAML::Node& n, const char* key) {
    return n[key] ? n[key].as<double>() : NAN;
  };
  try {
    for (const YAML::Node& f : frames) {
      const size_t k = s.names.size();
      s.names.push_back(f["name"].as<std::string>());
      s.written.push_back(f["written"] && f["written"].as<bool>());
      s.points.push_back(number(f, "points"));
      s.points_below_ground.push_back(number(f, "points_below_ground"));
      s.disparities_unsupported.push_back(number(f, "disparities_unsupported"));
      for (const char* stage : kStages) s.ms[stage].push_back(f["ms"] ? number(f["ms"], stage) : NAN);
      for (const MapSpec& m : maps)
        for (const char* kind : kAreaKinds) s.areas[m.id][kind].push_back(NAN);
      if (const YAML::Node areas = f["areas_m2"])
        for (const YAML::Node& a : areas) {
          const std::string id = a["layer"].as<std::string>();
          if (!s.areas.count(id)) continue;
          for (const char* kind : kAreaKinds) s.areas[id][kind][k] = number(a, kind);
        }
      if (const YAML::Node pose = f["T_W_B"]) {
        std::vector<double> p = pose.as<std::vector<double>>();
        if (p.size() != 7)
          throw Error(file.string() + ": frame " + s.names.back() + ": \"T_W_B\" holds " +
                      std::to_string(p.size()) + " numbers, not 7 (x y z qx qy qz qw)");
        s.T_W_B.push_back(std::move(p));
      } else {
        s.T_W_B.push_back(std::nullopt);
      }
    }
  } catch (const YAML::Exception& e) {
    throw Error(file.string() + ": \"frames\": " + e.what());
  }
  return s;
}

double yaw_of(const Eigen::Quaterniond& q) {
  const Eigen::Matrix3d R = q.normalized().toRotationMatrix();
  return std::atan2(R(1, 0), R(0, 0));  // heading of the body's x axis in W
}

/// The processed frames' poses: summary.json's, else the recorded sequence's poses.txt
/// (runs made before summary.json had them); empty when neither is there.
std::vector<Pose2> frame_poses(const FrameSeries& s, const YAML::Node& summary,
                               std::string* source) {
  std::vector<Pose2> poses;
  if (!s.names.empty() &&
      std::all_of(s.T_W_B.begin(), s.T_W_B.end(), [](const auto& p) { return p.has_value(); })) {
    for (const auto& p : s.T_W_B) {
      const std::vector<double>& v = *p;
      poses.push_back({v[0], v[1], yaw_of(Eigen::Quaterniond(v[6], v[3], v[4], v[5]))});
    }
    *source = "summary.json";
    return poses;
  }
  const std::string sequence = summary["sequence"] ? summary["sequence"].as<std::string>() : "";
  const fs::path file = fs::path(sequence) / "poses.txt";
  if (sequence.empty() || !fs::exists(file)) return {};
  std::map<std::string, Pose3d> by_name;
  for (const auto& [name, pose] : parse_poses(read_file(file), file.string()))
    by_name[name] = pose.T_W_B;
  for (const std::string& name : s.names) {
    const auto p = by_name.find(name);
    if (p == by_name.end()) return {};  // another sequence now: no path rather than a wrong one
    poses.push_back({p->second.translation().x(), p->second.translation().y(),
                     yaw_of(Eigen::Quaterniond(p->second.linear()))});
  }
  *source = file.string();
  return poses;
}

/// RUN/eval, when `hazmap evaluate` wrote it there.
struct EvalData {
  bool present = false;
  HtmlTable table;
  std::vector<std::string> layers;  ///< as metrics.csv names them
  std::vector<std::string> frames;
  /// metric -> layer -> per frame
  std::map<std::string, std::map<std::string, std::vector<double>>> per_frame;
  std::vector<std::pair<std::string, std::string>> error_maps;  ///< frame, data URI
};

const char* const kEvalSeries[] = {"height_rms_m", "hazard_recall", "missed_m2",
                                   "false_alarm_fraction", "unknown_fraction"};

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

EvalData read_evaluation(const fs::path& eval_dir) {
  EvalData e;
  const fs::path metrics = eval_dir / "metrics.json";
  if (!fs::exists(metrics)) return e;
  e.present = true;
  const YAML::Node root = load_yaml(metrics);
  e.table.id = "metrics";
  e.table.caption = "Pooled over the evaluated frames (eval/metrics.json)";
  e.table.header = {"layer",          "cell [cm]",          "rule",
                    "h_min [cm]",     "height RMS [cm]",    "unknown [%]",
                    "missed [m2]",    "missed [% of obstacles]", "false alarm [m2]",
                    "false alarm [% of known]", "recall [%]", "obstacles unknown [%]",
                    "variance violations [%]"};
  try {
    const YAML::Node layers = root["layers"];
    if (!layers || !layers.IsSequence()) throw Error(metrics.string() + ": no \"layers\" list");
    for (const YAML::Node& l : layers) {
      const auto num = [&](const char* key) {
        return l[key] && !l[key].IsNull() ? l[key].as<double>() : NAN;
      };
      e.table.rows.push_back({l["layer"].as<std::string>(), fmt(num("resolution_m") * 100, "%g"),
                              l["rule"].as<std::string>(), fmt(num("h_min_m") * 100, "%.1f"),
                              fmt(num("height_rms_m") * 100, "%.3f"),
                              fmt(num("unknown_fraction") * 100, "%.2f"),
                              fmt(num("missed_m2"), "%.4f"),
                              fmt(num("missed_of_hazard") * 100, "%.2f"),
                              fmt(num("false_alarm_m2"), "%.4f"),
                              fmt(num("false_alarm_fraction") * 100, "%.2f"),
                              fmt(num("hazard_recall") * 100, "%.2f"),
                              fmt(num("hazard_unknown") * 100, "%.2f"),
                              fmt(num("variance_violation") * 100, "%.2f")});
    }
  } catch (const YAML::Exception& ex) {
    throw Error(metrics.string() + ": " + ex.what());
  }

  // metrics.csv: the per-frame values, by column name (evaluate may add --near columns).
  const fs::path csv = eval_dir / "metrics.csv";
  if (fs::exists(csv)) {
    std::istringstream in(read_file(csv));
    std::string line;
    std::getline(in, line);
    const std::vector<std::string> header = split_csv_line(line);
    const auto column = [&](const std::string& name) -> size_t {
      const auto it = std::find(header.begin(), header.end(), name);
      if (it == header.end()) throw Error(csv.string() + ":1: no column \"" + name + "\"");
      return static_cast<size_t>(it - header.begin());
    };
    const size_t frame_col = column("frame"), layer_col = column("layer");
    std::map<std::string, size_t> cols;
    for (const char* m : kEvalSeries) cols[m] = column(m);
    std::map<std::string, size_t> frame_index;
    for (int line_no = 2; std::getline(in, line); ++line_no) {
      if (line.empty()) continue;
      const std::vector<std::string> cells = split_csv_line(line);
      if (cells.size() != header.size())
        throw Error(csv.string() + ":" + std::to_string(line_no) + ": " +
                    std::to_string(cells.size()) + " cells, the header has " +
                    std::to_string(header.size()));
      const std::string& frame = cells[frame_col];
      const std::string& layer = cells[layer_col];
      if (!frame_index.count(frame)) {
        frame_index[frame] = e.frames.size();
        e.frames.push_back(frame);
      }
      if (std::find(e.layers.begin(), e.layers.end(), layer) == e.layers.end())
        e.layers.push_back(layer);
      const size_t f = frame_index[frame];
      for (const auto& [metric, c] : cols) {
        std::vector<double>& v = e.per_frame[metric][layer];
        v.resize(e.frames.size(), NAN);
        char* end = nullptr;
        const double x = std::strtod(cells[c].c_str(), &end);
        v[f] = end != cells[c].c_str() ? x : NAN;  // "nan" reads as NaN too
      }
    }
    for (auto& [metric, by_layer] : e.per_frame)
      for (auto& [layer, v] : by_layer) v.resize(e.frames.size(), NAN);
  }

  // errors_<frame>.png, as data URIs (the page stays one file).
  std::vector<fs::path> pngs;
  for (const auto& entry : fs::directory_iterator(eval_dir)) {
    const std::string n = entry.path().filename().string();
    if (n.rfind("errors_", 0) == 0 && entry.path().extension() == ".png") pngs.push_back(entry.path());
  }
  std::sort(pngs.begin(), pngs.end());
  for (const fs::path& png : pngs) {
    const std::string bytes = read_file(png);
    static const std::string kSignature = "\x89PNG\r\n\x1a\n";
    if (bytes.compare(0, kSignature.size(), kSignature) != 0)
      throw Error(png.string() + ": not a PNG file");
    const std::string stem = png.stem().string();
    e.error_maps.emplace_back(stem.substr(std::string("errors_").size()),
                              "data:image/png;base64," +
                                  base64_encode(std::vector<unsigned char>(bytes.begin(), bytes.end())));
  }
  return e;
}

/// run.log's last warning and error lines (the log is appended to by every run).
std::vector<std::string> log_problems(const fs::path& log) {
  std::vector<std::string> lines;
  if (!fs::exists(log)) return lines;
  std::istringstream in(read_file(log));
  for (std::string line; std::getline(in, line);)
    if (line.find("] [warning] ") != std::string::npos || line.find("] [error] ") != std::string::npos ||
        line.find("] [critical] ") != std::string::npos)
      lines.push_back(line);
  if (lines.size() > kMaxLogLines)
    lines.erase(lines.begin(), lines.end() - static_cast<std::ptrdiff_t>(kMaxLogLines));
  return lines;
}

void string_array(JsonWriter& j, const std::vector<std::string>& v) {
  j.begin_array();
  for (const std::string& s : v) j.value(s);
  j.end_array();
}

void number_array(JsonWriter& j, const std::vector<double>& v) {
  j.begin_array();
  for (double x : v) j.value(x);  // NaN -> null
  j.end_array();
}

/// Everything the page shows, read from the run folder and checked.
struct RunContent {
  std::string title;
  std::string subtitle;
  std::string settings_yaml;
  std::vector<MapSpec> maps;
  std::vector<PackedFrame> frames;
  double clip_pct = 0;  ///< output.png_height_clip_pct: the colour ranges' percentiles
  /// Per map: the widest of the frames' robust ranges (see widen()).
  std::vector<std::optional<std::pair<double, double>>> run_height, run_sigma;
  FrameSeries series;
  std::vector<Pose2> poses;
  std::string pose_source;
  EvalData eval;
  std::vector<std::string> log_problems;
  size_t grid_bytes = 0;  ///< values before packing
};

/// RUN/frames/<name>/, hidden staging folders left out, sorted.
std::vector<std::string> frame_folders(const fs::path& frames_dir) {
  if (!fs::is_directory(frames_dir))
    throw Error(frames_dir.string() + ": missing (the run wrote no frame)");
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(frames_dir)) {
    const std::string n = entry.path().filename().string();
    if (entry.is_directory() && !n.empty() && n[0] != '.') names.push_back(n);
  }
  std::sort(names.begin(), names.end());
  if (names.empty()) throw Error(frames_dir.string() + ": no frame folders");
  return names;
}

/// The maps with the files every frame has: optional grids (the footprint map, the CCM
/// slopes and the clearance are newer than the others) join only then.
std::vector<MapSpec> maps_present(const std::vector<MapSpec>& all, const fs::path& frames_dir,
                                  const std::vector<std::string>& names) {
  std::vector<MapSpec> maps;
  for (MapSpec m : all) {
    std::vector<GridFile> files;
    for (const GridFile& f : m.files)
      if (f.required || std::all_of(names.begin(), names.end(), [&](const std::string& n) {
            return grid_exists(frames_dir / n, f.stem);
          }))
        files.push_back(f);
    const bool has_hazard = std::any_of(files.begin(), files.end(),
                                        [](const GridFile& f) { return f.quantity == "hazard"; });
    if (!has_hazard) continue;  // the footprint map of an older run
    m.files = files;
    maps.push_back(m);
  }
  return maps;
}

RunContent read_run(const fs::path& run_dir) {
  const fs::path summary_file = run_dir / run_layout::kSummaryJson;
  const Config config = read_run_config(run_dir);  // names summary.json when missing or bad
  if (!config.output.jdem)
    throw Error(summary_file.string() +
                ": the run wrote no grids (output.jdem: false); hazmap view needs them");
  const YAML::Node summary = load_yaml(summary_file);
  const std::vector<MapSpec> all_maps = map_specs(config);
  if (all_maps.empty()) throw Error(summary_file.string() + ": settings_yaml has no map layers");

  RunContent c;
  c.series = read_frame_series(summary, summary_file, all_maps);
  const fs::path frames_dir = run_dir / run_layout::kFramesDir;
  const std::vector<std::string> names = frame_folders(frames_dir);
  c.maps = maps_present(all_maps, frames_dir, names);
  c.clip_pct = config.output.png_height_clip_pct;
  for (const std::string& name : names)
    c.frames.push_back(pack_frame(frames_dir / name, name, c.maps, c.clip_pct));
  c.run_height.resize(c.maps.size());
  c.run_sigma.resize(c.maps.size());
  for (const PackedFrame& f : c.frames)
    for (size_t m = 0; m < c.maps.size(); ++m) {
      widen(c.run_height[m], f.maps[m].height_range);
      widen(c.run_sigma[m], f.maps[m].sigma_range);
      for (const auto& [q, a] : f.maps[m].arrays)
        c.grid_bytes += a.count * (a.type == PackedType::float32 ? 4 : 1);
    }
  c.poses = frame_poses(c.series, summary, &c.pose_source);
  c.eval = read_evaluation(run_dir / run_layout::kEvalDir);
  c.log_problems = log_problems(run_dir / run_layout::kRunLog);

  const auto str = [&](const char* key) {
    return summary[key] && summary[key].IsScalar() ? summary[key].as<std::string>() : std::string();
  };
  const std::string stopped = str("stopped_after_frame");
  const std::string finished = str("finished") == "true" ? "finished"
                               : !stopped.empty()        ? "stopped after frame " + stopped
                                                         : "not finished";
  c.title = "hazmap view: " + run_name(run_dir);
  c.subtitle = "run " + fs::absolute(run_dir).lexically_normal().string() + " | sequence " +
               str("sequence") + " | config " + str("config") + " | " +
               std::to_string(c.frames.size()) + " written of " +
               std::to_string(c.series.names.size()) + " processed frames, " + finished +
               " | hazmap " + str("hazmap_version");
  c.settings_yaml = str("settings_yaml");
  return c;
}

/// "maps": what each map is and its height and sigma ranges over the whole run.
void write_map_specs(JsonWriter& j, const RunContent& c) {
  j.key("maps").begin_array();
  for (size_t m = 0; m < c.maps.size(); ++m) {
    const MapSpec& s = c.maps[m];
    j.begin_object();
    j.key("id").value(s.id);
    j.key("title").value(s.title);
    j.key("kind").value(s.kind);
    j.key("rule").value(s.rule);
    j.key("resolution_m").value(s.resolution_m);
    j.key("h_min_m").value(s.h_min_m);
    j.key("quantities").begin_array();
    for (const GridFile& f : s.files) j.value(f.quantity);
    j.end_array();
    j.key("range_run").begin_object();
    j.key("height");
    range_value(j, c.run_height[m]);
    j.key("sigma");
    range_value(j, c.run_sigma[m]);
    j.end_object();
    j.end_object();
  }
  j.end_array();
}

/// One frame's map: its geometry, where its arrays lie in the frame's bytes, its ranges.
void write_packed_map(JsonWriter& j, const PackedMap& p) {
  j.begin_object();
  j.key("rows").value(p.rows);
  j.key("cols").value(p.cols);
  j.key("resolution_m").value(p.resolution_m);
  j.key("center_m").begin_array().value(p.center_x_m).value(p.center_y_m).end_array();
  j.key("arrays").begin_object();  // quantity: [type, byte offset, count]
  for (const auto& [quantity, a] : p.arrays) {
    j.key(quantity).begin_array();
    j.value(a.type == PackedType::float32 ? "f32" : "class");
    j.value(a.offset).value(a.count);
    j.end_array();
  }
  j.end_object();
  j.key("range").begin_object();
  j.key("height");
  range_value(j, p.height_range);
  j.key("sigma");
  range_value(j, p.sigma_range);
  j.end_object();
  j.end_object();
}

/// "frames": one element per written frame.
void write_packed_frames(JsonWriter& j, const RunContent& c) {
  j.key("frames").begin_array();
  for (const PackedFrame& f : c.frames) {
    j.begin_object();
    j.key("name").value(f.name);
    j.key("maps").begin_array();
    for (const PackedMap& p : f.maps) write_packed_map(j, p);
    j.end_array();
    j.end_object();
  }
  j.end_array();
}

/// "processed": summary.json's per-frame series, every frame processed.
void write_processed_series(JsonWriter& j, const RunContent& c) {
  const FrameSeries& s = c.series;
  j.key("processed").begin_object();
  j.key("names");
  string_array(j, s.names);
  j.key("points");
  number_array(j, s.points);
  j.key("points_below_ground");
  number_array(j, s.points_below_ground);
  j.key("disparities_unsupported");
  number_array(j, s.disparities_unsupported);
  j.key("ms").begin_object();
  for (const char* stage : kStages) {
    j.key(stage);
    number_array(j, s.ms.at(stage));
  }
  j.end_object();
  j.key("areas_m2").begin_object();
  for (const MapSpec& m : c.maps) {
    j.key(m.id).begin_object();
    for (const char* kind : kAreaKinds) {
      j.key(kind);
      number_array(j, s.areas.at(m.id).at(kind));
    }
    j.end_object();
  }
  j.end_object();
  j.end_object();
}

/// "poses": the rover's path.
void write_poses(JsonWriter& j, const RunContent& c) {
  j.key("poses").begin_object();
  j.key("source").value(c.pose_source);
  std::vector<double> x, y, yaw;
  for (const Pose2& p : c.poses) x.push_back(p.x_m), y.push_back(p.y_m), yaw.push_back(p.yaw_rad);
  j.key("x_m");
  number_array(j, x);
  j.key("y_m");
  number_array(j, y);
  j.key("yaw_rad");
  number_array(j, yaw);
  j.end_object();
}

/// "eval": the evaluation's per-frame metrics, when the run has been evaluated.
void write_eval_metrics(JsonWriter& j, const RunContent& c) {
  j.key("eval").begin_object();
  j.key("frames");
  string_array(j, c.eval.frames);
  j.key("layers");
  string_array(j, c.eval.layers);
  j.key("per_frame").begin_object();  // metric: {layer: per frame}
  for (const auto& [metric, by_layer] : c.eval.per_frame) {
    j.key(metric).begin_object();
    for (const auto& [layer, v] : by_layer) {
      j.key(layer);
      number_array(j, v);
    }
    j.end_object();
  }
  j.end_object();
  j.end_object();
}

/// The page's data as JSON (run_viewer.js reads it): everything but the grids, which
/// follow as one element per frame.
std::string data_json(const RunContent& c) {
  JsonWriter j;
  j.begin_object();
  j.key("title").value(c.title);
  j.key("clip_pct").value(c.clip_pct);
  write_map_specs(j, c);
  write_packed_frames(j, c);
  write_processed_series(j, c);
  write_poses(j, c);
  if (c.eval.present) write_eval_metrics(j, c);
  j.key("colour_maps").begin_object();
  j.key("height").value(colour_map_hex(cv::COLORMAP_VIRIDIS));
  j.key("sigma").value(colour_map_hex(cv::COLORMAP_INFERNO));
  j.end_object();
  j.end_object();
  return j.str();
}

/// The controls the script wires (ids and data- attributes are its interface).
void write_controls(std::ostream& o, const RunContent& c) {
  o << "<div id=\"controls\">\n"
    << "<button id=\"play\" title=\"play / pause (space)\">&#9654; play</button>\n"
    << "<button id=\"prev\" title=\"previous frame (left arrow)\">&larr;</button>"
    << "<input id=\"frame-slider\" type=\"range\" min=\"0\" max=\"" << c.frames.size() - 1
    << "\" value=\"" << c.frames.size() - 1 << "\" aria-label=\"frame\">"
    << "<button id=\"next\" title=\"next frame (right arrow)\">&rarr;</button>\n"
    << "<span id=\"frame-label\">frame " << html_escape(c.frames.back().name) << "</span>\n"
    << "<label>speed <select id=\"fps\"><option>1</option><option selected>2</option>"
    << "<option>5</option><option>10</option></select> frames/s</label>\n"
    << "<span class=\"group\">all layers: <button data-all=\"hazard\">hazard</button>"
    << "<button data-all=\"height\">height</button><button data-all=\"sigma\">&sigma;</button>"
    << "</span>\n<label>colours over <select id=\"range-mode\"><option value=\"run\">the whole run"
    << "</option><option value=\"frame\">this frame</option></select></label>\n"
    << "<label><input type=\"checkbox\" id=\"link\" checked> link views</label>\n"
    << "<button id=\"fit\" title=\"fit every map to its known cells (double-click a map)\">fit maps</button>\n"
    << "<span id=\"status\">loading&hellip;</span>\n</div>\n";
}

/// One section per map, the readout beside them.
void write_maps(std::ostream& o, const RunContent& c) {
  o << "<div id=\"main\">\n<div id=\"maps\">\n";
  for (const MapSpec& s : c.maps) {
    o << "<section class=\"map\" id=\"map-" << s.id << "\" data-map=\"" << s.id << "\">\n<h3>"
      << html_escape(s.title) << "</h3>";
    if (s.kind == "layer")
      o << "<span class=\"qsel\"><button data-q=\"hazard\">hazard</button><button data-q=\"height\">"
           "height</button><button data-q=\"sigma\">&sigma;</button></span>";
    o << "\n<canvas class=\"view\" width=\"360\" height=\"360\" aria-label=\"" << html_escape(s.title)
      << "\"></canvas>\n<div class=\"legend\"></div>\n<div class=\"stats\"></div>\n</section>\n";
  }
  o << "</div>\n<aside id=\"side\">\n<h3>Under the pointer</h3>\n<div id=\"readout\">"
    << "Point at a map: position in W and every map's cell there.</div>\n"
    << "<p class=\"hint\">Maps open fitted to their known cells. Wheel: zoom. Drag: pan. "
       "Double-click: fit. &larr; &rarr;: frames. "
       "Space: play. The path is the rover's body origin over every processed frame; the "
       "ring is where it is, its tick its heading (x axis). Open view.html#frame=N for a "
       "frame.</p>\n"
    << "</aside>\n</div>\n";
  if (c.poses.empty())
    o << "<p class=\"note\">No poses: summary.json predates the T_W_B record and the "
         "sequence's poses.txt was not found; maps are shown without the path.</p>\n";
}

void write_evaluation(std::ostream& o, const EvalData& eval) {
  o << "<h2 id=\"evaluation\">Evaluation</h2>\n"
    << "<p>From eval/ (hazmap evaluate): missed = obstacle at least h_min high called "
       "traversable; false alarm = obstacle-free ground called a hazard; recall = share "
       "of the obstacle pixels labelled hazard.</p>\n"
    << render_table(eval.table) << "<div id=\"eval-plots\" class=\"plots\"></div>\n"
    << "<h3>Error maps</h3>\n<div id=\"error-maps\">\n";
  if (eval.error_maps.empty())
    o << "<p>None in eval/ (hazmap evaluate --error-maps FRAMES writes them).</p>\n";
  for (const auto& [frame, uri] : eval.error_maps)
    o << "<figure class=\"error-map\" data-frame=\"" << html_escape(frame) << "\"><img alt=\"errors "
      << html_escape(frame) << "\" src=\"" << uri << "\"><figcaption>frame " << html_escape(frame)
      << ": per layer |h - h_gt| and the outcome at each ground-truth pixel</figcaption></figure>\n";
  o << "</div>\n";
}

std::string page_html(const RunContent& c) {
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
    << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
    << "<title>" << html_escape(c.title) << "</title>\n<style>" << report_style()
    << viewer_assets::kStyle << "</style>\n</head>\n<body>\n<h1>" << html_escape(c.title)
    << "</h1>\n<p class=\"subtitle\">" << html_escape(c.subtitle) << "</p>\n";
  write_controls(o, c);
  write_maps(o, c);
  o << "<h2>Per frame</h2>\n<p>From summary.json, over every processed frame; a click picks "
       "the nearest written frame. Areas are over each map's window.</p>\n"
    << "<div id=\"plots\" class=\"plots\"></div>\n";
  if (c.eval.present) write_evaluation(o, c.eval);
  o << "<h2>Run log</h2>\n";
  if (c.log_problems.empty()) {
    o << "<p>No warning or error in run.log.</p>\n";
  } else {
    o << "<details id=\"log\"><summary>" << c.log_problems.size()
      << " warning and error lines of run.log"
      << (c.log_problems.size() == kMaxLogLines ? " (the last ones)" : "") << "</summary>\n<pre>";
    for (const std::string& l : c.log_problems) o << html_escape(l) << '\n';
    o << "</pre></details>\n";
  }
  o << "<h2>Configuration</h2>\n<details><summary>settings_yaml of summary.json</summary>\n<pre>"
    << html_escape(c.settings_yaml) << "</pre></details>\n";
  o << "<script type=\"application/json\" id=\"run-data\">" << script_safe(data_json(c))
    << "</script>\n";
  for (size_t f = 0; f < c.frames.size(); ++f)
    o << "<script type=\"application/octet-stream\" id=\"grids-" << f << "\">"
      << c.frames[f].base64 << "</script>\n";
  o << "<script>" << viewer_assets::kScript << "</script>\n</body>\n</html>\n";
  return o.str();
}

}  // namespace

std::string render_run_viewer(const fs::path& run_dir, ViewerReport* report) {
  const RunContent content = read_run(run_dir);
  std::string page = page_html(content);
  if (report) {
    report->page_bytes = page.size();
    report->frames = content.frames.size();
    report->frames_processed = content.series.names.size();
    report->maps = content.maps.size();
    report->grid_bytes = content.grid_bytes;
    report->grid_text_bytes = 0;
    for (const PackedFrame& f : content.frames) report->grid_text_bytes += f.base64.size();
    report->with_poses = !content.poses.empty();
    report->with_evaluation = content.eval.present;
  }
  return page;
}

ViewerReport write_run_viewer(const ViewerOptions& options) {
  ViewerReport report;
  const std::string page = render_run_viewer(options.run_dir, &report);
  report.out_file =
      options.out_file.empty() ? options.run_dir / run_layout::kViewHtml : options.out_file;
  write_file_atomically(report.out_file, page);
  return report;
}

}  // namespace hazmap::eval
