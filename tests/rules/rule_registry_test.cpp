// The rule registry (rules/rule_registry.hpp): every RuleKind has a row read off its rule
// struct, names round-trip, and the questions the program asks of a rule kind (plane or
// not, hazard family, pooling family, the layer make_layer builds) answer as they did when
// they were switches, as does the configuration's error for a name no rule has.

#include "hazmap/rules/rule_registry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <iterator>
#include <vector>

#include "hazmap/core/error.hpp"
#include "hazmap/hazard/hazard_params.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/map/layer_stack.hpp"

namespace hazmap {
namespace {

/// The four rules the map shipped with when the registry replaced the switches: the
/// "as before" tests below pin what each answered then. Every other list here is the
/// registry's own (kRuleTable, Rules), so that adding a rule edits no test.
const RuleKind kShippedKinds[] = {RuleKind::bananas, RuleKind::kalman, RuleKind::omg, RuleKind::ccm};

/// Every kind in the registry, in its order.
std::vector<RuleKind> all_kinds() {
  std::vector<RuleKind> kinds;
  for (const RuleInfo& row : kRuleTable) kinds.push_back(row.kind);
  return kinds;
}

/// The rule structs' kName, in the order of the registry's entries (Rules).
template <class... Entries>
std::vector<std::string> struct_names(RuleEntries<Entries...>) {
  return {Entries::type::kName...};
}

TEST(RuleRegistry, OneRowPerKindInEnumOrder) {
  ASSERT_EQ(Rules::size, all_kinds().size());
  for (std::size_t i = 0; i < Rules::size; ++i) EXPECT_EQ(kRuleTable[i].kind, static_cast<RuleKind>(i));
  for (std::size_t i = 0; i < std::size(kShippedKinds); ++i) EXPECT_EQ(kRuleTable[i].kind, kShippedKinds[i]);
}

TEST(RuleRegistry, NamesRoundTripForEveryKind) {
  std::vector<std::string> names;
  for (const char* n : rule_names()) names.emplace_back(n);
  EXPECT_EQ(names, struct_names(Rules{}));
  const std::vector<std::string> shipped = {"bananas", "kalman", "omg", "ccm"};
  ASSERT_GE(names.size(), shipped.size());
  EXPECT_TRUE(std::equal(shipped.begin(), shipped.end(), names.begin()));
  for (RuleKind k : all_kinds()) {
    const std::string name = rule_name(k);
    EXPECT_EQ(rule_info(k).name, name);
    ASSERT_NE(find_rule(name), nullptr);
    EXPECT_EQ(find_rule(name)->kind, k);
  }
  for (const char* other : {"", "Ccm", "ccm ", "fused", "footprint", "min_height"}) {
    EXPECT_EQ(find_rule(other), nullptr) << other;
  }
}

TEST(RuleRegistry, NamesComeFromTheRuleStructs) {
  EXPECT_STREQ(rule_name(RuleKind::bananas), BananasRule::kName);
  EXPECT_STREQ(rule_name(RuleKind::kalman), KalmanRule::kName);
  EXPECT_STREQ(rule_name(RuleKind::omg), OmgRule::kName);
  EXPECT_STREQ(rule_name(RuleKind::ccm), CcmRule::kName);
}

TEST(RuleRegistry, OnlyCcmHasAPlane) {
  for (RuleKind k : kShippedKinds) {
    EXPECT_EQ(rule_info(k).has_plane, k == RuleKind::ccm) << rule_name(k);
    EXPECT_EQ(rule_has_plane(rule_name(k)), k == RuleKind::ccm) << rule_name(k);
  }
  EXPECT_FALSE(rule_has_plane("fused"));
  EXPECT_FALSE(rule_has_plane("footprint"));
}

TEST(RuleRegistry, HazardFamiliesAsBefore) {
  EXPECT_EQ(hazard_family(RuleKind::bananas), HazardFamily::piecewise_constant);
  EXPECT_EQ(hazard_family(RuleKind::kalman), HazardFamily::piecewise_constant);
  EXPECT_EQ(hazard_family(RuleKind::omg), HazardFamily::piecewise_constant);
  EXPECT_EQ(hazard_family(RuleKind::ccm), HazardFamily::plane);
}

TEST(RuleRegistry, PoolFamiliesAsBefore) {
  // Before the registry: ccm alone, bananas alone, kalman with omg.
  auto family = [](RuleKind k) { return k == RuleKind::ccm ? 0 : k == RuleKind::bananas ? 1 : 2; };
  for (RuleKind a : kShippedKinds)
    for (RuleKind b : kShippedKinds)
      EXPECT_EQ(same_pool_family(a, b), family(a) == family(b)) << rule_name(a) << " " << rule_name(b);
}

TEST(RuleRegistry, VisitRuleCallsWithTheKindsStruct) {
  for (RuleKind k : all_kinds()) {
    const char* visited = visit_rule(k, [](auto tag) { return decltype(tag)::type::kName; });
    EXPECT_STREQ(visited, rule_name(k));
  }
}

TEST(RuleRegistry, MakeLayerBuildsTheKindsRule) {
  for (RuleKind k : all_kinds()) {
    MapConfig map;
    LayerConfig layer;
    layer.rule = k;
    layer.size = 8;
    map.layers = {layer};
    const auto built = make_layer(map, RulesConfig{}, 0);
    EXPECT_STREQ(built->rule_name(), rule_name(k));
  }
}

std::string config_error(const std::string& yaml) {
  try {
    parse_config(yaml, "test.yaml", {});
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(RuleRegistry, UnknownNameIsAnErrorNamingTheKeyAndTheRules) {
  std::string names;  // "bananas | kalman | omg | ccm": every name in the registry
  for (const char* n : rule_names()) names += (names.empty() ? "" : " | ") + std::string(n);
  EXPECT_EQ(names.rfind("bananas | kalman | omg | ccm", 0), 0u);
  EXPECT_EQ(config_error("map:\n  layers:\n    - {resolution: 0.01, size: 8, rule: magic}\n"),
            "test.yaml:3: key 'map.layers.0.rule': 'magic' is not one of " + names);
  EXPECT_EQ(config_error("map:\n  layers:\n    - {resolution: 0.01, size: 8, rule: Ccm}\n"),
            "test.yaml:3: key 'map.layers.0.rule': 'Ccm' is not one of " + names);
}

TEST(RuleRegistry, PoolingAcrossFamiliesIsAnError) {
  EXPECT_EQ(config_error("map:\n  insertion: finest_then_pool\n  layers:\n"
                         "    - {resolution: 0.01, size: 8, rule: omg}\n"
                         "    - {resolution: 0.04, size: 8, rule: bananas}\n"),
            "config: key 'map.layers.1.rule': finest_then_pool pools only between layers of one "
            "rule family (ccm with ccm, kalman/omg with kalman/omg), but layer 0 is omg and layer "
            "1 is bananas; use map.insertion: all_layers");
  EXPECT_EQ(config_error("map:\n  insertion: finest_then_pool\n  layers:\n"
                         "    - {resolution: 0.01, size: 8, rule: kalman}\n"
                         "    - {resolution: 0.04, size: 8, rule: omg}\n"),
            "");
}

}  // namespace
}  // namespace hazmap
