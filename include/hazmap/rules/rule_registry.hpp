#pragma once
// The registry of the update rules a configuration can name (map.layers.<i>.rule): one
// entry per RuleKind, in enum order, each pairing the enumerator with the rule struct
// (rules/update_rule.hpp). Everything the rest of the program asks about a rule kind is
// read off the struct here, once:
//
//   name         Rule::kName        rule_name, parsing map.layers.<i>.rule, the allowed names
//   has_plane    Rule::kHasPlane    hazard family (plane / piecewise constant), the plane
//                                   grids (slope_x, slope_y) in outputs, evaluation, viewer,
//                                   a layer's memory estimate (pipeline.cpp)
//   pool_family  Rule::kPoolFamily  which layers finest_then_pool may pool together
//                                   (optional, rules/update_rule.hpp: a rule without it
//                                   pools only with itself)
//
// and visit_rule(kind, f) calls f(RuleTag<Entry>{}) with the kind's line, so code that
// builds something per rule (make_layer) is one template instead of a switch.
//
// Adding a rule: its header, its #include below and one RuleEntry line in Rules (plus its
// enumerator in RuleKind, core/core_config.hpp). A rule with settings declares them once,
// as a struct in core/core_config.hpp and its member in RulesConfig, which its RuleEntry
// names; the rule's Config is that struct (an alias, like Kalman's) or extends it (CCM's);
// rule_config below copies them for make_layer. Each setting's YAML key is one line in
// io/config_schema.cpp.

#include <cstddef>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "hazmap/core/core_config.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/rules/bananas.hpp"
#include "hazmap/rules/ccm.hpp"
#include "hazmap/rules/kalman.hpp"
#include "hazmap/rules/omg.hpp"

namespace hazmap {

/// One registry line: the enumerator, the rule struct it selects and, for a rule with
/// settings, the RulesConfig member holding them (rules.<name> in the YAML, keys declared in
/// io/config_schema.cpp); the rule's Config is that struct or extends it (rule_config).
template <RuleKind K, class Rule, auto Settings = nullptr>
struct RuleEntry {
  static constexpr RuleKind kind = K;
  using type = Rule;
  static constexpr auto settings = Settings;  ///< &RulesConfig::<name>, or nullptr: none
};
template <class... Entries>
struct RuleEntries {
  static constexpr std::size_t size = sizeof...(Entries);
};

/// Every rule a configuration can name, in RuleKind order (checked below).
using Rules = RuleEntries<RuleEntry<RuleKind::bananas, BananasRule>,                       //
                          RuleEntry<RuleKind::kalman, KalmanRule, &RulesConfig::kalman>,   //
                          RuleEntry<RuleKind::omg, OmgRule, &RulesConfig::omg>,            //
                          RuleEntry<RuleKind::ccm, CcmRule, &RulesConfig::ccm>>;

/// A registry line passed to visit_rule's callable: `type` is the rule struct.
template <class Entry>
struct RuleTag {
  using type = typename Entry::type;
  using entry = Entry;
};

namespace rule_registry_detail {
template <class R, class = void>
struct DerivesConfig : std::false_type {};
template <class R>
struct DerivesConfig<R, std::void_t<decltype(R::derive_config(
                            std::declval<typename R::Config&>(), std::declval<const HazardConfig&>()))>>
    : std::true_type {};
}  // namespace rule_registry_detail

/// The Config a layer of the entry's rule gets: the rule's settings as `rules` holds them
/// (Entry::settings; none: Config{}), then what the rule derives from the hazard section
/// (optional Rule::derive_config(Config&, const HazardConfig&), rules/update_rule.hpp).
template <class Entry>
typename Entry::type::Config rule_config(const RulesConfig& rules, const HazardConfig& hazard) {
  using Rule = typename Entry::type;
  typename Rule::Config cfg{};
  if constexpr (!std::is_null_pointer_v<decltype(Entry::settings)>) {
    using Settings = std::decay_t<decltype(rules.*(Entry::settings))>;
    static_cast<Settings&>(cfg) = rules.*(Entry::settings);
  }
  if constexpr (rule_registry_detail::DerivesConfig<Rule>::value) Rule::derive_config(cfg, hazard);
  return cfg;
}

namespace rule_registry_detail {

template <class R, class = void>
struct PoolFamily {
  static constexpr const char* value = R::kName;  // no kPoolFamily: pools only with itself
};
template <class R>
struct PoolFamily<R, std::void_t<decltype(R::kPoolFamily)>> {
  static constexpr const char* value = R::kPoolFamily;
};

template <class... Entries>
constexpr bool in_enum_order(RuleEntries<Entries...>) {
  std::size_t i = 0;
  bool ok = true;
  ((ok = ok && static_cast<std::size_t>(Entries::kind) == i++), ...);
  return ok;
}

}  // namespace rule_registry_detail

static_assert(rule_registry_detail::in_enum_order(Rules{}),
              "rule_registry.hpp: Rules lists RuleKind's enumerators in order, each once");

/// What the program knows about a rule kind, all of it from the rule struct.
struct RuleInfo {
  RuleKind kind;
  const char* name;         ///< Rule::kName: the name in the YAML and the outputs
  bool has_plane;           ///< Rule::kHasPlane: cells fit a plane (CCM), plane hazard tests
  const char* pool_family;  ///< Rule::kPoolFamily, else kName: layers pool within one family
};

template <class Entry>
constexpr RuleInfo rule_info_of() {
  using R = typename Entry::type;
  return RuleInfo{Entry::kind, R::kName, R::kHasPlane, rule_registry_detail::PoolFamily<R>::value};
}

namespace rule_registry_detail {
template <class... Entries>
struct Table {
  static constexpr RuleInfo rows[] = {rule_info_of<Entries>()...};
};
template <class... Entries>
constexpr Table<Entries...> table(RuleEntries<Entries...>) {
  return {};
}
}  // namespace rule_registry_detail

/// The registry: one row per RuleKind, indexed by the enumerator.
inline constexpr const RuleInfo (&kRuleTable)[Rules::size] =
    decltype(rule_registry_detail::table(Rules{}))::rows;

namespace rule_registry_detail {
template <class... Entries>
struct Names {
  static constexpr const char* names[] = {Entries::type::kName...};
};
template <class... Entries>
constexpr Names<Entries...> names_of(RuleEntries<Entries...>) {
  return {};
}
}  // namespace rule_registry_detail

/// RuleKind's names as a configuration enum (core/enum_names.hpp: enum_name, enum_value,
/// enum_names): each rule's kName, so the key table treats map.layers[].rule like any
/// other enum key.
template <>
struct EnumNames<RuleKind> : decltype(rule_registry_detail::names_of(Rules{})) {};

/// The row of `kind`.
inline const RuleInfo& rule_info(RuleKind kind) {
  const auto i = static_cast<std::size_t>(kind);
  check(i < Rules::size, "rule_registry: a RuleKind without a registry entry (rule_registry.hpp)");
  return kRuleTable[i];
}

/// The name of `kind` (Rule::kName): in the YAML and the outputs.
inline const char* rule_name(RuleKind kind) { return rule_info(kind).name; }

/// The row named `name` (Rule::kName), nullptr for any other name.
inline const RuleInfo* find_rule(std::string_view name) {
  for (const RuleInfo& r : kRuleTable)
    if (name == r.name) return &r;
  return nullptr;
}

/// Whether `name` is a rule whose cells fit a plane; false for other names (evaluation and
/// the viewer also hold "fused", "footprint").
inline bool rule_has_plane(std::string_view name) {
  const RuleInfo* r = find_rule(name);
  return r != nullptr && r->has_plane;
}

/// Whether finest_then_pool may pool a layer of rule `a` into one of rule `b` (SPEC 5).
inline bool same_pool_family(RuleKind a, RuleKind b) {
  return std::string_view(rule_info(a).pool_family) == rule_info(b).pool_family;
}

/// Every rule's name, in RuleKind order.
inline std::vector<const char*> rule_names() {
  std::vector<const char*> names;
  for (const RuleInfo& r : kRuleTable) names.push_back(r.name);
  return names;
}

namespace rule_registry_detail {
template <class F, class Entry, class... Rest>
decltype(auto) visit_entries(RuleKind kind, F&& f) {
  if constexpr (sizeof...(Rest) == 0) {
    check(kind == Entry::kind, "rule_registry: a RuleKind without a registry entry (rule_registry.hpp)");
    return std::forward<F>(f)(RuleTag<Entry>{});
  } else {
    if (kind == Entry::kind) return std::forward<F>(f)(RuleTag<Entry>{});
    return visit_entries<F, Rest...>(kind, std::forward<F>(f));
  }
}
template <class F, class... Entries>
decltype(auto) visit(RuleKind kind, F&& f, RuleEntries<Entries...>) {
  return visit_entries<F, Entries...>(kind, std::forward<F>(f));
}
}  // namespace rule_registry_detail

/// Calls f(RuleTag<Entry>{}) with the registry line of `kind` and returns what f returns
/// (f must return one type for every rule): a dispatch over Rules, no switch to extend.
template <class F>
decltype(auto) visit_rule(RuleKind kind, F&& f) {
  return rule_registry_detail::visit(kind, std::forward<F>(f), Rules{});
}

}  // namespace hazmap
