// The configuration's keys, one line each (io/config_schema.hpp): name, member, unit,
// help, checks. Defaults are the struct members' own initialisers.
#include "hazmap/io/config_schema.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <type_traits>
#include <utility>

#include "hazmap/map/grid_math.hpp"
#include "hazmap/rules/rule_registry.hpp"

namespace hazmap {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The member a key binds, as a function pointer (one per key, no captures).
#define CONFIG_FIELD(member) +[](Config& c) -> auto& { return c.member; }
#define LAYER_FIELD(member) +[](LayerConfig& l) -> auto& { return l.member; }

// Checks, by the shape of their interval ("[)": closed below, open above).
ValueCheck in(double lo, double hi, const char* ends, std::string what = "") {
  ValueCheck c;
  c.lo = lo;
  c.hi = hi;
  c.lo_open = ends[0] == '(';
  c.hi_open = ends[1] == ')';
  c.what = std::move(what);
  return c;
}
ValueCheck at_least(double lo, std::string what = "") { return in(lo, kInf, "[]", std::move(what)); }
ValueCheck above(double lo, std::string what = "") { return in(lo, kInf, "(]", std::move(what)); }
ValueCheck odd_in(double lo, double hi, std::string what) {
  ValueCheck c = in(lo, hi, "[]", std::move(what));
  c.odd = true;
  return c;
}
ValueCheck finite(std::string what, double lo = -kInf, double hi = kInf) {
  ValueCheck c = in(lo, hi, "[]", std::move(what));
  c.finite = true;
  return c;
}
ValueCheck finite_above(double lo, std::string what) {
  ValueCheck c = above(lo, std::move(what));
  c.finite = true;
  return c;
}
ValueCheck or_exactly(double except, ValueCheck c) {
  c.has_except = true;
  c.except = except;
  return c;
}
// The numbers an older config wrote for `auto` (`sentinel`: "0", "a negative value"),
// rejected with the advice to write `auto` (`derived`: what `auto` gives).
ValueCheck old_auto(ValueCheck numbers, const std::string& sentinel, const std::string& derived) {
  numbers.old_auto = true;
  numbers.what = sentinel + " no longer means `auto`: write `auto` (" + derived + ")";
  return numbers;
}
ValueCheck old_auto_zero(const std::string& derived) { return old_auto(in(0, 0, "[]"), "0", derived); }
ValueCheck old_auto_negative(const std::string& derived) {
  ValueCheck negative = finite("", -kInf, 0);
  negative.hi_open = true;
  return old_auto(negative, "a negative value", derived);
}
// The same, for keys whose old `auto` was any value <= 0.
ValueCheck old_auto_not_positive(const std::string& derived) {
  return old_auto(finite("", -kInf, 0), "a value <= 0", derived);
}
ValueCheck multiple_of(int n, ValueCheck c) {
  c.multiple_of = n;
  return c;
}

std::string number_text(double v) {
  if (v == std::floor(v) && std::abs(v) < 1e15) return std::to_string(static_cast<long long>(v));
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace

bool ValueCheck::passes(double value) const {
  if (has_except && value == except) return true;
  const bool described = (!finite || std::isfinite(value)) &&
                         (lo_open ? value > lo : value >= lo) &&
                         (hi_open ? value < hi : value <= hi) &&
                         !(odd && std::fmod(value, 2.0) == 0) &&
                         !(multiple_of != 0 && std::fmod(value, multiple_of) != 0);
  return described != old_auto;
}

std::string ValueCheck::message() const {
  if (!what.empty()) return what;
  if (hi == kInf) return std::string("must be ") + (lo_open ? "> " : ">= ") + number_text(lo);
  return std::string("must be in ") + (lo_open ? "(" : "[") + number_text(lo) + ", " +
         number_text(hi) + (hi_open ? ")" : "]");
}

const std::vector<TopKey>& config_keys() {
  static const std::vector<TopKey> keys = {
      // stereo (SPEC 3)
      {"stereo.matcher", CONFIG_FIELD(stereo.matcher), "", "`bm` (cv::StereoBM), `sgbm` (cv::StereoSGBM) or `c2f` (ours: census cost, semi-global aggregation, coarse to fine; `stereo.c2f.*`, [docs/stereo.md](docs/stereo.md)). c2f searches `[min_disparity, min(min_disparity + num_disparities, f B / z_min))`", {}},
      {"stereo.num_disparities", CONFIG_FIELD(stereo.num_disparities), "px",
       "search range, multiple of 16; must cover the nearest ground (d = f B / z) or it is mismatched: level, the 0.4-scale image bottom needs 122 px, pitched down a 15-20 deg slope > 150 px",
       {multiple_of(16, above(0, "must be a positive multiple of 16"))}, false, "shipped 0.4-scale configs 160"},
      {"stereo.block_size", CONFIG_FIELD(stereo.block_size), "px", "odd window size", {odd_in(5, 255, "must be odd and in [5, 255]")}},
      {"stereo.min_disparity", CONFIG_FIELD(stereo.min_disparity), "px", "disparities <= this are invalid", {at_least(0)}},
      {"stereo.uniqueness_ratio", CONFIG_FIELD(stereo.uniqueness_ratio), "%", "margin of the best match", {at_least(0)}},
      {"stereo.texture_threshold", CONFIG_FIELD(stereo.texture_threshold), "", "StereoBM: minimum texture", {at_least(0)}},
      {"stereo.min_texture_snr", CONFIG_FIELD(stereo.min_texture_snr), "",
       "any matcher: a disparity is dropped when its window in the left image (c2f's census window, else the block) has a grey-level contrast above the image's noise below this times the noise (the noise estimated per frame from the left image; [docs/stereo.md](docs/stereo.md)). Without it a semi-global matcher fills smooth low-sun ground with noise matches; 0 off",
       {in(0, 100, "[]")}},
      {"stereo.match_left_border", CONFIG_FIELD(stereo.match_left_border), "",
       "bm / sgbm: OpenCV leaves the left image's first min_disparity + num_disparities columns without a disparity (their full range would reach past the right image's edge); true pads both images on the left so that those columns are searched over what the right image holds, keeping a match only with a window to spare from its edge (c2f always matches them); false: OpenCV's blank band",
       {}},
      {"stereo.pre_filter_cap", CONFIG_FIELD(stereo.pre_filter_cap), "", "OpenCV's pre-filter cap", {in(1, 63, "[]")}},
      {"stereo.speckle_window", CONFIG_FIELD(stereo.speckle_window), "px", "speckle filter's region size; 0 off", {at_least(0)}},
      {"stereo.speckle_range", CONFIG_FIELD(stereo.speckle_range), "px", "speckle filter's disparity range (x16 for StereoBM, SPEC 3)", {at_least(0)}},
      {"stereo.disp12_max_diff", CONFIG_FIELD(stereo.disp12_max_diff), "px",
       "OpenCV's left-right check, -1 off; removes ground seen by the left camera only (behind rocks)", {}, false, "default.yaml: 1"},
      {"stereo.sgbm_p1", CONFIG_FIELD(stereo.sgbm_p1), "", "SGBM penalty P1; `auto`: 8 x block^2",
       {old_auto_zero("8 x block^2"), above(0, "penalties must be > 0 or `auto`")}},
      {"stereo.sgbm_p2", CONFIG_FIELD(stereo.sgbm_p2), "", "SGBM penalty P2, greater than P1; `auto`: 32 x block^2",
       {old_auto_zero("32 x block^2"), above(0, "penalties must be > 0 or `auto`")}},
      {"stereo.sgbm_mode", CONFIG_FIELD(stereo.sgbm_mode), "", "SGBM mode", {}},
      {"stereo.pre_filter_type", CONFIG_FIELD(stereo.pre_filter_type), "", "StereoBM pre-filter", {}},
      {"stereo.pre_filter_size", CONFIG_FIELD(stereo.pre_filter_size), "px", "StereoBM `normalized_response` window (odd)", {odd_in(5, 255, "must be odd and in [5, 255]")}},
      {"stereo.input_bits", CONFIG_FIELD(stereo.input_bits), "bits",
       "significant bits of 16-bit input (`auto`: detect per pair from the brighter image; 10 or 12 for low-bit sensors); ignored for 8-bit input",
       {old_auto_zero("detect"), in(8, 16, "[]", "must be in [8, 16] or `auto` (detect)")}},
      {"stereo.rectify_alpha", CONFIG_FIELD(stereo.rectify_alpha), "", "cv::stereoRectify alpha (-1: OpenCV's default)",
       {or_exactly(-1, in(0, 1, "[]", "must be in [0, 1] (or -1 for OpenCV's default)"))}},
      {"stereo.stride", CONFIG_FIELD(stereo.stride), "px", "use every n-th pixel in u and v",
       // A stride of 4096 keeps one pixel per 4096 x 4096 block: beyond that a stride selects
       // nothing more in any camera image, and near INT_MAX the pixel loop's counters overflowed.
       {in(1, kMaxStride, "[]", "must be in [1, " + std::to_string(kMaxStride) +
                                    "] (a larger stride keeps at most one pixel of a 4096 px image)")}},
      {"stereo.roi", CONFIG_FIELD(stereo.roi_px), "px",
       "`[x, y, w, h]` in the rectified left image that produces points; width or height 0 = whole image",
       {at_least(0, "x, y, width and height must be >= 0")}},
      {"stereo.z_min", CONFIG_FIELD(stereo.z_min_m), "m", "depth gate: nearest point kept", {above(0)}},
      {"stereo.z_max", CONFIG_FIELD(stereo.z_max_m), "m", "depth gate: farthest point kept (greater than `z_min`)"},
      {"stereo.max_below_ground", CONFIG_FIELD(stereo.max_below_ground_m), "m",
       "points farther below the wheel plane (body z = 0) are mismatches: dropped and counted (SPEC 3.3); <= 0 off",
       {finite("must be finite (<= 0 disables the check)")}},
      {"stereo.below_ground_tolerance", CONFIG_FIELD(stereo.below_ground_tolerance_m), "m",
       "a point more than this below the wheel plane, seen along a ray that descends steeper than `max_depression_slope_deg`, could only be seen down a wall at least that steep: a mismatch (ground or a rock nearer than the search reaches), dropped and counted with `max_below_ground`",
       {in(0, 1e3, "[)", "must be in [0, 1000) m")}},
      {"stereo.max_depression_slope_deg", CONFIG_FIELD(stereo.max_depression_slope_deg), "deg",
       "the ray slope of the check above; 90 off", {in(0, 90, "(]", "must be in (0, 90] deg (90: off)")}},
      {"stereo.occlusion_reach", CONFIG_FIELD(stereo.occlusion_reach), "",
       "points seen through terrain the map already knows are mismatches (ours; \"Stereo front end\", [docs/stereo.md](docs/stereo.md)): each ray is followed, out to `occlusion_reach` times the depth the disparity search cannot reach in its row (f B / highest disparity searched: 8.4 cm at 0.4 scale with 160), against the finest layer's heights and variances published the frame before; a point is dropped and counted (`points_occluded` in summary.json) when its ray passes more than `occlusion_margin` + 3 sigma below known terrain, or, nearer than the search reaches, below an unseen cell next to seen ones (`occlusion_fill`). Needs a map: `hazmap stereo` and `check` do not apply it. 0 off",
       {in(0, 100, "[]", "must be in [0, 100] (0: off)")}},
      {"stereo.occlusion_margin", CONFIG_FIELD(stereo.occlusion_margin_m), "m",
       "how far (plus 3 sigma) a ray may pass below known terrain (`occlusion_reach`)", {in(0, 1e3, "[)", "must be in [0, 1000) m")}},
      {"stereo.occlusion_fill", CONFIG_FIELD(stereo.occlusion_fill_m), "m",
       "an unseen cell next to seen ones counts as high as the highest seen cell within this distance (rounded up to whole cells of the finest layer; default the smallest hazard's width, SPEC 11); 0: unseen cells block nothing",
       {in(0, 10, "[]", "must be in [0, 10] m")}},
      {"stereo.support_rows", CONFIG_FIELD(stereo.support_rows), "px",
       "unsupported disparities: a pixel whose disparity exceeds, by more than `support_tolerance` and `support_margin_px`, most of the valid pixels in the `support_rows` rows below it floats (nothing seen from above the ground can): removed and counted (`disparities_unsupported` in summary.json). Catches sky-line mismatches on a black sky; drops overhangs too, so keep it off indoors. 0 off",
       {in(0, 100000, "[]", "must be in [0, 100000] pixels (0: off)")}, false, "shipped: 32"},
      {"stereo.support_tolerance", CONFIG_FIELD(stereo.support_tolerance), "",
       "relative margin of the support check: farther is disparity < d (1 - tolerance) - margin", {in(0, 1, "[)")}},
      {"stereo.support_margin_px", CONFIG_FIELD(stereo.support_margin_px), "px", "absolute margin of the support check",
       {in(0, 1e4, "[)", "must be in [0, 1e4) pixels")}},
      {"stereo.search", CONFIG_FIELD(stereo.search), "",
       "`full`: one range `[min_disparity, min_disparity + num_disparities)` for the whole image; `ground_band` (SPEC 3.4): horizontal strips, each searching only the disparities terrain can produce in its rows (from the camera's pose on the body), strips in parallel; not limited by `num_disparities`, capped at f B / `z_min` and by the image width; pixels outside their strip's band are invalid. StereoBM gives a full search's disparities inside the band",
       {}},
      {"stereo.band_max_slope_deg", CONFIG_FIELD(stereo.band_max_slope_deg), "deg",
       "`ground_band` terrain: the wheel plane tilted up to this slope about the point below the camera", {in(0, 90, "[)")}},
      {"stereo.band_max_height", CONFIG_FIELD(stereo.band_max_height_m), "m",
       "`ground_band` terrain: obstacles up to this above the wheel plane. With obstacles taller than the camera is high (CADRE: 0.15 m) every band reaches the cap",
       {finite("must be finite and >= 0", 0)}},
      {"stereo.band_max_depth", CONFIG_FIELD(stereo.band_max_depth_m), "m",
       "`ground_band` terrain: depressions down to this below the wheel plane", {finite("must be finite and >= 0", 0)}},
      {"stereo.row_offset_px", CONFIG_FIELD(stereo.row_offset), "px",
       "rows the rectified right image is moved down so that its rows agree with the left's (y_left - y_right of the rectified pair, as `hazmap check` measures it from feature matches; [docs/stereo.md](docs/stereo.md)): a residual calibration error. `auto`: measured once, from the first frame with enough matches. 0 off",
       {finite("must be a number of pixels in [-100, 100] or `auto`", -100, 100)}},  // 0 is off: no old `auto`
      {"stereo.c2f.levels", CONFIG_FIELD(stereo.c2f.levels), "", "c2f: pyramid levels; the full-range search runs at 1/2^(levels - 1) of the resolution, each finer level refines", {in(1, 6, "[]")}},
      {"stereo.c2f.radius", CONFIG_FIELD(stereo.c2f.radius), "px", "c2f: a finer level searches +- this around twice the coarser level's disparity", {in(1, 7, "[]")}},
      {"stereo.c2f.census_width", CONFIG_FIELD(stereo.c2f.census_width), "px", "c2f: census window width (a bit per window pixel but the centre: at most 9 x 7)", {odd_in(3, 9, "must be odd and in [3, 9]")}},
      {"stereo.c2f.census_height", CONFIG_FIELD(stereo.c2f.census_height), "px", "c2f: census window height", {odd_in(1, 7, "must be odd and in [1, 7]")}},
      {"stereo.c2f.p1", CONFIG_FIELD(stereo.c2f.p1), "bits", "c2f: semi-global penalty for a 1 px disparity step (census cost: differing bits)", {in(0, 1000, "[]")}},
      {"stereo.c2f.p2", CONFIG_FIELD(stereo.c2f.p2), "bits", "c2f: semi-global penalty for a larger step (normally >= p1)", {in(0, 4000, "[]")}},
      {"stereo.c2f.paths", CONFIG_FIELD(stereo.c2f.paths), "", "c2f: aggregation paths, 4 (along rows and columns, in parallel strips) or 8 (also diagonals, serial)", {in(4, 8, "[]")}},
      {"stereo.c2f.lr_max_diff", CONFIG_FIELD(stereo.c2f.lr_max_diff), "px", "c2f: left-right check at every level; -1 off", {at_least(-1)}},
      {"stereo.c2f.uniqueness", CONFIG_FIELD(stereo.c2f.uniqueness), "%", "c2f: at the full-range level a pixel's best cost must be below (100 - this) % of the best more than 1 px away", {in(0, 99, "[]")}},
      {"stereo.c2f.fill_unseeded", CONFIG_FIELD(stereo.c2f.fill_unseeded), "", "c2f: a pixel the coarser level left invalid is searched around the background of its row (the smaller of the nearest seeds to its left and right); false: it stays invalid"},
      {"stereo.c2f.p2_edge", CONFIG_FIELD(stereo.c2f.p2_edge), "DN", "c2f: edge-aware P2, a path step between pixels whose left-image intensities differ by D pays max(p1, p2 e / (e + D)) for a larger disparity jump (outlines may jump, smooth ground stays smooth); 0: p2 everywhere", {in(0, 255, "[]")}},
      {"stereo.c2f.subpixel_radius", CONFIG_FIELD(stereo.c2f.subpixel_radius), "px", "c2f, finest level: r > 0 takes the sub-pixel disparity from two lines of opposite slope through the raw census costs summed over a (2 r + 1) x (2 r + 1) box of neighbours at the pixel's three disparities, where the box's lowest sum is at the pixel's winner; 0: a parabola through the pixel's aggregated costs, which locks onto whole pixels by 0.06-0.19 px but lets the 4 cm layer's hole-free test prove more ground ([docs/stereo.md](docs/stereo.md))", {in(0, 3, "[]")}},
      {"stereo.c2f.max_match_cost", CONFIG_FIELD(stereo.c2f.max_match_cost), "bits", "c2f, finest level: a disparity whose own census distance at its winning disparity (before aggregation) exceeds this is dropped, where the semi-global paths carried a disparity the pixel's window does not match; 0 off", {in(0, 64, "[]")}},
      {"stereo.c2f.outline_jump_px", CONFIG_FIELD(stereo.c2f.outline_jump_px), "px", "c2f: where a column's disparity jumps by more than this between valid pixels at most 2 `outline_rows` + 2 rows apart (a crest's or a rock's top outline against the ground behind it), `outline_rows` pixels on the far side of the jump are dropped: a census window straddling the outline gives the near surface's first rows the far ground's disparity, points in the air over hidden ground ([docs/stereo.md](docs/stereo.md)); 0 off", {at_least(0)}},
      {"stereo.c2f.outline_rows", CONFIG_FIELD(stereo.c2f.outline_rows), "rows", "c2f: rows dropped on the far side of an outline (`outline_jump_px`); about the census window's half-height", {in(1, 32, "[]")}},
      // sensor (SPEC 4)
      {"sensor.model", CONFIG_FIELD(sensor.model), "", "`axis` (thesis) or `ray` (first-order propagation)", {}},
      {"sensor.pointing_error_px", CONFIG_FIELD(sensor.pointing_error_px), "px", "pixel noise p", {at_least(0)}},
      {"sensor.disparity_error_px", CONFIG_FIELD(sensor.disparity_error_px), "px", "matching noise m", {above(0)}},
      // map (SPEC 5, 6)
      {"map.insertion", CONFIG_FIELD(map.insertion), "",
       "`all_layers`: every point into every layer; `finest_then_pool`: into the finest layer holding it (and coarse cells not fully covered by the finer layer), covered coarse cells rebuilt as prior (+) pooled children (SPEC 5, 6.5); needs one rule family per consecutive pair",
       {}},
      {"map.layers", {}, "",
       "the layers, finest first, resolutions integer multiples (keys `map.layers[].*` below); the robot must stay within 2^30 cells of W's origin in every layer (and poses within 1e7 m)", {}, true},
      // rules (SPEC 6)
      {"rules.kalman.time_inflation", CONFIG_FIELD(rules.kalman.time_inflation_m2), "m^2",
       "added to every known cell's variance per frame", {at_least(0)}},
      {"rules.kalman.min_variance", CONFIG_FIELD(rules.kalman.min_variance_m2), "m^2",
       "variance floor, applied after each run of points in a cell", {at_least(0)}},
      {"rules.kalman.gate_sigma", CONFIG_FIELD(rules.kalman.gate_sigma), "",
       "drop a point with \\|z - mu\\| > gate x sqrt(var + sigma_m^2) against a known cell: one wild point does not move a converged cell; 0 off. Off in the shipped configs: it also locks in a cell first built from a correlated stereo error (a blob of one frame, 2 cm off, kept for 15 frames)",
       {at_least(0)}},
      {"rules.omg.max_weight", CONFIG_FIELD(rules.omg.max_weight), "", "cap on S", {above(0)}},
      {"rules.omg.decay", CONFIG_FIELD(rules.omg.decay), "", "S *= decay per frame", {in(0, 1, "(]")}},
      {"rules.omg.gate_sigma", CONFIG_FIELD(rules.omg.gate_sigma), "", "as `rules.kalman.gate_sigma` (SPEC 4 consistency gate); 0 off", {at_least(0)}},
      {"rules.ccm.weighting", CONFIG_FIELD(rules.ccm.weighting), "",
       "`constant` (w = 1), `trace` (1/trace Sigma), `det` (1/det Sigma; needs `sensor.pointing_error_px` > 0)", {}},
      {"rules.ccm.full_plane", CONFIG_FIELD(rules.ccm.full_plane), "", "solve slopes with Sxy; false: the thesis' diagonal forms"},
      {"rules.ccm.max_weight", CONFIG_FIELD(rules.ccm.max_weight), "",
       "W cap, applied once per frame after the frame's merge; near the rover one frame brings hundreds of points into a 4 cm cell, so a cap near that lets partial views at the image bottom wipe out the cell's lateral coverage",
       {above(0)}, false, "shipped configs 1e5"},
      {"rules.ccm.min_points", CONFIG_FIELD(rules.ccm.min_points), "", "evaluable cell: at least this many points", {at_least(1)}},
      {"rules.ccm.min_coverage", CONFIG_FIELD(rules.ccm.min_coverage), "", "evaluable cell: points spread over at least this share of the cell", {at_least(0)}},
      {"rules.ccm.max_std_ratio", CONFIG_FIELD(rules.ccm.max_std_ratio), "", "the layers' default `max_std_ratio`; 0 off", {at_least(0)}},
      // hazard (SPEC 8)
      {"hazard.max_slope_deg", CONFIG_FIELD(hazard.max_slope_deg), "deg", "greatest traversable slope", {in(0, 90, "()")}},
      {"hazard.wheelbase", CONFIG_FIELD(hazard.wheelbase_m), "m", "the rover's wheelbase",
       // Both this and footprint_radius become a reach in cells (radius / resolution, as an
       // int): 100 m is beyond any rover and keeps that reach within int at 1e-4 m cells.
       {in(0, 100, "(]", "must be in (0, 100] m (a reach in cells must fit an int)")}},
      {"hazard.min_kernel_fill", CONFIG_FIELD(hazard.min_kernel_fill), "", "fraction of kernel cells that must be observed to prove a cell traversable", {in(0, 1, "[]")}},
      {"hazard.roughness", CONFIG_FIELD(hazard.roughness), "",
       "piecewise-constant kernel statistic on layers finer than the wheelbase: `range` (max - min, SPEC 8.1, the thesis') or `detrended` (max - min of the residuals about the kernel's least-squares plane; slopes go to the wheel ring's vehicle-slope test, and a kernel plane rising h_min within the kernel's radius is face evidence)",
       {}, false, "shipped flight/default configs: `detrended`"},
      {"hazard.min_axis_coverage", CONFIG_FIELD(hazard.min_axis_coverage), "",
       "CCM: slope evidence from one axis of a partly covered cell needs the points' variance along it >= this x r^2/12 (a strip a third of the cell wide); across thinner strips the spread is the points' own ray-correlated noise (measured: 56 and 65 deg read on a 15 deg ramp across strips of coverage 0.04 and 0.02). A trade: with `cadre_flight` it ends the ramp's footprint false alarms (2.9 % -> 0) and costs 25 deg ramp recall (63 -> 50 % within 1.5 m; 0.25: 45 %)",
       {in(0, 1, "[]")}},
      {"hazard.k_sigma", CONFIG_FIELD(hazard.k_sigma), "", "hazard when s - k sigma > T, traversable when s + k sigma <= T (SPEC 8)", {in(0, 100, "[]")}},
      {"hazard.critical_height", CONFIG_FIELD(hazard.critical_height_m), "m",
       "smallest obstacle the rover must avoid: only layers with h_min <= it may call a fused cell traversable (SPEC 8.4); `auto`: the finest layer's h_min",
       {old_auto_negative("the finest layer's h_min"), finite_above(0, "must be finite and > 0, or `auto` (the finest layer's h_min)")}},
      {"hazard.footprint_radius", CONFIG_FIELD(hazard.footprint_radius_m), "m",
       "radius of the footprint map's disc (SPEC 8.5), at most 100; `auto`: wheelbase / 2",
       {old_auto_negative("wheelbase / 2"),
        finite("must be finite, in [0, 100] m (a reach in cells must fit an int), or `auto` (wheelbase / 2)", 0, 100)}},
      {"hazard.fused_extent", CONFIG_FIELD(hazard.fused_extent_m), "m",
       "side of the fused and footprint maps, at the finest resolution; `auto`: the largest layer's extent",
       {old_auto_zero("the largest layer's extent"),
        in(0, 1e4, "()", "must be in (0, 1e4) m or `auto` (the largest layer's extent)")}},
      {"hazard.finer_proof", CONFIG_FIELD(hazard.finer_proof), "",
       "fused map: a hazard of one layer yields where a strictly finer layer with h_min <= critical_height proves the cell traversable (a coarse cell on a rock's rim is a hazard over its whole area; the finer layer measured this part of it and passed every test); false: any layer's hazard stands (SPEC 8.4)",
       {}, false, "shipped `cadre_flight`, `cadre_full_res`, `thesis_ccm`, `k10`, `polar_traverse`: `true`"},
      {"hazard.partial_ring_proof", CONFIG_FIELD(hazard.partial_ring_proof), "",
       "when a wheel ring cut short proves from its exact samples' plane (an opposite pair and a third sample; [docs/hazards.md](docs/hazards.md)): `false` never (only full rings prove); `view_edge` when every missing sample lies where the stereo pair has never looked (outside every frame's image and depth range; a hole inside the view, such as a shadow or ground a rock hid, still blocks); `true` always, which under low sun proved rock-rim cells whose heights were wrong",
       {}, false, "shipped `cadre_flight`, `cadre_full_res`, `thesis_ccm`, `k10`, `polar_traverse`: `view_edge`"},
      {"hazard.coarse_ring_fill", CONFIG_FIELD(hazard.coarse_ring_fill), "",
       "a wheel-ring sample this layer has not measured is taken from the next coarser layer when that layer is CCM and the cell holding the point has a plane: the plane there, with its prediction variance plus the cell's roughness ([docs/hazards.md](docs/hazards.md)); false: such a sample is missing and the ring cannot prove",
       {}, false, "shipped `cadre_flight`, `cadre_full_res`, `thesis_ccm`, `k10`, `polar_traverse`: `true`"},
      {"hazard.footprint_centre_ring", CONFIG_FIELD(hazard.footprint_centre_ring), "",
       "footprint map: the rover's wheels stand on the ring around its centre, so only the centre's cell needs its wheel ring proven; a cell under the body that is unknown only because its own ring was not measured (every other test of a vouching layer proved it, and on CCM layers its height agrees with every neighbour's plane within h_min) counts as clear ([docs/hazards.md](docs/hazards.md)); false: every cell under the body proven with its own ring (SPEC 8.5)",
       {}, false, "shipped `default`, `cadre_flight`, `cadre_full_res`, `thesis_ccm`, `k10`, `polar_traverse`: `true`"},
      {"hazard.proof_margin", CONFIG_FIELD(hazard.proof_margin_m), "m",
       "fused map: a cell whose centre lies within this distance of a fused hazard cell's centre is not proven traversable (unknown, and not clear for the footprint): at a rock's silhouette the matcher's window measures the rock's base as the ground in front of it, so the cells beside the hazard the map saw may hold rock ([docs/hazards.md](docs/hazards.md)); 0: off",
       {in(0, 1, "[)", "must be in [0, 1) m")}, false, "shipped `cadre_flight`, `cadre_full_res`: 0.01; `default`: 0.03; `thesis_ccm`, `polar_traverse`: 0.04; `k10`: 0.02 (one fused cell)"},
      {"hazard.hole_free_tolerance", CONFIG_FIELD(hazard.hole_free_tolerance_px), "px",
       "hole-free test (`map.layers.N.hole_free_coverage`): a pixel over a cell whose disparity is within this of the cell's level plane saw its ground; one off by more (nearer: hidden; farther: another surface) keeps that frame from judging its quarter of the cell",
       {finite_above(0, "must be finite and > 0")}},
      {"hazard.incremental", CONFIG_FIELD(hazard.incremental), "",
       "SPEC 8.6: re-classify only cells whose result can have changed (identical maps; see \"Incremental hazard stage\", [docs/hazards.md](docs/hazards.md)); false: every cell every frame"},
      // pose uncertainty (SPEC 7)
      {"pose_uncertainty.enabled", CONFIG_FIELD(pose_uncertainty.enabled), "",
       "inflate reported variance by the pose noise (poses.txt `sx sy sz syaw`) added since each cell's last update (SPEC 7)"},
      // output (SPEC 9)
      {"output.every_n", CONFIG_FIELD(output.every_n), "frames", "write every n-th frame (and always the last)", {at_least(1)}},
      {"output.png", CONFIG_FIELD(output.png), "", "write the PNGs"},
      {"output.jdem", CONFIG_FIELD(output.jdem), "", "write the grid files, in `output.format`"},
      {"output.format", CONFIG_FIELD(output.format), "",
       "grid files: `jdem` (text), `geotiff` (`.tif`: float32, DEFLATE, nodata NaN, georeferenced in W; see Outputs), `both` (GeoTIFF for GIS tools plus the JDEM that `hazmap evaluate` reads)",
       {}},
      {"output.queue_frames", CONFIG_FIELD(output.queue_frames), "frames",
       "finished frames waiting for the writer thread (each holds a copy of every grid); the frame loop waits only when this many are queued; 0: write on the frame loop's thread",
       {in(0, kMaxOutputQueueFrames, "[]",
           "must be in [0, " + std::to_string(kMaxOutputQueueFrames) + "] (0: synchronous)")}},
      {"output.png_min_size", CONFIG_FIELD(output.png_min_size), "px", "PNGs are enlarged by whole pixels per cell to at least this size", {in(1, 8192, "[]")}},
      {"output.png_height_clip_pct", CONFIG_FIELD(output.png_height_clip_pct), "%",
       "height PNGs colour the known cells' [p, 100 - p] percentiles (the full range is printed under the bar); 0: full range", {in(0, 50, "[)")}},
      {"output.mosaic", CONFIG_FIELD(output.mosaic), "", "also write `OUT/mosaic/<frame>.png`: every layer side by side (same as `--mosaic`)"},
      {"output.unknown_reasons", CONFIG_FIELD(output.unknown_reasons), "",
       "also write `L<i>_unknown_reason` grids: why each unknown cell stayed unknown (bits, see docs/evaluation.md), from a diagnostic pass per written frame; `hazmap evaluate` counts them"},
  };
  return keys;
}

const std::vector<LayerKey>& layer_keys() {
  static const std::vector<LayerKey> keys = {
      {"resolution", LAYER_FIELD(resolution_m), "m", "cell size; an integer multiple of the previous layer's",
       {in(kMinResolutionM, kMaxResolutionM, "[]",
           "must be in [1e-4, 1000] m (finer than 0.1 mm is far below any stereo point's error; "
           "coarser than 1 km maps nothing a rover meets)")}, true},
      {"size", LAYER_FIELD(size), "cells", "cells per side, even",
       {multiple_of(2, at_least(2, "must be even and >= 2")),
        in(-kInf, kMaxLayerSize, "[]",
           "must be <= " + std::to_string(kMaxLayerSize) +
               " (a layer's size^2 cells are addressed with 32-bit indices)")}, true},
      {"rule", LAYER_FIELD(rule), "", "the layer's update rule, one of the registry's (allowed); `bananas` is the baseline: last point", {}, true},
      {"max_std_ratio", LAYER_FIELD(max_std_ratio), "",
       "any rule: drop a point for this layer when its lateral std exceeds ratio x r / sqrt(12) (SPEC 4); 0 off; `auto`: `rules.ccm.max_std_ratio`",
       {old_auto_negative("rules.ccm.max_std_ratio"), finite("must be finite and >= 0 (0: off), or `auto` (rules.ccm.max_std_ratio)", 0)}},
      {"hole_free_coverage", LAYER_FIELD(hole_free_coverage), "",
       "CCM: a cell whose points spread over at least this share of it (kappa, as `rules.ccm.min_coverage`) also has a plane, for its own tests only, when no part of it went unmeasured: its points have landed in every one of its 4 x 4 sub-cells, or some frame's disparity image saw all of it (each quarter with a pixel on its level plane and none off it; a quarter no pixel matched, where the right camera could match, is a hole and ends the second way for good) ([docs/hazards.md](docs/hazards.md)); 0 off",
       {in(0, 1, "[]")}, false, "shipped `cadre_flight`, `cadre_full_res`, `thesis_ccm`, `polar_traverse`: 0.5 on the 4 cm layer; `k10`: on the 2 cm layer"},
      {"hazard.kernel", LAYER_FIELD(hazard.kernel), "cells",
       "piecewise-constant layers: roughness kernel diameter (odd, smaller than the layer)",
       {odd_in(1, kInf, "must be odd, >= 1 and smaller than the layer size")}},
      {"hazard.roughness_threshold", LAYER_FIELD(hazard.roughness_threshold_m), "m",
       "piecewise-constant roughness threshold; `auto`: (kernel - 1) r tan(max_slope)",
       {old_auto_negative("(kernel - 1) r tan(max_slope)"), finite("must be finite and >= 0, or `auto`", 0)}},
      {"hazard.h_min", LAYER_FIELD(hazard.h_min_m), "m",
       "smallest obstacle the layer vouches for (SPEC 8.1-8.4); `auto`: CCM 0.75 r (rock face if inclination > atan(h_min / r)), piecewise constant its roughness threshold",
       {old_auto_not_positive("CCM 0.75 r, piecewise constant the roughness threshold"),
        finite_above(0, "must be finite and > 0, or `auto`")}},
      {"hazard.rho_max", LAYER_FIELD(hazard.rho_max_m2), "m^2", "CCM roughness threshold; `auto`: h_min^2 / 16",
       {old_auto_not_positive("h_min^2 / 16"), finite_above(0, "must be finite and > 0, or `auto`")}},
  };
  return keys;
}

#undef CONFIG_FIELD
#undef LAYER_FIELD

namespace {

template <class Owner>
std::vector<std::string> choices_of(const ConfigKey<Owner>& key) {
  return std::visit(
      [](auto field) -> std::vector<std::string> {
        using F = decltype(field);
        if constexpr (std::is_same_v<F, std::monostate>) {
          return {};
        } else {
          using V = std::remove_reference_t<decltype(field(std::declval<Owner&>()))>;
          if constexpr (std::is_enum_v<V>) {
            return enum_names<V>();
          } else {
            return {};
          }
        }
      },
      key.field);
}

template <class Owner>
std::string default_text(const ConfigKey<Owner>& key, Owner& defaults) {
  if (key.required) return "required";
  std::ostringstream text;
  std::visit(
      [&](auto field) {
        using F = decltype(field);
        if constexpr (std::is_same_v<F, std::monostate>) {
        } else {
          const auto& value = field(defaults);
          using V = std::decay_t<decltype(value)>;
          if constexpr (std::is_same_v<V, bool>) text << (value ? "true" : "false");
          else if constexpr (std::is_enum_v<V>) text << "`" << enum_name(value) << "`";
          else if constexpr (std::is_same_v<V, std::optional<double>> || std::is_same_v<V, std::optional<int>>)
            text << (value ? number_text(*value) : std::string("`auto`"));
          else if constexpr (std::is_same_v<V, std::array<int, 4>>)
            text << "`[" << value[0] << ", " << value[1] << ", " << value[2] << ", " << value[3] << "]`";
          else text << value;
        }
      },
      key.field);
  if (!key.default_note.empty()) text << " (" << key.default_note << ")";
  return text.str();
}

/// The values a key accepts: its choices or its checks' messages.
template <class Owner>
std::string allowed(const ConfigKey<Owner>& key) {
  std::string text;
  for (const std::string& c : key_choices(key)) text += (text.empty() ? "`" : " `") + c + "`";
  for (const ValueCheck& c : key.checks)
    if (!c.old_auto) text += (text.empty() ? "" : "; ") + c.message();
  return text;
}

template <class Owner>
std::string row(const std::string& name, const ConfigKey<Owner>& key, Owner& defaults) {
  return "| `" + name + "` | " + default_text(key, defaults) + " | " + key.unit + " | " +
         allowed(key) + " | " + key.help + " |\n";
}

}  // namespace

std::vector<std::string> key_choices(const TopKey& key) { return choices_of(key); }
std::vector<std::string> key_choices(const LayerKey& key) { return choices_of(key); }

std::string config_reference_markdown() {
  std::string table = "| key | default | unit | allowed | meaning |\n|---|---|---|---|---|\n";
  Config config;
  for (const TopKey& k : config_keys()) {
    table += row(k.name, k, config);
    if (k.name != "map.layers") continue;
    LayerConfig layer;
    for (const LayerKey& l : layer_keys()) table += row("map.layers[]." + l.name, l, layer);
  }
  // The help texts link docs/ pages from the top folder; the table lives in docs/.
  for (std::size_t at = table.find("](docs/"); at != std::string::npos; at = table.find("](docs/", at))
    table.erase(at + 2, 5);
  return table;
}

}  // namespace hazmap
