// The rule registry (rules/rule_registry.hpp): every RuleKind has a row read off its rule
// struct, names round-trip, and the questions the program asks of a rule kind (plane or
// not, hazard family, pooling family, the layer make_layer builds) answer as they did when
// they were switches, as does the configuration's error for a name no rule has.

#include "hazmap/rules/rule_registry.hpp"

#include <gtest/gtest.h>

#include <string>
#include <iterator>
#include <vector>

#include "hazmap/core/error.hpp"
#include "hazmap/hazard/hazard_params.hpp"
#include "hazmap/io/config.hpp"
#include "hazmap/map/layer_stack.hpp"

namespace hazmap {
namespace {

const RuleKind kAllKinds[] = {RuleKind::bananas, RuleKind::kalman, RuleKind::omg, RuleKind::ccm};

TEST(RuleRegistry, OneRowPerKindInEnumOrder) {
  ASSERT_EQ(Rules::size, std::size(kAllKinds));
  for (std::size_t i = 0; i < Rules::size; ++i) EXPECT_EQ(kRuleTable[i].kind, kAllKinds[i]);
}

TEST(RuleRegistry, NamesRoundTripForEveryKind) {
  const std::vector<std::string> expected = {"bananas", "kalman", "omg", "ccm"};
  std::vector<std::string> names;
  for (const char* n : rule_names()) names.emplace_back(n);
  EXPECT_EQ(names, expected);
  for (RuleKind k : kAllKinds) {
    const std::string name = rule_name(k);
    EXPECT_EQ(rule_info(k).name, name);
    ASSERT_TRUE(rule_kind(name).has_value()) << name;
    EXPECT_EQ(*rule_kind(name), k) << name;
    ASSERT_NE(find_rule(name), nullptr);
    EXPECT_EQ(find_rule(name)->kind, k);
  }
  for (const char* other : {"", "Ccm", "ccm ", "fused", "footprint", "min_height"}) {
    EXPECT_FALSE(rule_kind(other).has_value()) << other;
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
  for (RuleKind k : kAllKinds) {
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
  for (RuleKind a : kAllKinds)
    for (RuleKind b : kAllKinds)
      EXPECT_EQ(same_pool_family(a, b), family(a) == family(b)) << rule_name(a) << " " << rule_name(b);
}

TEST(RuleRegistry, VisitRuleCallsWithTheKindsStruct) {
  for (RuleKind k : kAllKinds) {
    const char* visited = visit_rule(k, [](auto tag) { return decltype(tag)::type::kName; });
    EXPECT_STREQ(visited, rule_name(k));
  }
  std::vector<std::string> seen;
  for_each_rule([&](auto tag) { seen.emplace_back(decltype(tag)::type::kName); });
  EXPECT_EQ(seen, (std::vector<std::string>{"bananas", "kalman", "omg", "ccm"}));
}

TEST(RuleRegistry, MakeLayerBuildsTheKindsRule) {
  for (RuleKind k : kAllKinds) {
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
  EXPECT_EQ(config_error("map:\n  layers:\n    - {resolution: 0.01, size: 8, rule: magic}\n"),
            "test.yaml:3: key 'map.layers.0.rule': 'magic' is not one of bananas | kalman | omg | "
            "ccm");
  EXPECT_EQ(config_error("map:\n  layers:\n    - {resolution: 0.01, size: 8, rule: Ccm}\n"),
            "test.yaml:3: key 'map.layers.0.rule': 'Ccm' is not one of bananas | kalman | omg | "
            "ccm");
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
