#pragma once
// One declaration per configuration key (SPEC 13): its dotted name, the Config member it
// binds, unit, help text and checks. Parsing (and with it `--set`), validation, the
// resolved-configuration dump (to_yaml) and the README's reference table all walk these
// tables. A key's default is its struct member's initialiser (read off Config{} /
// LayerConfig{}); the tables never repeat it (a key's default_note only comments on it).
//
// Adding a key: the struct member with its default (core/core_config.hpp,
// stereo/stereo_config.hpp or io/config.hpp) and one line in src/io/config_schema.cpp
// (docs/config.md).

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "hazmap/io/config.hpp"

namespace hazmap {

/// One value check on a numeric key (an int array: on every element; a key that may be
/// `auto`: on its number). The value passes when it equals `except`, or when it lies in
/// the interval (`lo`, `hi`; an end at +-infinity is unbounded, NaN fails every interval),
/// is finite if `finite`, odd if `odd` and a multiple of `multiple_of` if that is not 0.
/// `what` is the error's text ("must be ..."); empty: generated from the interval.
/// An `old_auto` check turns this round: the numbers it describes are how older configs
/// said `auto` (0, or < 0); they fail, and the error says to write `auto`.
struct ValueCheck {
  double lo = -std::numeric_limits<double>::infinity();
  bool lo_open = false;
  double hi = std::numeric_limits<double>::infinity();
  bool hi_open = false;
  bool finite = false;
  bool odd = false;
  int multiple_of = 0;
  bool has_except = false;
  double except = 0;
  bool old_auto = false;
  std::string what;

  bool passes(double value) const;
  /// `what`, or the interval in words: "must be in [0, 1)", "must be >= 0", "must be > 0".
  std::string message() const;
};

/// Where a key's value lives in its owner (Config, or one LayerConfig for map.layers.N.*);
/// std::monostate for the layer list's own entry, whose elements have the layer keys.
/// An enum's names come from its EnumNames (core/enum_names.hpp), RuleKind's from the rule
/// registry; a new enum type needs its alternative here. A std::optional member is a
/// number or `auto` (empty).
template <class Owner>
using KeyField =
    std::variant<std::monostate, int& (*)(Owner&), double& (*)(Owner&), bool& (*)(Owner&),
                 std::array<int, 4>& (*)(Owner&), RuleKind& (*)(Owner&), Insertion& (*)(Owner&),
                 CcmWeighting& (*)(Owner&), RoughnessStatistic& (*)(Owner&), PartialRingProof& (*)(Owner&),
                 StereoMatcher& (*)(Owner&), SgbmMode& (*)(Owner&), PreFilterType& (*)(Owner&),
                 DisparitySearch& (*)(Owner&), SensorModel& (*)(Owner&), GridFormat& (*)(Owner&),
                 std::optional<double>& (*)(Owner&), std::optional<int>& (*)(Owner&)>;

/// One configuration key.
template <class Owner>
struct ConfigKey {
  ConfigKey(std::string name_, KeyField<Owner> field_, std::string unit_, std::string help_,
            std::vector<ValueCheck> checks_ = {}, bool required_ = false,
            std::string default_note_ = "")
      : name(std::move(name_)), field(field_), unit(std::move(unit_)), help(std::move(help_)),
        checks(std::move(checks_)), required(required_), default_note(std::move(default_note_)) {}

  std::string name;                  ///< dotted, relative to Owner: "stereo.z_max", "hazard.kernel"
  KeyField<Owner> field;             ///< the member it binds
  std::string unit;                  ///< "m", "deg", "px", ... ("" for none)
  std::string help;                  ///< the README's text (markdown)
  std::vector<ValueCheck> checks;    ///< value checks, in order (validate())
  bool required = false;             ///< must be present (layer keys)
  std::string default_note;          ///< README: after the default ("shipped configs use ...")
};

using TopKey = ConfigKey<Config>;
using LayerKey = ConfigKey<LayerConfig>;

/// Every key outside the layer list, in the dump's order; "map.layers" is a placeholder
/// entry (no field) where each layer's keys (layer_keys()) go.
const std::vector<TopKey>& config_keys();

/// The keys of one map.layers element, relative to it ("resolution", "hazard.kernel").
const std::vector<LayerKey>& layer_keys();

/// The names an enum key accepts (RuleKind: the rule registry's), empty for other keys.
std::vector<std::string> key_choices(const TopKey& key);
std::vector<std::string> key_choices(const LayerKey& key);

/// The configuration reference table (markdown, one row per key), generated from the
/// tables above; docs/config_reference.md holds it between the markers below.
std::string config_reference_markdown();
inline constexpr const char* kConfigReferenceBegin = "<!-- config-reference:begin -->";
inline constexpr const char* kConfigReferenceEnd = "<!-- config-reference:end -->";

}  // namespace hazmap
