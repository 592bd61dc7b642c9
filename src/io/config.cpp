#include "hazmap/io/config.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <type_traits>
#include <variant>
#include <vector>

#include "hazmap/core/error.hpp"
#include "hazmap/io/config_schema.hpp"
#include "hazmap/rules/rule_registry.hpp"
#include "yaml_access.hpp"

namespace hazmap {

namespace {

void one_of(const YamlMap& m, const std::string& key, const std::string& value,
            const std::vector<std::string>& allowed) {
  std::string list;
  for (const std::string& a : allowed) {
    if (value == a) return;
    list += (list.empty() ? "" : " | ") + a;
  }
  m.fail(key, "'" + value + "' is not one of " + list);
}

/// Keys [begin, end) of `keys` share their first `depth` parts; the run of keys from
/// `begin` that also shares part `depth` and goes deeper (a nested map).
template <class Key>
std::size_t section_end(const std::vector<Key>& keys, std::size_t begin, std::size_t end,
                        std::size_t depth) {
  const std::vector<std::string> first = dotted_parts(keys[begin].name);
  std::size_t j = begin + 1;
  for (; j < end; ++j) {
    const std::vector<std::string> parts = dotted_parts(keys[j].name);
    if (parts.size() <= depth + 1 || parts[depth] != first[depth]) break;
  }
  return j;
}

/// Walks a key table as the YAML nests it: `leaf(map, part, key)` for each key of the map
/// at `depth`, a child map per section; each map then rejects the keys nobody read.
template <class Key, class Leaf>
void parse_map(YamlMap& m, const std::vector<Key>& keys, std::size_t begin, std::size_t end,
               std::size_t depth, const Leaf& leaf) {
  for (std::size_t i = begin; i < end;) {
    const std::vector<std::string> parts = dotted_parts(keys[i].name);
    if (parts.size() == depth + 1) {
      leaf(m, parts[depth], keys[i]);
      ++i;
      continue;
    }
    const std::size_t j = section_end(keys, i, end, depth);
    YamlMap child = m.child(parts[depth]);
    parse_map(child, keys, i, j, depth + 1, leaf);
    i = j;
  }
  // The names this map may hold, for "did you mean" on an unknown one.
  std::vector<std::string> known;
  for (std::size_t i = begin; i < end; ++i) {
    const std::string part = dotted_parts(keys[i].name)[depth];
    if (known.empty() || known.back() != part) known.push_back(part);
  }
  m.finish(known);
}

template <class T>
struct IsOptional : std::false_type {};
template <class T>
struct IsOptional<std::optional<T>> : std::true_type {};

/// Reads one key (`name` within map `m`) into its member of `owner`.
template <class Owner>
void read_key(YamlMap& m, const std::string& name, const ConfigKey<Owner>& key, Owner& owner) {
  if (key.required && !m.has(name)) m.fail(name, "missing required key");
  std::visit(
      [&](auto field) {
        using F = decltype(field);
        if constexpr (std::is_same_v<F, std::monostate>) {
        } else if constexpr (std::is_enum_v<std::remove_reference_t<decltype(field(owner))>>) {
          // Enums (RuleKind's names from the rule registry) are parsed here, once.
          using E = std::remove_reference_t<decltype(field(owner))>;
          if (!m.has(name)) return;
          std::string text;
          m.get(name, text);
          one_of(m, name, text, key_choices(key));
          field(owner) = *enum_value<E>(text);
        } else if constexpr (std::is_same_v<F, std::array<int, 4>& (*)(Owner&)>) {
          if (!m.has(name)) return;
          std::vector<double> values;
          m.get(name, values, 4);
          for (size_t i = 0; i < 4; ++i) {
            if (values[i] != std::floor(values[i]) || std::abs(values[i]) > 1e6)
              m.fail(name, "expected 4 integers [x, y, width, height]");
            field(owner)[i] = static_cast<int>(values[i]);
          }
        } else if constexpr (IsOptional<std::remove_reference_t<decltype(field(owner))>>::value) {
          // A number, or the word `auto` (empty). An old config's way to say `auto` (0, or
          // a negative number) fails here, where the error can name the line.
          if (!m.has(name)) return;
          std::string text;
          m.get(name, text);
          if (text == "auto") {
            field(owner).reset();
            return;
          }
          typename std::remove_reference_t<decltype(field(owner))>::value_type value{};
          m.get(name, value);
          for (const ValueCheck& check : key.checks)
            if (check.old_auto && !check.passes(value)) m.fail(name, check.message());
          field(owner) = value;
        } else {
          m.get(name, field(owner));
        }
      },
      key.field);
}

/// map.layers: each element read with the layer keys (the list replaces the default).
void parse_layers(YamlMap& m, MapConfig& map) {
  if (!m.has("layers")) return;
  const YAML::Node layers = m.sequence("layers");
  map.layers.clear();
  for (size_t i = 0; i < layers.size(); ++i) {
    YamlMap l(layers[i], m.key_path("layers") + "." + std::to_string(i), m.source(),
              m.overrides());
    LayerConfig layer;
    parse_map(l, layer_keys(), 0, layer_keys().size(), 0,
              [&](YamlMap& at, const std::string& name, const LayerKey& key) {
                read_key(at, name, key, layer);
              });
    map.layers.push_back(layer);
  }
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
  YamlOverrides set_keys;
  for (const auto& assignment : overrides) apply_yaml_override(root, assignment, &set_keys);

  Config config;
  YamlMap top(root, "", source, &set_keys);
  parse_map(top, config_keys(), 0, config_keys().size(), 0,
            [&](YamlMap& m, const std::string& name, const TopKey& key) {
              if (key.name == "map.layers") parse_layers(m, config.map);
              else read_key(m, name, key, config);
            });
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

namespace {

/// Runs a key's value checks on its member of `owner`; `name` is the full dotted key.
template <class Owner>
void check_key(const std::string& name, const ConfigKey<Owner>& key, Owner& owner) {
  const auto check_number = [&](double value) {
    for (const ValueCheck& check : key.checks)
      if (!check.passes(value)) invalid(name, check.message());
  };
  std::visit(
      [&](auto field) {
        using F = decltype(field);
        if constexpr (std::is_same_v<F, int& (*)(Owner&)> || std::is_same_v<F, double& (*)(Owner&)>)
          check_number(static_cast<double>(field(owner)));
        else if constexpr (std::is_same_v<F, std::array<int, 4>& (*)(Owner&)>)
          for (const int v : field(owner)) check_number(v);
        else if constexpr (std::is_same_v<F, std::optional<double>& (*)(Owner&)> ||
                           std::is_same_v<F, std::optional<int>& (*)(Owner&)>)
          if (field(owner)) check_number(static_cast<double>(*field(owner)));
      },
      key.field);
}

/// The rules that involve more than one key (or one key and a layer's other keys).
void check_cross_key_rules(const Config& c) {
  const StereoConfig& s = c.stereo;
  if (s.sgbm_p2 && *s.sgbm_p2 <= s.sgbm_p1.value_or(0))
    invalid("stereo.sgbm_p2", "must be greater than sgbm_p1");
  if (!(s.z_max_m > s.z_min_m)) invalid("stereo.z_max", "must be greater than stereo.z_min");
  if (s.c2f.paths != 4 && s.c2f.paths != 8) invalid("stereo.c2f.paths", "must be 4 or 8");
  // Without pointing error the covariance is singular: every det weight would be infinite.
  if (c.rules.ccm.weighting == CcmWeighting::det && !(c.sensor.pointing_error_px > 0))
    invalid("rules.ccm.weighting", "'det' needs sensor.pointing_error_px > 0 (singular covariance)");

  for (size_t i = 0; i < c.map.layers.size(); ++i) {
    const LayerConfig& l = c.map.layers[i];
    const std::string k = "map.layers." + std::to_string(i);
    if (l.hazard.kernel >= l.size)
      invalid(k + ".hazard.kernel", "must be odd, >= 1 and smaller than the layer size");
    if (i > 0) {
      const double prev = c.map.layers[i - 1].resolution_m;
      const double ratio = l.resolution_m / prev;
      if (ratio < 1.0 - 1e-9 || std::abs(ratio - std::round(ratio)) > 1e-6)
        invalid(k + ".resolution", "must be an integer multiple of the previous layer's (" +
                                       std::to_string(prev) + ")");
    }
  }
  if (c.map.insertion == Insertion::finest_then_pool) {
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
}

}  // namespace

void validate(const Config& config) {
  // The checks only read; the key table's accessors take a mutable owner.
  Config& c = const_cast<Config&>(config);
  for (const TopKey& key : config_keys()) {
    if (key.name != "map.layers") {
      check_key(key.name, key, c);
      continue;
    }
    if (c.map.layers.empty()) invalid("map.layers", "at least one layer is required");
    for (size_t i = 0; i < c.map.layers.size(); ++i)
      for (const LayerKey& layer_key : layer_keys())
        check_key("map.layers." + std::to_string(i) + "." + layer_key.name, layer_key, c.map.layers[i]);
  }
  check_cross_key_rules(c);
}

namespace {

/// The dump's layout, as it has always been: these maps (every rule's settings, and each
/// layer) on one line.
bool written_in_flow(const std::string& section) {
  if (section.rfind("rules.", 0) == 0) return true;
  for (const char* flow : {"hazard", "pose_uncertainty", "output"})
    if (section == flow) return true;
  return false;
}

template <class Owner>
void emit_value(YAML::Emitter& out, const ConfigKey<Owner>& key, Owner& owner) {
  std::visit(
      [&](auto field) {
        using F = decltype(field);
        if constexpr (std::is_same_v<F, std::monostate>) {
        } else if constexpr (std::is_enum_v<std::remove_reference_t<decltype(field(owner))>>) {
          out << enum_name(field(owner));
        } else if constexpr (std::is_same_v<F, std::array<int, 4>& (*)(Owner&)>) {
          out << YAML::Flow << YAML::BeginSeq;
          for (const int v : field(owner)) out << v;
          out << YAML::EndSeq;
        } else if constexpr (IsOptional<std::remove_reference_t<decltype(field(owner))>>::value) {
          if (field(owner)) out << *field(owner);
          else out << "auto";
        } else {
          out << field(owner);
        }
      },
      key.field);
}

/// Writes keys [begin, end) of a table, nested as parse_map reads them; `value` writes
/// one key's value.
template <class Key, class Value>
void emit_map(YAML::Emitter& out, const std::vector<Key>& keys, std::size_t begin, std::size_t end,
              std::size_t depth, const Value& value) {
  for (std::size_t i = begin; i < end;) {
    const std::vector<std::string> parts = dotted_parts(keys[i].name);
    out << YAML::Key << parts[depth] << YAML::Value;
    if (parts.size() == depth + 1) {
      value(keys[i]);
      ++i;
      continue;
    }
    std::string section = parts[0];
    for (std::size_t p = 1; p <= depth; ++p) section += "." + parts[p];
    if (written_in_flow(section)) out << YAML::Flow;
    out << YAML::BeginMap;
    const std::size_t j = section_end(keys, i, end, depth);
    emit_map(out, keys, i, j, depth + 1, value);
    out << YAML::EndMap;
    i = j;
  }
}

}  // namespace

std::string to_yaml(const Config& config) {
  // Only reads; the key table's accessors take a mutable owner.
  Config& c = const_cast<Config&>(config);
  YAML::Emitter out;
  out << YAML::BeginMap;
  emit_map(out, config_keys(), 0, config_keys().size(), 0, [&](const TopKey& key) {
    if (key.name != "map.layers") return emit_value(out, key, c);
    out << YAML::BeginSeq;
    for (LayerConfig& layer : c.map.layers) {
      out << YAML::Flow << YAML::BeginMap;
      emit_map(out, layer_keys(), 0, layer_keys().size(), 0,
               [&](const LayerKey& k) { emit_value(out, k, layer); });
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  });
  out << YAML::EndMap;
  return out.c_str();
}

}  // namespace hazmap
