#include "hazmap/io/config.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "hazmap/core/error.hpp"
#include "hazmap/map/grid_math.hpp"
#include "hazmap/rules/rule_registry.hpp"
#include "yaml_access.hpp"

namespace hazmap {

namespace {

void one_of(const YamlMap& m, const std::string& key, const std::string& value,
            const std::vector<const char*>& allowed) {
  std::string list;
  for (const char* a : allowed) {
    if (value == a) return;
    list += (list.empty() ? "" : " | ") + std::string(a);
  }
  m.fail(key, "'" + value + "' is not one of " + list);
}

void parse_stereo(YamlMap m, StereoConfig& s) {
  m.get("matcher", s.matcher);
  one_of(m, "matcher", s.matcher, {"bm", "sgbm"});
  m.get("num_disparities", s.num_disparities);
  m.get("block_size", s.block_size);
  m.get("min_disparity", s.min_disparity);
  m.get("uniqueness_ratio", s.uniqueness_ratio);
  m.get("texture_threshold", s.texture_threshold);
  m.get("pre_filter_cap", s.pre_filter_cap);
  m.get("speckle_window", s.speckle_window);
  m.get("speckle_range", s.speckle_range);
  m.get("disp12_max_diff", s.disp12_max_diff);
  m.get("sgbm_p1", s.sgbm_p1);
  m.get("sgbm_p2", s.sgbm_p2);
  m.get("sgbm_mode", s.sgbm_mode);
  one_of(m, "sgbm_mode", s.sgbm_mode, {"sgbm", "hh", "sgbm_3way", "hh4"});
  m.get("pre_filter_type", s.pre_filter_type);
  one_of(m, "pre_filter_type", s.pre_filter_type, {"normalized_response", "xsobel"});
  m.get("pre_filter_size", s.pre_filter_size);
  m.get("input_bits", s.input_bits);
  m.get("rectify_alpha", s.rectify_alpha);
  m.get("stride", s.stride);
  if (m.has("roi")) {
    std::vector<double> roi;
    m.get("roi", roi, 4);
    for (size_t i = 0; i < 4; ++i) {
      if (roi[i] != std::floor(roi[i]) || std::abs(roi[i]) > 1e6)
        m.fail("roi", "expected 4 integers [x, y, width, height]");
      s.roi_px[i] = static_cast<int>(roi[i]);
    }
  }
  m.get("z_min", s.z_min_m);
  m.get("z_max", s.z_max_m);
  m.get("max_below_ground", s.max_below_ground_m);
  m.get("below_ground_tolerance", s.below_ground_tolerance_m);
  m.get("max_depression_slope_deg", s.max_depression_slope_deg);
  m.get("occlusion_reach", s.occlusion_reach);
  m.get("occlusion_margin", s.occlusion_margin_m);
  m.get("occlusion_fill", s.occlusion_fill_m);
  m.get("support_rows", s.support_rows);
  m.get("support_tolerance", s.support_tolerance);
  m.get("support_margin_px", s.support_margin_px);
  m.get("search", s.search);
  one_of(m, "search", s.search, {"full", "ground_band"});
  m.get("band_max_slope_deg", s.band_max_slope_deg);
  m.get("band_max_height", s.band_max_height_m);
  m.get("band_max_depth", s.band_max_depth_m);
  m.finish();
}

void parse_sensor(YamlMap m, SensorConfig& s) {
  m.get("model", s.model);
  one_of(m, "model", s.model, {"axis", "ray"});
  m.get("pointing_error_px", s.pointing_error_px);
  m.get("disparity_error_px", s.disparity_error_px);
  m.finish();
}

void parse_map(YamlMap m, MapConfig& map) {
  m.get("insertion", map.insertion);
  one_of(m, "insertion", map.insertion, {"all_layers", "finest_then_pool"});
  if (m.has("layers")) {
    const YAML::Node layers = m.sequence("layers");
    map.layers.clear();
    for (size_t i = 0; i < layers.size(); ++i) {
      YamlMap l(layers[i], m.key_path("layers") + "." + std::to_string(i), m.source());
      LayerConfig layer;
      l.require("resolution", layer.resolution_m);
      l.require("size", layer.size);
      std::string rule = "kalman";
      l.require("rule", rule);
      one_of(l, "rule", rule, rule_names());
      layer.rule = *rule_kind(rule);
      l.get("max_std_ratio", layer.max_std_ratio);
      YamlMap h = l.child("hazard");
      h.get("kernel", layer.hazard.kernel);
      h.get("roughness_threshold", layer.hazard.roughness_threshold_m);
      h.get("h_min", layer.hazard.h_min_m);
      h.get("rho_max", layer.hazard.rho_max_m2);
      h.finish();
      l.finish();
      map.layers.push_back(layer);
    }
  }
  m.finish();
}

void parse_rules(YamlMap m, RulesConfig& r) {
  {
    YamlMap k = m.child("kalman");
    k.get("time_inflation", r.kalman.time_inflation_m2);
    k.get("min_variance", r.kalman.min_variance_m2);
    k.get("gate_sigma", r.kalman.gate_sigma);
    k.finish();
  }
  {
    YamlMap o = m.child("omg");
    o.get("max_weight", r.omg.max_weight);
    o.get("decay", r.omg.decay);
    o.get("gate_sigma", r.omg.gate_sigma);
    o.finish();
  }
  {
    YamlMap c = m.child("ccm");
    c.get("weighting", r.ccm.weighting);
    one_of(c, "weighting", r.ccm.weighting, {"constant", "trace", "det"});
    c.get("full_plane", r.ccm.full_plane);
    c.get("max_weight", r.ccm.max_weight);
    c.get("min_points", r.ccm.min_points);
    c.get("min_coverage", r.ccm.min_coverage);
    c.get("max_std_ratio", r.ccm.max_std_ratio);
    c.finish();
  }
  m.finish();
}

void parse_hazard(YamlMap m, HazardConfig& h) {
  m.get("max_slope_deg", h.max_slope_deg);
  m.get("wheelbase", h.wheelbase_m);
  m.get("min_kernel_fill", h.min_kernel_fill);
  m.get("roughness", h.roughness);
  one_of(m, "roughness", h.roughness, {"range", "detrended"});
  m.get("min_axis_coverage", h.min_axis_coverage);
  m.get("k_sigma", h.k_sigma);
  m.get("critical_height", h.critical_height_m);
  m.get("footprint_radius", h.footprint_radius_m);
  m.get("fused_extent", h.fused_extent_m);
  m.get("incremental", h.incremental);
  m.finish();
}

void parse_output(YamlMap m, OutputConfig& o) {
  m.get("every_n", o.every_n);
  m.get("png", o.png);
  m.get("jdem", o.jdem);
  m.get("format", o.format);
  one_of(m, "format", o.format, {"jdem", "geotiff", "both"});
  m.get("queue_frames", o.queue_frames);
  m.get("png_min_size", o.png_min_size);
  m.get("png_height_clip_pct", o.png_height_clip_pct);
  m.get("mosaic", o.mosaic);
  m.finish();
}

[[noreturn]] void invalid(const std::string& key, const std::string& what) {
  throw Error("config: key '" + key + "': " + what);
}

}  // namespace

Config parse_config(const std::string& yaml_text, const std::string& source,
                    const std::vector<std::string>& overrides) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw Error(source + ":" + std::to_string(e.mark.line + 1) + ": invalid YAML: " + e.msg);
  }
  reject_duplicate_keys(root, source);
  for (const auto& assignment : overrides) apply_yaml_override(root, assignment);

  Config config;
  YamlMap top(root, "", source);
  parse_stereo(top.child("stereo"), config.stereo);
  parse_sensor(top.child("sensor"), config.sensor);
  parse_map(top.child("map"), config.map);
  parse_rules(top.child("rules"), config.rules);
  parse_hazard(top.child("hazard"), config.hazard);
  {
    YamlMap p = top.child("pose_uncertainty");
    p.get("enabled", config.pose_uncertainty.enabled);
    p.finish();
  }
  parse_output(top.child("output"), config.output);
  top.finish();
  validate(config);
  return config;
}

Config load_config(const std::filesystem::path& path, const std::vector<std::string>& overrides) {
  // A folder opens as an empty stream on Linux and would read as an empty config.
  if (std::filesystem::is_directory(path))
    throw Error(path.string() + ": is a folder, not a configuration file");
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot open configuration file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_config(text.str(), path.string(), overrides);
}

void validate(const Config& c) {
  const StereoConfig& s = c.stereo;
  if (s.num_disparities <= 0 || s.num_disparities % 16 != 0)
    invalid("stereo.num_disparities", "must be a positive multiple of 16");
  if (s.block_size < 5 || s.block_size % 2 == 0 || s.block_size > 255)
    invalid("stereo.block_size", "must be odd and in [5, 255]");
  if (s.min_disparity < 0) invalid("stereo.min_disparity", "must be >= 0");
  if (s.uniqueness_ratio < 0) invalid("stereo.uniqueness_ratio", "must be >= 0");
  if (s.texture_threshold < 0) invalid("stereo.texture_threshold", "must be >= 0");
  if (s.pre_filter_cap < 1 || s.pre_filter_cap > 63)
    invalid("stereo.pre_filter_cap", "must be in [1, 63]");
  if (s.speckle_window < 0) invalid("stereo.speckle_window", "must be >= 0");
  if (s.speckle_range < 0) invalid("stereo.speckle_range", "must be >= 0");
  if (s.sgbm_p1 < 0 || s.sgbm_p2 < 0) invalid("stereo.sgbm_p1", "penalties must be >= 0");
  if (s.sgbm_p2 != 0 && s.sgbm_p2 <= s.sgbm_p1)
    invalid("stereo.sgbm_p2", "must be greater than sgbm_p1");
  if (s.rectify_alpha != -1 && (s.rectify_alpha < 0 || s.rectify_alpha > 1))
    invalid("stereo.rectify_alpha", "must be in [0, 1] (or -1 for OpenCV's default)");
  if (s.pre_filter_size < 5 || s.pre_filter_size % 2 == 0 || s.pre_filter_size > 255)
    invalid("stereo.pre_filter_size", "must be odd and in [5, 255]");
  if (s.input_bits != 0 && (s.input_bits < 8 || s.input_bits > 16))
    invalid("stereo.input_bits", "must be 0 (detect) or in [8, 16]");
  // A stride of 4096 keeps one pixel per 4096 x 4096 block: beyond that a stride selects
  // nothing more in any camera image, and near INT_MAX the pixel loop's counters overflowed.
  if (s.stride < 1 || s.stride > kMaxStride)
    invalid("stereo.stride", "must be in [1, " + std::to_string(kMaxStride) +
                                 "] (a larger stride keeps at most one pixel of a 4096 px image)");
  if (s.roi_px[0] < 0 || s.roi_px[1] < 0 || s.roi_px[2] < 0 || s.roi_px[3] < 0)
    invalid("stereo.roi", "x, y, width and height must be >= 0");
  if (!(s.z_min_m > 0)) invalid("stereo.z_min", "must be > 0");
  if (!(s.z_max_m > s.z_min_m)) invalid("stereo.z_max", "must be greater than stereo.z_min");

  if (!(c.sensor.pointing_error_px >= 0)) invalid("sensor.pointing_error_px", "must be >= 0");
  if (!(c.sensor.disparity_error_px > 0)) invalid("sensor.disparity_error_px", "must be > 0");
  // Without pointing error the covariance is singular: every det weight would be infinite.
  if (c.rules.ccm.weighting == "det" && !(c.sensor.pointing_error_px > 0))
    invalid("rules.ccm.weighting", "'det' needs sensor.pointing_error_px > 0 (singular covariance)");

  if (c.map.layers.empty()) invalid("map.layers", "at least one layer is required");
  for (size_t i = 0; i < c.map.layers.size(); ++i) {
    const LayerConfig& l = c.map.layers[i];
    const std::string k = "map.layers." + std::to_string(i);
    if (!(l.resolution_m >= kMinResolutionM && l.resolution_m <= kMaxResolutionM))
      invalid(k + ".resolution",
              "must be in [1e-4, 1000] m (finer than 0.1 mm is far below any stereo point's "
              "error; coarser than 1 km maps nothing a rover meets)");
    if (l.size < 2 || l.size % 2 != 0) invalid(k + ".size", "must be even and >= 2");
    if (l.size > kMaxLayerSize)
      invalid(k + ".size", "must be <= " + std::to_string(kMaxLayerSize) +
                               " (a layer's size^2 cells are addressed with 32-bit indices)");
    if (!std::isfinite(l.max_std_ratio)) invalid(k + ".max_std_ratio", "must be finite");
    if (l.hazard.kernel < 1 || l.hazard.kernel % 2 == 0 || l.hazard.kernel >= l.size)
      invalid(k + ".hazard.kernel", "must be odd, >= 1 and smaller than the layer size");
    if (i > 0) {
      const double prev = c.map.layers[i - 1].resolution_m;
      const double ratio = l.resolution_m / prev;
      if (ratio < 1.0 - 1e-9 || std::abs(ratio - std::round(ratio)) > 1e-6)
        invalid(k + ".resolution", "must be an integer multiple of the previous layer's (" +
                                       std::to_string(prev) + ")");
    }
  }
  if (c.map.insertion == "finest_then_pool") {
    // SPEC 5: pooling is defined between consecutive layers of one rule family (the
    // rules' kPoolFamily, rules/rule_registry.hpp).
    for (size_t i = 1; i < c.map.layers.size(); ++i)
      if (!same_pool_family(c.map.layers[i].rule, c.map.layers[i - 1].rule))
        invalid("map.layers." + std::to_string(i) + ".rule",
                std::string("finest_then_pool pools only between layers of one rule family (ccm "
                            "with ccm, kalman/omg with kalman/omg), but layer ") +
                    std::to_string(i - 1) + " is " + rule_name(c.map.layers[i - 1].rule) +
                    " and layer " + std::to_string(i) + " is " + rule_name(c.map.layers[i].rule) +
                    "; use map.insertion: all_layers");
  }
  if (c.rules.kalman.time_inflation_m2 < 0) invalid("rules.kalman.time_inflation", "must be >= 0");
  if (c.rules.kalman.min_variance_m2 < 0) invalid("rules.kalman.min_variance", "must be >= 0");
  if (!(c.rules.kalman.gate_sigma >= 0)) invalid("rules.kalman.gate_sigma", "must be >= 0");
  if (!(c.rules.omg.gate_sigma >= 0)) invalid("rules.omg.gate_sigma", "must be >= 0");
  if (!(c.rules.omg.max_weight > 0)) invalid("rules.omg.max_weight", "must be > 0");
  if (!(c.rules.omg.decay > 0 && c.rules.omg.decay <= 1)) invalid("rules.omg.decay", "must be in (0, 1]");
  if (!(c.rules.ccm.max_weight > 0)) invalid("rules.ccm.max_weight", "must be > 0");
  if (c.rules.ccm.min_points < 1) invalid("rules.ccm.min_points", "must be >= 1");
  if (!(c.rules.ccm.min_coverage >= 0)) invalid("rules.ccm.min_coverage", "must be >= 0");
  if (!(c.rules.ccm.max_std_ratio >= 0)) invalid("rules.ccm.max_std_ratio", "must be >= 0");
  if (!(c.hazard.max_slope_deg > 0 && c.hazard.max_slope_deg < 90))
    invalid("hazard.max_slope_deg", "must be in (0, 90)");
  // Both become a reach in cells (radius / resolution, converted to int): 100 m is beyond
  // any rover and keeps that reach within int at the finest resolution accepted (1e-4 m).
  if (!(c.hazard.wheelbase_m > 0 && c.hazard.wheelbase_m <= 100))
    invalid("hazard.wheelbase", "must be in (0, 100] m (a reach in cells must fit an int)");
  if (!(c.hazard.min_kernel_fill >= 0 && c.hazard.min_kernel_fill <= 1))
    invalid("hazard.min_kernel_fill", "must be in [0, 1]");
  if (!(c.hazard.min_axis_coverage >= 0 && c.hazard.min_axis_coverage <= 1))
    invalid("hazard.min_axis_coverage", "must be in [0, 1]");
  if (!(c.hazard.k_sigma >= 0 && c.hazard.k_sigma <= 100)) invalid("hazard.k_sigma", "must be in [0, 100]");
  if (!std::isfinite(c.hazard.critical_height_m) || c.hazard.critical_height_m == 0)
    invalid("hazard.critical_height", "must be > 0 (or < 0 to use the finest layer's h_min)");
  if (!(std::isfinite(c.hazard.footprint_radius_m) && c.hazard.footprint_radius_m <= 100))
    invalid("hazard.footprint_radius",
            "must be finite and <= 100 m, a reach in cells must fit an int (< 0: wheelbase / 2)");
  if (!(c.hazard.fused_extent_m >= 0 && c.hazard.fused_extent_m < 1e4))
    invalid("hazard.fused_extent", "must be in [0, 1e4) m (0: the largest layer's extent)");
  if (!std::isfinite(c.stereo.max_below_ground_m))
    invalid("stereo.max_below_ground", "must be finite (<= 0 disables the check)");
  if (!(c.stereo.below_ground_tolerance_m >= 0 && c.stereo.below_ground_tolerance_m < 1e3))
    invalid("stereo.below_ground_tolerance", "must be in [0, 1000) m");
  if (!(c.stereo.max_depression_slope_deg > 0 && c.stereo.max_depression_slope_deg <= 90))
    invalid("stereo.max_depression_slope_deg", "must be in (0, 90] deg (90: off)");
  if (!(c.stereo.occlusion_reach >= 0 && c.stereo.occlusion_reach <= 100))
    invalid("stereo.occlusion_reach", "must be in [0, 100] (0: off)");
  if (!(c.stereo.occlusion_margin_m >= 0 && c.stereo.occlusion_margin_m < 1e3))
    invalid("stereo.occlusion_margin", "must be in [0, 1000) m");
  if (!(c.stereo.occlusion_fill_m >= 0 && c.stereo.occlusion_fill_m <= 10))
    invalid("stereo.occlusion_fill", "must be in [0, 10] m");
  if (c.stereo.support_rows < 0 || c.stereo.support_rows > 100000)
    invalid("stereo.support_rows", "must be in [0, 100000] pixels (0: off)");
  if (!(c.stereo.support_tolerance >= 0 && c.stereo.support_tolerance < 1))
    invalid("stereo.support_tolerance", "must be in [0, 1)");
  if (!(c.stereo.support_margin_px >= 0 && c.stereo.support_margin_px < 1e4))
    invalid("stereo.support_margin_px", "must be in [0, 1e4) pixels");
  if (!(s.band_max_slope_deg >= 0 && s.band_max_slope_deg < 90))
    invalid("stereo.band_max_slope_deg", "must be in [0, 90)");
  if (!(s.band_max_height_m >= 0 && std::isfinite(s.band_max_height_m)))
    invalid("stereo.band_max_height", "must be finite and >= 0");
  if (!(s.band_max_depth_m >= 0 && std::isfinite(s.band_max_depth_m)))
    invalid("stereo.band_max_depth", "must be finite and >= 0");
  if (c.output.every_n < 1) invalid("output.every_n", "must be >= 1");
  if (c.output.queue_frames < 0 || c.output.queue_frames > kMaxOutputQueueFrames)
    invalid("output.queue_frames",
            "must be in [0, " + std::to_string(kMaxOutputQueueFrames) + "] (0: synchronous)");
  if (c.output.png_min_size < 1 || c.output.png_min_size > 8192)
    invalid("output.png_min_size", "must be in [1, 8192]");
  if (!(c.output.png_height_clip_pct >= 0 && c.output.png_height_clip_pct < 50))
    invalid("output.png_height_clip_pct", "must be in [0, 50)");
}

std::string to_yaml(const Config& c) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  const StereoConfig& s = c.stereo;
  out << YAML::Key << "stereo" << YAML::Value << YAML::BeginMap
      << YAML::Key << "matcher" << YAML::Value << s.matcher
      << YAML::Key << "num_disparities" << YAML::Value << s.num_disparities
      << YAML::Key << "block_size" << YAML::Value << s.block_size
      << YAML::Key << "min_disparity" << YAML::Value << s.min_disparity
      << YAML::Key << "uniqueness_ratio" << YAML::Value << s.uniqueness_ratio
      << YAML::Key << "texture_threshold" << YAML::Value << s.texture_threshold
      << YAML::Key << "pre_filter_cap" << YAML::Value << s.pre_filter_cap
      << YAML::Key << "speckle_window" << YAML::Value << s.speckle_window
      << YAML::Key << "speckle_range" << YAML::Value << s.speckle_range
      << YAML::Key << "disp12_max_diff" << YAML::Value << s.disp12_max_diff
      << YAML::Key << "sgbm_p1" << YAML::Value << s.sgbm_p1
      << YAML::Key << "sgbm_p2" << YAML::Value << s.sgbm_p2
      << YAML::Key << "sgbm_mode" << YAML::Value << s.sgbm_mode
      << YAML::Key << "pre_filter_type" << YAML::Value << s.pre_filter_type
      << YAML::Key << "pre_filter_size" << YAML::Value << s.pre_filter_size
      << YAML::Key << "input_bits" << YAML::Value << s.input_bits
      << YAML::Key << "rectify_alpha" << YAML::Value << s.rectify_alpha
      << YAML::Key << "stride" << YAML::Value << s.stride
      << YAML::Key << "roi" << YAML::Value << YAML::Flow << YAML::BeginSeq << s.roi_px[0]
      << s.roi_px[1] << s.roi_px[2] << s.roi_px[3] << YAML::EndSeq
      << YAML::Key << "z_min" << YAML::Value << s.z_min_m
      << YAML::Key << "z_max" << YAML::Value << s.z_max_m
      << YAML::Key << "max_below_ground" << YAML::Value << s.max_below_ground_m
      << YAML::Key << "below_ground_tolerance" << YAML::Value << s.below_ground_tolerance_m
      << YAML::Key << "max_depression_slope_deg" << YAML::Value << s.max_depression_slope_deg
      << YAML::Key << "occlusion_reach" << YAML::Value << s.occlusion_reach
      << YAML::Key << "occlusion_margin" << YAML::Value << s.occlusion_margin_m
      << YAML::Key << "occlusion_fill" << YAML::Value << s.occlusion_fill_m
      << YAML::Key << "support_rows" << YAML::Value << s.support_rows
      << YAML::Key << "support_tolerance" << YAML::Value << s.support_tolerance
      << YAML::Key << "support_margin_px" << YAML::Value << s.support_margin_px
      << YAML::Key << "search" << YAML::Value << s.search
      << YAML::Key << "band_max_slope_deg" << YAML::Value << s.band_max_slope_deg
      << YAML::Key << "band_max_height" << YAML::Value << s.band_max_height_m
      << YAML::Key << "band_max_depth" << YAML::Value << s.band_max_depth_m << YAML::EndMap;
  out << YAML::Key << "sensor" << YAML::Value << YAML::BeginMap
      << YAML::Key << "model" << YAML::Value << c.sensor.model
      << YAML::Key << "pointing_error_px" << YAML::Value << c.sensor.pointing_error_px
      << YAML::Key << "disparity_error_px" << YAML::Value << c.sensor.disparity_error_px
      << YAML::EndMap;
  out << YAML::Key << "map" << YAML::Value << YAML::BeginMap
      << YAML::Key << "insertion" << YAML::Value << c.map.insertion
      << YAML::Key << "layers" << YAML::Value << YAML::BeginSeq;
  for (const auto& l : c.map.layers) {
    out << YAML::Flow << YAML::BeginMap
        << YAML::Key << "resolution" << YAML::Value << l.resolution_m
        << YAML::Key << "size" << YAML::Value << l.size
        << YAML::Key << "rule" << YAML::Value << rule_name(l.rule)
        << YAML::Key << "max_std_ratio" << YAML::Value << l.max_std_ratio
        << YAML::Key << "hazard" << YAML::Value << YAML::BeginMap
        << YAML::Key << "kernel" << YAML::Value << l.hazard.kernel
        << YAML::Key << "roughness_threshold" << YAML::Value << l.hazard.roughness_threshold_m
        << YAML::Key << "h_min" << YAML::Value << l.hazard.h_min_m
        << YAML::Key << "rho_max" << YAML::Value << l.hazard.rho_max_m2
        << YAML::EndMap << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  out << YAML::Key << "rules" << YAML::Value << YAML::BeginMap
      << YAML::Key << "kalman" << YAML::Value << YAML::Flow << YAML::BeginMap
      << YAML::Key << "time_inflation" << YAML::Value << c.rules.kalman.time_inflation_m2
      << YAML::Key << "min_variance" << YAML::Value << c.rules.kalman.min_variance_m2
      << YAML::Key << "gate_sigma" << YAML::Value << c.rules.kalman.gate_sigma
      << YAML::EndMap
      << YAML::Key << "omg" << YAML::Value << YAML::Flow << YAML::BeginMap
      << YAML::Key << "max_weight" << YAML::Value << c.rules.omg.max_weight
      << YAML::Key << "decay" << YAML::Value << c.rules.omg.decay
      << YAML::Key << "gate_sigma" << YAML::Value << c.rules.omg.gate_sigma << YAML::EndMap
      << YAML::Key << "ccm" << YAML::Value << YAML::Flow << YAML::BeginMap
      << YAML::Key << "weighting" << YAML::Value << c.rules.ccm.weighting
      << YAML::Key << "full_plane" << YAML::Value << c.rules.ccm.full_plane
      << YAML::Key << "max_weight" << YAML::Value << c.rules.ccm.max_weight
      << YAML::Key << "min_points" << YAML::Value << c.rules.ccm.min_points
      << YAML::Key << "min_coverage" << YAML::Value << c.rules.ccm.min_coverage
      << YAML::Key << "max_std_ratio" << YAML::Value << c.rules.ccm.max_std_ratio
      << YAML::EndMap << YAML::EndMap;
  out << YAML::Key << "hazard" << YAML::Value << YAML::Flow << YAML::BeginMap
      << YAML::Key << "max_slope_deg" << YAML::Value << c.hazard.max_slope_deg
      << YAML::Key << "wheelbase" << YAML::Value << c.hazard.wheelbase_m
      << YAML::Key << "min_kernel_fill" << YAML::Value << c.hazard.min_kernel_fill
      << YAML::Key << "roughness" << YAML::Value << c.hazard.roughness
      << YAML::Key << "min_axis_coverage" << YAML::Value << c.hazard.min_axis_coverage
      << YAML::Key << "k_sigma" << YAML::Value << c.hazard.k_sigma
      << YAML::Key << "critical_height" << YAML::Value << c.hazard.critical_height_m
      << YAML::Key << "footprint_radius" << YAML::Value << c.hazard.footprint_radius_m
      << YAML::Key << "fused_extent" << YAML::Value << c.hazard.fused_extent_m
      << YAML::Key << "incremental" << YAML::Value << c.hazard.incremental
      << YAML::EndMap;
  out << YAML::Key << "pose_uncertainty" << YAML::Value << YAML::Flow << YAML::BeginMap
      << YAML::Key << "enabled" << YAML::Value << c.pose_uncertainty.enabled << YAML::EndMap;
  out << YAML::Key << "output" << YAML::Value << YAML::Flow << YAML::BeginMap
      << YAML::Key << "every_n" << YAML::Value << c.output.every_n
      << YAML::Key << "png" << YAML::Value << c.output.png
      << YAML::Key << "jdem" << YAML::Value << c.output.jdem
      << YAML::Key << "format" << YAML::Value << c.output.format
      << YAML::Key << "queue_frames" << YAML::Value << c.output.queue_frames
      << YAML::Key << "png_min_size" << YAML::Value << c.output.png_min_size
      << YAML::Key << "png_height_clip_pct" << YAML::Value << c.output.png_height_clip_pct
      << YAML::Key << "mosaic" << YAML::Value << c.output.mosaic << YAML::EndMap;
  out << YAML::EndMap;
  return out.c_str();
}

}  // namespace hazmap
