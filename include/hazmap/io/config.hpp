#pragma once
// The run configuration (SPEC 13): nested structs with defaults, loaded from YAML plus
// `--set key=value` overrides, validated in one place. Unknown keys, wrong types and
// impossible values are errors that name the key. Each stage declares its own part
// (core/core_config.hpp: map, rules, hazard; stereo/stereo_config.hpp: stereo, sensor);
// this header adds the pipeline's and the output's parts and aggregates them.

#include <filesystem>
#include <string>
#include <vector>

#include "hazmap/core/core_config.hpp"
#include "hazmap/core/enum_names.hpp"
#include "hazmap/stereo/stereo_config.hpp"

namespace hazmap {

/// output.format: the grid files written.
enum class GridFormat { jdem, geotiff, both };
template <>
struct EnumNames<GridFormat> {
  static constexpr const char* names[] = {"jdem", "geotiff", "both"};
};

struct PoseUncertaintyConfig {
  bool enabled = false;
};

/// Upper bound of output.queue_frames: each queued frame holds a copy of every grid.
constexpr int kMaxOutputQueueFrames = 64;

struct OutputConfig {
  int every_n = 1;        ///< write every n-th frame (and always the last)
  bool png = true;
  bool jdem = true;       ///< write the grid files (in `format`)
  /// Grid file format: jdem (text, SPEC 9), geotiff (float32, DEFLATE, GDAL) or
  /// both (e.g. GeoTIFF for GIS tools and JDEM for `hazmap evaluate`).
  GridFormat format = GridFormat::jdem;
  /// Finished frames waiting for the writer thread; the frame loop waits only when this
  /// many are queued. 0: write on the frame loop's thread (synchronous).
  int queue_frames = 2;
  int png_min_size = 512; ///< PNGs are scaled up by whole pixels per cell to at least this
  /// Height PNGs colour the known cells' percentiles [p, 100 - p] (one wild cell must not
  /// squash the rest into one colour); the full range is still written under the bar.
  /// 0: the full range.
  double png_height_clip_pct = 2.0;
  bool mosaic = false;    ///< also OUT/mosaic/<frame>.png: every layer side by side
  /// Also L<i>_unknown_reason grids: why each unknown cell stayed unknown (UnknownReason
  /// bits), from a diagnostic pass per written frame, for `hazmap evaluate`.
  bool unknown_reasons = false;
};

/// The map core's part (map, rules, hazard: core/core_config.hpp) and the rest.
struct Config : CoreConfig {
  StereoConfig stereo;
  SensorConfig sensor;
  PoseUncertaintyConfig pose_uncertainty;
  OutputConfig output;
};

/// Parses YAML text (`source` names it in messages) after applying overrides of the
/// form "dotted.key=value" (`map.layers.0.size=64`); validates the result.
Config parse_config(const std::string& yaml_text, const std::string& source,
                    const std::vector<std::string>& overrides = {});

/// Reads and parses a YAML file; see parse_config.
Config load_config(const std::filesystem::path& path,
                   const std::vector<std::string>& overrides = {});

/// Checks values that YAML typing cannot (odd sizes, resolutions that are not integer
/// multiples, negative noise, ...). Throws Error naming the key.
void validate(const Config& config);

/// The configuration as YAML, with every key and the value actually used.
std::string to_yaml(const Config& config);

}  // namespace hazmap
