// The key tables (io/config_schema.hpp) against the structs they bind, the parser, the
// dump and the README: tests generated from the tables, so that a new key is covered by
// its one line.
#include "hazmap/io/config_schema.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <type_traits>
#include <utility>

#include <yaml-cpp/yaml.h>

#include "hazmap/core/error.hpp"
#include "hazmap/rules/rule_registry.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

// One layer with kernel 1, so that every layer size the checks allow is also allowed by
// "kernel smaller than the layer".
const char* kOneLayer = "map:\n  layers:\n    - {resolution: 0.01, size: 128, rule: kalman, hazard: {kernel: 1}}\n";

std::string config_error(const std::vector<std::string>& sets) {
  try {
    parse_config(kOneLayer, "test.yaml", sets);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// --- how many members the structs have: aggregate initialisation with N of anything ---
template <class T>
struct IsOptional : std::false_type {};
template <class T>
struct IsOptional<std::optional<T>> : std::true_type {};
struct AnyValue {
  // Not to std::optional itself: an optional member is built from the value it holds
  // (the two conversions would otherwise compete, -Wconversion).
  template <class T, std::enable_if_t<!IsOptional<T>::value, int> = 0>
  operator T() const;  // declared only: used in unevaluated context
};
template <class T, class = void, class... A>
struct Initialisable : std::false_type {};
template <class T, class... A>
struct Initialisable<T, std::void_t<decltype(T{std::declval<A>()...})>, A...> : std::true_type {};

template <class T, class... A>
constexpr std::size_t member_count() {
  if constexpr (Initialisable<T, void, A..., AnyValue>::value)
    return member_count<T, A..., AnyValue>();
  else
    return sizeof...(A);
}

/// Members of every rule's settings struct (rules/rule_registry.hpp: RuleEntry::settings).
template <class Entry>
constexpr std::size_t settings_members() {
  if constexpr (std::is_null_pointer_v<decltype(Entry::settings)>) {
    return 0;
  } else {
    return member_count<std::decay_t<decltype(std::declval<RulesConfig&>().*(Entry::settings))>>();
  }
}
template <class... Entries>
constexpr std::size_t rule_settings_members(RuleEntries<Entries...>) {
  return (settings_members<Entries>() + ... + 0);
}
template <class... Entries>
constexpr std::size_t rules_with_settings(RuleEntries<Entries...>) {
  return ((std::is_null_pointer_v<decltype(Entries::settings)> ? 0 : 1) + ... + 0);
}

TEST(ConfigSchema, EveryStructMemberHasAKey) {
  // A member added to a config struct without its line in config_schema.cpp fails here.
  const std::size_t members =
      member_count<StereoConfig>() + member_count<SensorConfig>() + member_count<MapConfig>() +
      rule_settings_members(Rules{}) +  // rules.<name>: KalmanConfig, OmgConfig, CcmConfig
      member_count<HazardConfig>() + member_count<PoseUncertaintyConfig>() +
      member_count<OutputConfig>() +
      member_count<C2fConfig>() - 1;  // StereoConfig::c2f: a key per member, none for itself
  EXPECT_EQ(config_keys().size(), members);  // map.layers is MapConfig::layers' entry
  EXPECT_EQ(layer_keys().size(), member_count<LayerConfig>() - 1 + member_count<LayerHazardConfig>());
  EXPECT_EQ(member_count<RulesConfig>(), rules_with_settings(Rules{}));  // one per rule with settings
  EXPECT_EQ(member_count<LayerHazardConfig>(), 4u);
}

// --- a value per key that differs from the default and passes validation ---

std::string number_text(double v, bool integer) {
  char text[40];
  if (integer) std::snprintf(text, sizeof text, "%lld", static_cast<long long>(v));
  else std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

template <class Owner>
std::vector<std::string> candidates(const ConfigKey<Owner>& key, Owner& defaults) {
  std::vector<std::string> out;
  // Numbers near `d` and near the checks' bounds (any number differs from `auto`).
  const auto numbers = [&](double d, bool integer, bool is_auto) {
    std::vector<double> tries = {d + 1, d + 2, d - 1, d * 2, d / 2, d + 16, d + 0.5, d + 0.1, d - 0.1};
    for (const ValueCheck& c : key.checks)
      for (double b : {c.lo, c.hi}) tries.push_back(b);
    for (double t : tries)
      if (std::isfinite(t) && (is_auto || t != d) && (!integer || t == std::floor(t)))
        out.push_back(number_text(t, integer));
  };
  std::visit(
      [&](auto field) {
        using F = decltype(field);
        if constexpr (std::is_same_v<F, std::monostate>) {
        } else {
          const auto value = field(defaults);
          using V = std::decay_t<decltype(value)>;
          if constexpr (std::is_same_v<V, bool>) {
            out.push_back(value ? "false" : "true");
          } else if constexpr (std::is_same_v<V, RuleKind>) {
            for (const std::string& c : key_choices(key))
              if (c != rule_name(value)) out.push_back(c);
          } else if constexpr (std::is_enum_v<V>) {
            for (const std::string& c : key_choices(key))
              if (c != enum_name(value)) out.push_back(c);
          } else if constexpr (std::is_same_v<V, std::array<int, 4>>) {
            out.push_back("[1, 2, 3, 4]");
          } else if constexpr (IsOptional<V>::value) {
            if (value) out.push_back("auto");
            numbers(value.value_or(0.0), std::is_same_v<V, std::optional<int>>, !value);
          } else {
            numbers(value, std::is_same_v<V, int>, false);
          }
        }
      },
      key.field);
  return out;
}

/// --set assignments that change every key from its default, each one valid.
std::vector<std::string> every_key_changed() {
  std::vector<std::string> sets;
  const auto choose = [&](const std::string& name, const std::vector<std::string>& tries) {
    for (const std::string& value : tries) {
      sets.push_back(name + "=" + value);
      if (config_error(sets).empty()) return;
      sets.pop_back();
    }
    ADD_FAILURE() << name << ": no value other than the default passes validation";
  };
  Config defaults;
  for (const TopKey& key : config_keys())
    if (key.name != "map.layers") choose(key.name, candidates(key, defaults));
  LayerConfig layer;
  layer.hazard.kernel = 1;  // as in kOneLayer
  for (const LayerKey& key : layer_keys()) choose("map.layers.0." + key.name, candidates(key, layer));
  return sets;
}

/// Each key's value as the dump writes it, by dotted name.
std::map<std::string, std::string> dumped_values(const Config& config) {
  std::map<std::string, std::string> values;
  const YAML::Node root = YAML::Load(to_yaml(config));
  const std::function<void(const YAML::Node&, const std::string&)> walk = [&](const YAML::Node& n,
                                                                              const std::string& path) {
    if (n.IsMap()) {
      for (const auto& kv : n) walk(kv.second, path.empty() ? kv.first.Scalar() : path + "." + kv.first.Scalar());
    } else if (n.IsSequence() && path == "map.layers") {
      for (std::size_t i = 0; i < n.size(); ++i) walk(n[i], path + "." + std::to_string(i));
    } else {
      std::ostringstream text;
      text << n;
      values[path] = text.str();
    }
  };
  walk(root, "");
  return values;
}

TEST(ConfigSchema, EveryKeyIsSetByDottedNameAndRoundTripsThroughTheDump) {
  const std::vector<std::string> sets = every_key_changed();
  const Config changed = parse_config(kOneLayer, "test.yaml", sets);
  const auto before = dumped_values(parse_config(kOneLayer, "test.yaml"));
  const auto after = dumped_values(changed);
  // Every key in the dump, every one changed by its --set.
  for (const TopKey& key : config_keys()) {
    if (key.name == "map.layers") continue;
    EXPECT_NE(before.at(key.name), after.at(key.name)) << key.name;
  }
  for (const LayerKey& key : layer_keys())
    EXPECT_NE(before.at("map.layers.0." + key.name), after.at("map.layers.0." + key.name)) << key.name;
  EXPECT_EQ(after.size(), config_keys().size() - 1 + layer_keys().size());
  // The same values from YAML text, and back through the dump.
  Config from_text = parse_config(to_yaml(changed), "dump");
  EXPECT_EQ(dumped_values(from_text), after);
  EXPECT_EQ(to_yaml(from_text), to_yaml(changed));
}

TEST(ConfigSchema, SetReachesLayerAndEnumKeys) {
  const Config c = parse_config(kOneLayer, "t",
                                {"map.layers.0.hazard.h_min=0.02", "map.layers.0.rule=ccm",
                                 "rules.ccm.weighting=trace", "hazard.roughness=detrended",
                                 "output.format=both", "stereo.roi=[1, 2, 3, 4]"});
  EXPECT_EQ(c.map.layers[0].hazard.h_min_m, 0.02);
  EXPECT_EQ(c.map.layers[0].rule, RuleKind::ccm);
  EXPECT_EQ(c.rules.ccm.weighting, CcmWeighting::trace);
  EXPECT_EQ(c.hazard.roughness, RoughnessStatistic::detrended);
  EXPECT_EQ(c.output.format, GridFormat::both);
  EXPECT_EQ(c.stereo.roi_px, (std::array<int, 4>{1, 2, 3, 4}));
}

// --- every check rejects a value just outside its bound and accepts one at or inside it ---

template <class Owner>
void check_bounds(const std::string& name, const ConfigKey<Owner>& key) {
  const bool integer = std::holds_alternative<int& (*)(Owner&)>(key.field) ||
                       std::holds_alternative<std::optional<int>& (*)(Owner&)>(key.field) ||
                       std::holds_alternative<std::array<int, 4>& (*)(Owner&)>(key.field);
  const bool array = std::holds_alternative<std::array<int, 4>& (*)(Owner&)>(key.field);
  const auto set = [&](double v) {
    const std::string t = number_text(v, integer);
    return name + "=" + (array ? "[" + t + ", " + t + ", " + t + ", " + t + "]" : t);
  };
  for (const ValueCheck& c : key.checks) {
    if (c.old_auto) continue;  // an old config's `auto`: EveryOldAutoNamesTheKeyAndSaysWriteAuto
    const auto step = [&](double b) { return integer ? 1.0 : 1e-6 * std::max(1.0, std::abs(b)); };
    const auto valid_near = [&](double v, double direction) {
      while (!(c.odd ? std::fmod(v, 2.0) != 0 : true) || !(c.multiple_of ? std::fmod(v, c.multiple_of) == 0 : true))
        v += direction;
      return v;
    };
    std::vector<std::pair<double, double>> bounds;  // (outside, inside)
    if (std::isfinite(c.lo))
      bounds.emplace_back(c.lo_open ? c.lo : c.lo - step(c.lo),
                          valid_near(c.lo_open ? c.lo + step(c.lo) : c.lo, 1));
    if (std::isfinite(c.hi))
      bounds.emplace_back(c.hi_open ? c.hi : c.hi + step(c.hi),
                          valid_near(c.hi_open ? c.hi - step(c.hi) : c.hi, -1));
    if (bounds.empty()) {  // "finite" only: the YAML reader already refuses inf and nan
      EXPECT_TRUE(c.finite) << name << ": a check without a bound";
      continue;
    }
    for (const auto& [outside, inside] : bounds) {
      if (c.has_except && outside == c.except) continue;
      const std::string rejected = config_error({set(outside)});
      EXPECT_NE(rejected.find("key '" + name + "': "), std::string::npos) << set(outside) << ": " << rejected;
      bool one_of_its_messages = false;
      for (const ValueCheck& any : key.checks) one_of_its_messages |= rejected.find(any.message()) != std::string::npos;
      EXPECT_TRUE(one_of_its_messages) << rejected;
      EXPECT_EQ(config_error({set(inside)}), "") << set(inside);
    }
    if (c.has_except) {
      EXPECT_EQ(config_error({set(c.except)}), "") << set(c.except);
    }
  }
  for (const std::string& choice : key_choices(key)) EXPECT_EQ(config_error({name + "=" + choice}), "") << choice;
  if (!key_choices(key).empty()) {
    EXPECT_NE(config_error({name + "=no_such_value"}).find("key '" + name + "': 'no_such_value' is not one of"),
              std::string::npos);
  }
}

TEST(ConfigSchema, EveryCheckRejectsJustOutsideAndAcceptsAtItsBound) {
  for (const TopKey& key : config_keys())
    if (key.name != "map.layers") check_bounds(key.name, key);
  for (const LayerKey& key : layer_keys()) check_bounds("map.layers.0." + key.name, key);
}

TEST(ConfigSchema, GeneratedMessagesReadAsBefore) {
  EXPECT_EQ(config_error({"hazard.max_slope_deg=90"}), "config: key 'hazard.max_slope_deg': must be in (0, 90)");
  EXPECT_EQ(config_error({"stereo.z_min=0"}), "config: key 'stereo.z_min': must be > 0");
  EXPECT_EQ(config_error({"output.every_n=0"}), "config: key 'output.every_n': must be >= 1");
  EXPECT_EQ(config_error({"stereo.z_max=0.05"}), "config: key 'stereo.z_max': must be greater than stereo.z_min");
  EXPECT_EQ(config_error({"stereo.sgbm_p1=5", "stereo.sgbm_p2=5"}),
            "config: key 'stereo.sgbm_p2': must be greater than sgbm_p1");
  EXPECT_EQ(config_error({"stereo.sgbm_p1=5", "stereo.sgbm_p2=6"}), "");
}

// The rules across keys (check_cross_key_rules), at their bounds.
TEST(ConfigSchema, CrossKeyRulesRejectAtTheirBoundsAndAcceptInside) {
  EXPECT_EQ(config_error({"stereo.z_min=0.5", "stereo.z_max=0.5000001"}), "");
  EXPECT_EQ(config_error({"stereo.sgbm_p2=5"}), "");  // P1 auto: checked only against a set P1
  EXPECT_EQ(config_error({"map.layers.0.size=8", "map.layers.0.hazard.kernel=9"}),
            "config: key 'map.layers.0.hazard.kernel': must be odd, >= 1 and smaller than the layer size");
  EXPECT_EQ(config_error({"map.layers.0.size=8", "map.layers.0.hazard.kernel=7"}), "");
  EXPECT_EQ(config_error({"sensor.pointing_error_px=0", "rules.ccm.weighting=det"}),
            "config: key 'rules.ccm.weighting': 'det' needs sensor.pointing_error_px > 0 (singular "
            "covariance)");
  EXPECT_EQ(config_error({"sensor.pointing_error_px=1e-9", "rules.ccm.weighting=det"}), "");
}

// --- docs/config_reference.md's table is the generated one ---

TEST(ConfigSchema, ReferenceTableIsGenerated) {
  const std::filesystem::path readme = testing::source_dir() / "docs" / "config_reference.md";
  std::ifstream in(readme);
  std::stringstream buffer;
  buffer << in.rdbuf();
  std::string text = buffer.str();
  const std::size_t begin = text.find(kConfigReferenceBegin);
  const std::size_t end = text.find(kConfigReferenceEnd);
  ASSERT_NE(begin, std::string::npos) << readme << ": no " << kConfigReferenceBegin;
  ASSERT_NE(end, std::string::npos) << readme << ": no " << kConfigReferenceEnd;
  const std::size_t table_begin = begin + std::string(kConfigReferenceBegin).size() + 1;
  const std::string generated = config_reference_markdown();
  if (std::getenv("HAZMAP_UPDATE_CONFIG_REFERENCE") != nullptr) {
    text.replace(table_begin, end - table_begin, generated);
    std::ofstream(readme) << text;
    return;
  }
  std::istringstream have(text.substr(table_begin, end - table_begin)), want(generated);
  std::string have_line, want_line;
  int line = 0;
  while (true) {
    const bool more_have = static_cast<bool>(std::getline(have, have_line));
    const bool more_want = static_cast<bool>(std::getline(want, want_line));
    ++line;
    if (!more_have && !more_want) break;
    ASSERT_EQ(have_line, want_line)
        << "docs/config_reference.md differs from the key table at row " << line << " ("
        << want_line.substr(0, want_line.find(" |", 2)) << "); regenerate it: "
        << "HAZMAP_UPDATE_CONFIG_REFERENCE=1 build/tests/hazmap_tests "
           "--gtest_filter=ConfigSchema.ReferenceTableIsGenerated";
  }
}

}  // namespace
}  // namespace hazmap
