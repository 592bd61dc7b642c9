// Settings the program may derive: a number or `auto` (std::optional, empty = auto), one
// spelling for every such key; an old config's sentinel for "derive" (0, or a negative
// number) fails with a line that names the key and says to write `auto`; and `auto`
// resolves to what the sentinel used to give.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include <opencv2/calib3d.hpp>

#include "hazmap/core/error.hpp"
#include "hazmap/hazard/hazard_params.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/io/config_schema.hpp"
#include "hazmap/map/layer_stack.hpp"
#include "hazmap/stereo/disparity.hpp"

namespace hazmap {
namespace {

const std::string kOneLayer =
    "map:\n  layers:\n    - {resolution: 0.04, size: 64, rule: ccm, hazard: {kernel: 5}}\n";

std::string config_error(const std::string& yaml, const std::vector<std::string>& sets = {}) {
  try {
    parse_config(yaml, "old.yaml", sets);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

template <class Owner>
bool is_optional(const ConfigKey<Owner>& key) {
  return std::holds_alternative<std::optional<double>& (*)(Owner&)>(key.field) ||
         std::holds_alternative<std::optional<int>& (*)(Owner&)>(key.field);
}

/// The key's member as a double, or nullopt for `auto`.
template <class Owner>
std::optional<double> value_of(const ConfigKey<Owner>& key, Owner& owner) {
  if (auto* d = std::get_if<std::optional<double>& (*)(Owner&)>(&key.field)) return (*d)(owner);
  auto i = std::get<std::optional<int>& (*)(Owner&)>(key.field)(owner);
  return i ? std::optional<double>(*i) : std::nullopt;
}

// The keys that take `auto`, all of them: a key that turns into one, or stops being one,
// is a user-facing change and belongs in this list.
TEST(AutoSettings, TheKeysThatTakeAuto) {
  std::set<std::string> names;
  for (const TopKey& k : config_keys())
    if (is_optional(k)) names.insert(k.name);
  for (const LayerKey& k : layer_keys())
    if (is_optional(k)) names.insert("map.layers[]." + k.name);
  const std::set<std::string> expected = {
      "stereo.sgbm_p1", "stereo.sgbm_p2", "stereo.input_bits", "stereo.row_offset_px",
      "hazard.critical_height", "hazard.footprint_radius", "hazard.fused_extent",
      "map.layers[].max_std_ratio", "map.layers[].hazard.roughness_threshold",
      "map.layers[].hazard.h_min", "map.layers[].hazard.rho_max"};
  EXPECT_EQ(names, expected);
}

// Every such key reads `auto` as empty and a number as that number, and the dump writes
// both back as they were.
template <class Owner>
void check_auto_and_number(const std::string& name, const ConfigKey<Owner>& key,
                           Owner& (*owner)(Config&)) {
  SCOPED_TRACE(name);
  Config automatic = parse_config(kOneLayer, "t", {name + "=auto"});
  EXPECT_FALSE(value_of(key, owner(automatic)).has_value());
  // A number every such key accepts (sgbm_p2 > sgbm_p1 auto's 0, in [8, 16] for bits).
  const double number = 9;
  Config set = parse_config(kOneLayer, "t", {name + "=9"});
  EXPECT_EQ(value_of(key, owner(set)), std::optional<double>(number));
  Config dumped_auto = parse_config(to_yaml(automatic), "dump");
  Config dumped_set = parse_config(to_yaml(set), "dump");
  EXPECT_FALSE(value_of(key, owner(dumped_auto)).has_value());
  EXPECT_EQ(value_of(key, owner(dumped_set)), std::optional<double>(number));
}

TEST(AutoSettings, EveryKeyReadsAutoAndANumberAndDumpsThemBack) {
  Config& (*top)(Config&) = [](Config& c) -> Config& { return c; };
  LayerConfig& (*first)(Config&) = [](Config& c) -> LayerConfig& { return c.map.layers.at(0); };
  for (const TopKey& k : config_keys())
    if (is_optional(k)) check_auto_and_number(k.name, k, top);
  for (const LayerKey& k : layer_keys())
    if (is_optional(k)) check_auto_and_number("map.layers.0." + k.name, k, first);
}

// An old config's "derive" (0 for some keys, a negative number for others) is refused with
// one line naming the key and saying to write `auto`; values that mean something now pass.
TEST(AutoSettings, OldSentinelsNameTheKeyAndSayWriteAuto) {
  struct Case {
    std::string key, old_value;
  };
  const std::vector<Case> old = {
      {"stereo.sgbm_p1", "0"},          {"stereo.sgbm_p2", "0"},
      {"stereo.input_bits", "0"},       {"hazard.fused_extent", "0"},
      {"hazard.critical_height", "-1"}, {"hazard.footprint_radius", "-1"},
      {"map.layers.0.max_std_ratio", "-1"},
      {"map.layers.0.hazard.roughness_threshold", "-1"},
      {"map.layers.0.hazard.h_min", "-1"}, {"map.layers.0.hazard.h_min", "0"},
      {"map.layers.0.hazard.rho_max", "-1"}, {"map.layers.0.hazard.rho_max", "0"},
      {"hazard.critical_height", "-1e-9"}};
  for (const Case& c : old) {
    SCOPED_TRACE(c.key + "=" + c.old_value);
    const std::string e = config_error(kOneLayer, {c.key + "=" + c.old_value});
    EXPECT_NE(e.find("key '" + c.key + "': "), std::string::npos) << e;
    EXPECT_NE(e.find("no longer means `auto`: write `auto`"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_EQ(config_error(kOneLayer, {c.key + "=auto"}), "");
  }
  // 0 keeps its own meaning where it has one: no lateral gate, no row offset, a footprint
  // of the cell alone, a roughness threshold of 0.
  for (const char* zero : {"map.layers.0.max_std_ratio=0", "stereo.row_offset_px=0",
                           "hazard.footprint_radius=0", "map.layers.0.hazard.roughness_threshold=0"})
    EXPECT_EQ(config_error(kOneLayer, {zero}), "") << zero;
  // From a file: the error names the file and line too, and nothing else.
  const std::string file = kOneLayer + "hazard:\n  wheelbase: 0.3\n  critical_height: -1\n";
  EXPECT_EQ(config_error(file),
            "old.yaml:6: key 'hazard.critical_height': a negative value no longer means `auto`: "
            "write `auto` (the finest layer's h_min)");
  EXPECT_EQ(config_error(kOneLayer + "stereo: {sgbm_p1: 0}\n"),
            "old.yaml:4: key 'stereo.sgbm_p1': 0 no longer means `auto`: write `auto` (8 x block^2)");
}

// `auto` resolves as the old sentinels did, each against an independent computation.
TEST(AutoSettings, AutoResolvesToWhatTheOldSentinelGave) {
  const Config c = parse_config(
      "map:\n  layers:\n"
      "    - {resolution: 0.02, size: 100, rule: kalman, max_std_ratio: auto, hazard: {kernel: 7, "
      "roughness_threshold: auto, h_min: auto}}\n"
      "    - {resolution: 0.08, size: 40, rule: ccm, hazard: {h_min: auto, rho_max: auto}}\n"
      "rules: {ccm: {max_std_ratio: 1.5}}\n"
      "hazard: {max_slope_deg: 25, wheelbase: 0.42, critical_height: auto, footprint_radius: auto, "
      "fused_extent: auto}\n"
      "stereo: {matcher: sgbm, block_size: 7, sgbm_p1: auto, sgbm_p2: auto}\n",
      "t");
  const HazardParams p = resolve_hazard_params(c);
  const double t = std::tan(25 * M_PI / 180);
  // Piecewise constant: (kernel - 1) r tan(max_slope), and h_min that threshold.
  EXPECT_NEAR(p.layers[0].roughness_threshold_m, 6 * 0.02 * t, 1e-15);
  EXPECT_NEAR(p.layers[0].h_min_m, 6 * 0.02 * t, 1e-15);
  EXPECT_EQ(p.layers[0].h_min_source, "derived roughness threshold");
  // CCM: h_min 0.75 r, rho_max h_min^2 / 16.
  EXPECT_NEAR(p.layers[1].h_min_m, 0.06, 1e-15);
  EXPECT_NEAR(p.layers[1].rho_max_m2, 0.06 * 0.06 / 16, 1e-18);
  // Run-wide: the finest layer's h_min, wheelbase / 2, the largest layer's side.
  EXPECT_EQ(p.critical_height_m, p.layers[0].h_min_m);
  EXPECT_NEAR(p.footprint_radius_m, 0.21, 1e-15);
  EXPECT_NEAR(p.fused_extent_m, 40 * 0.08, 1e-12);  // 3.2 m > 100 x 0.02 m
  // The lateral gate: rules.ccm.max_std_ratio x r / sqrt(12).
  EXPECT_NEAR(gate_std_m(c.map.layers[0], c.rules), 1.5 * 0.02 / std::sqrt(12.0), 1e-15);
  // SGBM penalties: 8 and 32 x block^2.
  const cv::Ptr<cv::StereoMatcher> m = create_stereo_matcher(c.stereo, 0, 64, false);
  const cv::Ptr<cv::StereoSGBM> sgbm = m.dynamicCast<cv::StereoSGBM>();
  ASSERT_FALSE(sgbm.empty());
  EXPECT_EQ(sgbm->getP1(), 8 * 49);
  EXPECT_EQ(sgbm->getP2(), 32 * 49);
  // Numbers win over every derivation.
  const Config set = parse_config(
      kOneLayer + "hazard: {critical_height: 0.05, footprint_radius: 0.1, fused_extent: 2}\n"
                  "stereo: {matcher: sgbm, sgbm_p1: 100, sgbm_p2: 400}\n",
      "t", {"map.layers.0.hazard.h_min=0.02", "map.layers.0.hazard.rho_max=1e-4",
            "map.layers.0.max_std_ratio=0"});
  const HazardParams q = resolve_hazard_params(set);
  EXPECT_EQ(q.critical_height_m, 0.05);
  EXPECT_EQ(q.footprint_radius_m, 0.1);
  EXPECT_EQ(q.fused_extent_m, 2);
  EXPECT_EQ(q.layers[0].h_min_m, 0.02);
  EXPECT_EQ(q.layers[0].rho_max_m2, 1e-4);
  EXPECT_EQ(gate_std_m(set.map.layers[0], set.rules), 0.0);  // 0: off, whatever rules.ccm says
  const cv::Ptr<cv::StereoSGBM> fixed =
      create_stereo_matcher(set.stereo, 0, 64, false).dynamicCast<cv::StereoSGBM>();
  ASSERT_FALSE(fixed.empty());
  EXPECT_EQ(fixed->getP1(), 100);
  EXPECT_EQ(fixed->getP2(), 400);
}

// The reference table shows `auto` as the default of every key that derives by default.
TEST(AutoSettings, ReferenceTableShowsAutoDefaults) {
  const std::string table = config_reference_markdown();
  for (const char* key : {"stereo.sgbm_p1", "stereo.sgbm_p2", "stereo.input_bits",
                          "hazard.critical_height", "hazard.footprint_radius", "hazard.fused_extent",
                          "map.layers[].max_std_ratio", "map.layers[].hazard.roughness_threshold",
                          "map.layers[].hazard.h_min", "map.layers[].hazard.rho_max"})
    EXPECT_NE(table.find(std::string("| `") + key + "` | `auto` |"), std::string::npos) << key;
  EXPECT_NE(table.find("| `stereo.row_offset_px` | 0 |"), std::string::npos);
}

}  // namespace
}  // namespace hazmap
