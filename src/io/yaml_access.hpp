#pragma once
// Strict, typed access to a YAML mapping (private to the library). Every read names
// the dotted key and the source line in its error; finish() rejects keys nobody read.

#include <map>
#include <set>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace hazmap {

/// Dotted key -> the `--set KEY=VALUE` that gave it its value. A value set on the command
/// line has no line in the file, so its errors name the assignment instead.
using YamlOverrides = std::map<std::string, std::string>;

class YamlMap {
 public:
  /// `node` must be a map (or null/undefined, treated as empty). `path` is the dotted
  /// prefix for messages ("" at the top), `source` the file name, `overrides` (kept by
  /// reference, may be null) the keys set on the command line.
  YamlMap(const YAML::Node& node, std::string path, std::string source,
          const YamlOverrides* overrides = nullptr);

  bool has(const std::string& key) const;

  /// Reads key into `out` when present (keeps the default otherwise).
  void get(const std::string& key, int& out);
  void get(const std::string& key, double& out);
  void get(const std::string& key, bool& out);
  void get(const std::string& key, std::string& out);
  void get(const std::string& key, std::vector<double>& out, size_t expected_size);

  /// Like get, but the key must be present.
  template <class T>
  void require(const std::string& key, T& out) {
    if (!has(key)) fail(key, "missing required key");
    get(key, out);
  }

  /// A nested map (empty when absent). Throws if the key holds no map.
  YamlMap child(const std::string& key);
  /// A nested sequence node (marks the key as read). Throws if not a sequence.
  YAML::Node sequence(const std::string& key);
  /// The raw node (marks the key as read).
  YAML::Node raw(const std::string& key);

  /// Throws Error naming the first key that was never read; with `known` (the keys this
  /// map may hold), the nearest of them as "did you mean".
  void finish(const std::vector<std::string>& known = {}) const;

  std::string key_path(const std::string& key) const;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  const std::string& source() const { return source_; }
  const YamlOverrides* overrides() const { return overrides_; }

 private:
  YAML::Node scalar(const std::string& key);
  /// "source:line: " of `node`, or "--set KEY=VALUE: " if `key` (or a map holding it) was
  /// set on the command line.
  std::string location(const std::string& key, const YAML::Node& node) const;

  YAML::Node node_;
  std::string path_;
  std::string source_;
  const YamlOverrides* overrides_ = nullptr;
  std::set<std::string> read_;
};

/// "source:line: " for a node with a mark, "source: " otherwise.
std::string yaml_location(const YAML::Node& node, const std::string& source);

/// Throws Error naming the file, line and key path of the first key that appears twice in
/// one map anywhere under `root` (YAML parsers keep one of them silently).
void reject_duplicate_keys(const YAML::Node& root, const std::string& source);

/// The parts of a dotted key: "rules.ccm.weighting" -> rules, ccm, weighting (empty parts
/// kept: "a..b" -> a, "", b).
std::vector<std::string> dotted_parts(const std::string& key);

/// The known key nearest to `key` by edit distance, if near enough to be a misspelling
/// (at most a third of its letters, at least 2); "" otherwise.
std::string nearest_key(const std::string& key, const std::vector<std::string>& known);

/// Applies "dotted.key=value" to a YAML tree; sequence elements are addressed by index,
/// as `map.layers.0.size` or `map.layers[0].size`.
/// Records the key in `applied` (if given) for error messages.
void apply_yaml_override(YAML::Node& root, const std::string& assignment,
                         YamlOverrides* applied = nullptr);

}  // namespace hazmap
