#pragma once
// The stereo stage's configuration (SPEC 13, keys stereo.* and sensor.*): the matcher,
// its search and filters, and the sensor noise model. Declared here so the stereo code
// needs nothing above it; io/config.hpp aggregates it into Config and parses it.

#include <array>
#include <optional>

#include "hazmap/core/enum_names.hpp"
#include "hazmap/stereo/sensor_model.hpp"

namespace hazmap {

/// stereo.matcher: cv::StereoBM or cv::StereoSGBM.
enum class StereoMatcher { bm, sgbm, c2f };
template <>
struct EnumNames<StereoMatcher> {
  static constexpr const char* names[] = {"bm", "sgbm", "c2f"};
};

/// stereo.sgbm_mode: cv::StereoSGBM's MODE_SGBM, MODE_HH, MODE_SGBM_3WAY, MODE_HH4.
enum class SgbmMode { sgbm, hh, sgbm_3way, hh4 };
template <>
struct EnumNames<SgbmMode> {
  static constexpr const char* names[] = {"sgbm", "hh", "sgbm_3way", "hh4"};
};

/// stereo.pre_filter_type: StereoBM's PREFILTER_NORMALIZED_RESPONSE or PREFILTER_XSOBEL.
enum class PreFilterType { normalized_response, xsobel };
template <>
struct EnumNames<PreFilterType> {
  static constexpr const char* names[] = {"normalized_response", "xsobel"};
};

/// stereo.search (SPEC 3.4): one disparity range for the image, or per-strip ground bands.
enum class DisparitySearch { full, ground_band };
template <>
struct EnumNames<DisparitySearch> {
  static constexpr const char* names[] = {"full", "ground_band"};
};

/// sensor.model (SPEC 4): the thesis' axis-aligned errors or first-order ray propagation.
template <>
struct EnumNames<SensorModel> {
  static constexpr const char* names[] = {"axis", "ray"};
};

/// Largest stereo.stride validate() accepts (pixels).
constexpr int kMaxStride = 4096;

/// `stereo.matcher: c2f` (c2f_matcher.hpp): census cost, semi-global aggregation, coarse to
/// fine over an image pyramid.
struct C2fConfig {
  int levels = 3;          ///< pyramid levels; the full-range search runs at 1/2^(levels-1)
  int radius = 2;          ///< finer levels search +- radius px around the upsampled seed
  int census_width = 9;    ///< census window (odd; width x height - 1 <= 64 bits)
  int census_height = 7;
  int p1 = 32;             ///< SGM penalty for a 1 px disparity step (census bits)
  int p2 = 200;            ///< SGM penalty for a larger step (census bits), >= p1
  /// Edge-aware P2 [DN]: a path step between pixels whose left-image intensities differ
  /// by D pays max(p1, p2 e / (e + D)) for a jump (an object's outline may jump); 0: p2.
  int p2_edge = 0;
  int paths = 4;           ///< SGM paths: 4 (rows and columns) or 8 (and diagonals)
  int lr_max_diff = 1;     ///< left-right check at every level [px]; -1 off
  int uniqueness = 5;      ///< coarse level: best cost < (100 - this)% of the second best
  bool fill_unseeded = false;  ///< seed pixels without a coarse disparity from their row
  /// Finest level: sub-pixel from two lines through the raw census costs summed over a
  /// (2 r + 1)^2 box; 0: a parabola through the pixel's aggregated sums (locks onto whole
  /// pixels, but the 4 cm layer's hole-free test proves more with it: docs/stereo.md).
  int subpixel_radius = 0;
  /// Finest level: a disparity whose own census distance at the winner (before
  /// aggregation) exceeds this many bits is dropped: the paths carried it there, the
  /// pixel's window did not match; 0 off.
  int max_match_cost = 0;
  /// Horizontal outlines (a crest, a rock's top against the ground behind it): where a
  /// column's disparity jumps by more than this [px] between valid pixels at most
  /// 2 outline_rows + 2 rows apart, `outline_rows` pixels on the jump's far side (the
  /// smaller disparity) are dropped, from the jump outwards. A census window straddling
  /// the outline gives the near surface's first rows the far ground's disparity: points in
  /// the air over the hidden ground behind it. 0 off.
  double outline_jump_px = 0;
  int outline_rows = 3;  ///< rows dropped at an outline (about the census half-height)
};

struct StereoConfig {
  StereoMatcher matcher = StereoMatcher::bm;
  int num_disparities = 128;        ///< multiple of 16
  int block_size = 11;              ///< odd
  int min_disparity = 0;
  int uniqueness_ratio = 10;
  int texture_threshold = 10;       ///< StereoBM only
  /// Any matcher: drop a disparity whose window's contrast above the image's noise is
  /// below this times the noise (texture_gate.hpp); 0 off.
  double min_texture_snr = 0.0;
  /// bm / sgbm: also match the left image's first min_disparity + num_disparities
  /// columns, which OpenCV leaves blank, by padding both images on the left.
  bool match_left_border = true;
  int pre_filter_cap = 31;
  int speckle_window = 100;         ///< 0 disables the speckle filter
  int speckle_range = 2;            ///< pixels (scaled x16 for StereoBM, SPEC 3)
  int disp12_max_diff = -1;         ///< left-right consistency in px; -1 disables
  std::optional<int> sgbm_p1;       ///< auto: 8 * block_size^2
  std::optional<int> sgbm_p2;       ///< auto: 32 * block_size^2
  SgbmMode sgbm_mode = SgbmMode::hh;
  PreFilterType pre_filter_type = PreFilterType::normalized_response;  ///< StereoBM only
  int pre_filter_size = 9;          ///< StereoBM normalized_response window: odd, 5..255
  /// Significant bits of 16-bit input (10, 12, ...: the pair is scaled by 2^(8 - bits) to
  /// 8 bit); auto detects them per pair from the brighter image. Ignored for 8-bit input.
  std::optional<int> input_bits;
  double rectify_alpha = 0.0;
  int stride = 1;                   ///< use every stride-th pixel in u and v (<= kMaxStride)
  /// Region of interest in the rectified left image, pixels: x, y, width, height.
  /// width or height 0: the whole image. Pixels outside produce no points.
  std::array<int, 4> roi_px{0, 0, 0, 0};
  double z_min_m = 0.05;
  double z_max_m = 10.0;
  /// SPEC 3.3: points farther than this below the body's wheel plane (z_B = 0) are
  /// mismatches and are dropped (counted); <= 0 disables the check.
  double max_below_ground_m = 0.5;
  /// Ours, with the check above: a point more than below_ground_tolerance below the wheel
  /// plane seen along a ray that descends steeper than max_depression_slope_deg could only
  /// be seen down a wall at least that steep right under the ray: a mismatch (ground or a
  /// rock nearer than the search reaches). Dropped and counted with the above; the
  /// slope >= 90 disables it, as does max_below_ground <= 0.
  double below_ground_tolerance_m = 0.05;
  double max_depression_slope_deg = 45.0;
  /// Ours, also SPEC 3.3's impossible points: a pixel whose ray, on its way to the point,
  /// passes more than occlusion_margin + 3 sigma below the terrain the map has already
  /// published (the previous frame's heights and variances) sees that terrain, not the
  /// point: a mismatch, dropped and counted. Typically a surface nearer than the disparity
  /// search reaches, aliased to a smaller disparity, which puts the point far along its
  /// ray, inside the rock it looked at. Rays are followed out to occlusion_reach times the
  /// nearest depth the search reaches in the pixel's row, f B / (highest disparity
  /// searched), which bounds the cost; 0 disables the check. Needs a map: `hazmap stereo`
  /// and `hazmap check` run without it.
  double occlusion_reach = 2.0;
  double occlusion_margin_m = 0.01;
  /// In the near field a ray must also stay above terrain not yet seen next to seen
  /// terrain: a cell nobody knows counts as high as the highest known cell within this
  /// distance [m], rounded up to whole cells of the finest layer (0: unseen cells block
  /// nothing). Default: the smallest hazard's width (SPEC 11), the least an obstacle seen
  /// up to its edge extends beyond it. The hidden far side of a rock the cameras pass
  /// over is unseen, and it is nearer than the search reaches.
  double occlusion_fill_m = 0.03;
  /// Unsupported disparities (support_check.hpp): a pixel much nearer than most of what
  /// lies within support_rows below it in its column floats and is dropped (counted);
  /// 0 disables the check. Farther: disparity < d (1 - support_tolerance) - margin.
  int support_rows = 0;
  double support_tolerance = 0.25;
  double support_margin_px = 1.0;
  /// SPEC 3.4: `full` searches [min_disparity, min_disparity + num_disparities) in every
  /// row; `ground_band` searches per horizontal strip only the disparities terrain can
  /// produce there (ground_band.hpp), whatever num_disparities says.
  DisparitySearch search = DisparitySearch::full;
  double band_max_slope_deg = 30.0;  ///< ground_band: wheel plane tilted up to this [deg]
  double band_max_height_m = 0.5;    ///< ground_band: obstacles up to this above it [m]
  double band_max_depth_m = 0.5;     ///< ground_band: depressions down to this below it [m]
  /// stereo.row_offset_px: rows the rectified right image moves down to agree with the
  /// left (y_left - y_right of the rectified pair, stereo/row_offset.hpp), or auto:
  /// measured once from the first frames.
  std::optional<double> row_offset = 0.0;
  C2fConfig c2f;
};

/// Whether the matcher searches the left image's first min_disparity + num_disparities
/// columns: c2f always, bm and sgbm with match_left_border (OpenCV leaves them blank).
inline bool matches_left_columns(const StereoConfig& c) {
  return c.matcher == StereoMatcher::c2f || c.match_left_border;
}

/// The left image's leading columns that never get a disparity: OpenCV's blank band when
/// it is not matched, else 0.
inline int blank_left_columns(const StereoConfig& c) {
  return matches_left_columns(c) ? 0 : c.min_disparity + c.num_disparities;
}

/// How far from the right image's left border a match must fall to be kept: bm and sgbm
/// with match_left_border drop a match within block_size of it (a window to spare,
/// docs/stereo.md); c2f, and OpenCV's blank band, have no such rule (0).
inline int right_border_drop_px(const StereoConfig& c) {
  return c.matcher != StereoMatcher::c2f && c.match_left_border ? c.block_size : 0;
}

struct SensorConfig {
  SensorModel model = SensorModel::axis;
  double pointing_error_px = 0.5;
  double disparity_error_px = 0.25;
};

}  // namespace hazmap
