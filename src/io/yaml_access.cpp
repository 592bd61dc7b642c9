#include "yaml_access.hpp"

#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <set>
#include <string>

#include "hazmap/core/error.hpp"

namespace hazmap {

std::string yaml_location(const YAML::Node& node, const std::string& source) {
  const YAML::Mark mark = node.Mark();
  if (mark.line >= 0 && !mark.is_null()) return source + ":" + std::to_string(mark.line + 1) + ": ";
  return source + ": ";
}

namespace {

void check_duplicates(const YAML::Node& node, const std::string& path, const std::string& source) {
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      check_duplicates(node[i], path + "." + std::to_string(i), source);
    return;
  }
  if (!node.IsMap()) return;
  std::set<std::string> seen;
  for (const auto& kv : node) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string("<complex key>");
    const std::string key_path = path.empty() ? key : path + "." + key;
    if (!seen.insert(key).second)
      throw Error(yaml_location(kv.first, source) + "duplicate key '" + key_path + "'");
    check_duplicates(kv.second, key_path, source);
  }
}

}  // namespace

void reject_duplicate_keys(const YAML::Node& root, const std::string& source) {
  check_duplicates(root, "", source);
}

YamlMap::YamlMap(const YAML::Node& node, std::string path, std::string source,
                 const YamlOverrides* overrides)
    : node_(node), path_(std::move(path)), source_(std::move(source)), overrides_(overrides) {
  if (node_.IsDefined() && !node_.IsNull() && !node_.IsMap())
    throw Error(yaml_location(node_, source_) + "key '" + (path_.empty() ? "<top>" : path_) +
                "': expected a map of keys");
}

std::string YamlMap::location(const std::string& key, const YAML::Node& node) const {
  if (overrides_ != nullptr) {
    // A key that --set created (a misspelt section): the assignment that made it.
    const std::string below = key_path(key) + ".";
    for (const auto& [set_key, assignment] : *overrides_)
      if (set_key.compare(0, below.size(), below) == 0) return "--set " + assignment + ": ";
    // The key itself, or a map above it, set on the command line (the longest match).
    std::string path = key_path(key);
    while (true) {
      const auto it = overrides_->find(path);
      if (it != overrides_->end()) return "--set " + it->second + ": ";
      const auto dot = path.rfind('.');
      if (dot == std::string::npos) break;
      path.resize(dot);
    }
  }
  return yaml_location(node, source_);
}

std::string YamlMap::key_path(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

void YamlMap::fail(const std::string& key, const std::string& what) const {
  YAML::Node at = node_;
  if (node_.IsMap() && node_[key]) at = node_[key];
  throw Error(location(key, at) + "key '" + key_path(key) + "': " + what);
}

bool YamlMap::has(const std::string& key) const {
  return node_.IsMap() && node_[key] && !node_[key].IsNull();
}

YAML::Node YamlMap::scalar(const std::string& key) {
  read_.insert(key);
  YAML::Node n = node_[key];
  if (!n.IsScalar()) fail(key, "expected a single value");
  return n;
}

void YamlMap::get(const std::string& key, int& out) {
  if (!has(key)) return;
  const std::string text = scalar(key).Scalar();
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < -2147483647L || v > 2147483647L)
    fail(key, "expected an integer, found '" + text + "'");
  out = static_cast<int>(v);
}

void YamlMap::get(const std::string& key, double& out) {
  if (!has(key)) return;
  const std::string text = scalar(key).Scalar();
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v))
    fail(key, "expected a number, found '" + text + "'");
  out = v;
}

void YamlMap::get(const std::string& key, bool& out) {
  if (!has(key)) return;
  const std::string text = scalar(key).Scalar();
  if (text == "true" || text == "True" || text == "yes" || text == "on") out = true;
  else if (text == "false" || text == "False" || text == "no" || text == "off") out = false;
  else fail(key, "expected true or false, found '" + text + "'");
}

void YamlMap::get(const std::string& key, std::string& out) {
  if (!has(key)) return;
  out = scalar(key).Scalar();
}

void YamlMap::get(const std::string& key, std::vector<double>& out, size_t expected_size) {
  if (!has(key)) return;
  read_.insert(key);
  const YAML::Node n = node_[key];
  if (!n.IsSequence() || n.size() != expected_size)
    fail(key, "expected a list of " + std::to_string(expected_size) + " numbers");
  out.clear();
  for (const auto& item : n) {
    const std::string text = item.IsScalar() ? item.Scalar() : "";
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v))
      fail(key, "expected numbers, found '" + text + "'");
    out.push_back(v);
  }
}

YamlMap YamlMap::child(const std::string& key) {
  read_.insert(key);
  if (!has(key)) return YamlMap(YAML::Node(), key_path(key), source_, overrides_);
  if (!node_[key].IsMap()) fail(key, "expected a map of keys");
  return YamlMap(node_[key], key_path(key), source_, overrides_);
}

YAML::Node YamlMap::sequence(const std::string& key) {
  read_.insert(key);
  if (!has(key)) return YAML::Node(YAML::NodeType::Sequence);
  if (!node_[key].IsSequence()) fail(key, "expected a list");
  return node_[key];
}

YAML::Node YamlMap::raw(const std::string& key) {
  read_.insert(key);
  return node_[key];
}

void YamlMap::finish(const std::vector<std::string>& known) const {
  if (!node_.IsMap()) return;
  for (const auto& item : node_) {
    const std::string key = item.first.Scalar();
    if (read_.count(key)) continue;
    const std::string near = nearest_key(key, known);
    throw Error(location(key, item.first) + "unknown key '" + key_path(key) + "'" +
                (near.empty() ? std::string() : "; did you mean '" + key_path(near) + "'?"));
  }
}

std::string nearest_key(const std::string& key, const std::vector<std::string>& known) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, key.size() / 3) + 1;
  for (const std::string& k : known) {
    // Levenshtein distance, one row at a time.
    std::vector<std::size_t> row(k.size() + 1);
    for (std::size_t j = 0; j <= k.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= key.size(); ++i) {
      std::size_t diagonal = row[0];
      row[0] = i;
      for (std::size_t j = 1; j <= k.size(); ++j) {
        const std::size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (key[i - 1] == k[j - 1] ? 0 : 1)});
        diagonal = up;
      }
    }
    if (row[k.size()] < best_distance) best_distance = row[k.size()], best = k;
  }
  return best;
}

namespace {

void set_path(YAML::Node node, const std::vector<std::string>& parts, size_t i,
              const YAML::Node& value, const std::string& assignment) {
  const std::string& part = parts[i];
  const bool last = i + 1 == parts.size();
  std::string prefix;
  for (size_t k = 0; k <= i; ++k) prefix += (k ? "." : "") + parts[k];
  if (node.IsSequence()) {
    char* end = nullptr;
    const long index = std::strtol(part.c_str(), &end, 10);
    if (part.empty() || *end != '\0' || index < 0 || static_cast<size_t>(index) >= node.size())
      throw Error("--set " + assignment + ": '" + prefix + "' is not an element of a list of " +
                  std::to_string(node.size()) +
                  (node.size() == 0 ? std::string()
                                    : " (indices 0 to " + std::to_string(node.size() - 1) + ")"));
    if (last) {
      node[static_cast<size_t>(index)] = value;
      return;
    }
    set_path(node[static_cast<size_t>(index)], parts, i + 1, value, assignment);
    return;
  }
  if (node.IsDefined() && !node.IsNull() && !node.IsMap())
    throw Error("--set " + assignment + ": '" + prefix + "' is inside a value, not a map");
  if (last) {
    node[part] = value;
    return;
  }
  if (!node[part] || node[part].IsNull()) node[part] = YAML::Node(YAML::NodeType::Map);
  set_path(node[part], parts, i + 1, value, assignment);
}

}  // namespace

std::vector<std::string> dotted_parts(const std::string& key) {
  std::vector<std::string> parts;
  std::string::size_type begin = 0;
  for (std::string::size_type dot; (dot = key.find('.', begin)) != std::string::npos; begin = dot + 1)
    parts.push_back(key.substr(begin, dot - begin));
  parts.push_back(key.substr(begin));
  return parts;
}

void apply_yaml_override(YAML::Node& root, const std::string& assignment,
                         YamlOverrides* applied) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw Error("--set " + assignment + ": expected KEY=VALUE");
  // map.layers[0].size is map.layers.0.size: the README's and most tools' spelling.
  std::string key;
  for (const char ch : assignment.substr(0, eq)) {
    if (ch == '[') key += '.';
    else if (ch != ']') key += ch;
  }
  const std::string text = assignment.substr(eq + 1);
  const std::vector<std::string> parts = dotted_parts(key);
  for (const auto& p : parts)
    if (p.empty()) throw Error("--set " + assignment + ": empty key component");
  YAML::Node value;
  try {
    value = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw Error("--set " + assignment + ": value is not valid YAML: " + e.msg);
  }
  if (!root.IsDefined() || root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  set_path(root, parts, 0, value, assignment);
  if (applied != nullptr) (*applied)[key] = assignment;
}

}  // namespace hazmap
