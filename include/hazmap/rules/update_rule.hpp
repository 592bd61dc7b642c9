#pragma once
// The update-rule interface: what a struct must provide for RollingLayer<Rule>
// (map/rolling_layer.hpp) to hold its cells. Written down once here, as documentation and
// as compile-time checks: RollingLayer<Rule> static_asserts check_update_rule<Rule>(), so
// a rule that lacks a member fails with one message per missing piece, naming the member
// and what it is for, before any error from inside the layer.
//
// Each check is the layer's own call expression in a decltype (the call site is named
// beside it), with the argument types and value categories the layer passes, except that
// Config is always passed const (a rule does not change its parameters); a member with
// the right name but a signature the layer cannot call fails like a missing one. The
// rules in this folder (bananas, kalman, omg, ccm) are the examples;
// tests/rules/update_rule_test.cpp has a complete minimal rule (MinHeightRule). A rule
// needs only public headers: this one, rules/merge_policy.hpp and rules/run_view.hpp (the
// runs it is handed), map/point_chunk.hpp and map/moments.hpp; map/internal/ holds the
// library's own kernels, which the built-in rules use.
//
// Every rule:
//   static constexpr const char* kName                   rule name (Layer::rule_name)
//   static constexpr bool kHasPlane                      cells fit a plane (below)
//   static constexpr MergePolicy kMerge                  how runs reach the cells (below)
//   static constexpr bool kStampInCell, kHeightGate      (below)
//     (these four in this order in every rule, so that the rule headers read alike)
//   struct Config    copyable                             the rule's parameters
//   struct Cell      default-constructible, copyable      one cell's state (the layer
//                                                         clears each cell before use)
//   struct Sums      default-constructible, assignable    a run's or a frame's points, summed
//   known(const Cell&) -> bool                            whether a cell holds data
//   clear(Cell&)                                          forget a cell (the window moved)
//   age(const Config&, Cell&, std::uint32_t frames)       `frames` frames of ageing at once
//   ages_exports(const Config&) -> bool                   whether age changes the export
//   to_moments(const Cell&) -> Moments                    pooling view of a cell
//   from_moments(const Config&, Cell&, const Moments&)    store pooled moments in a cell
//
// The merge policy (kMerge, rules/merge_policy.hpp) is the one choice of insertion path;
// each policy needs its own members:
//   per_run (runs merged straight into the cell, one by one; the baseline):
//     run_sums(const PointChunk&, const ChunkRuns&, int r) -> Sums-like  sums of run r
//     merge_run(const Config&, Cell&, <run_sums result>, double z_first_m,
//               std::uint32_t owed_frames, double max_precision)    age, then merge a run
//     max_precision(const Config&) -> double                         merge_run's cap
//   per_chunk (Kalman): per_run's members, and
//     weights(const PointChunk&) -> const float*     the layer sums each run's weighted
//                                                    heights (ChunkRuns::sum_heights)
//     merge_chunk_runs(const Config&, Cell*, std::uint32_t frame, const ChunkRuns&)
//       -> std::size_t (points merged)               an unpooled layer's whole run list
//   per_frame (runs summed into a per-frame accumulator, merged once per frame; CCM, OMG):
//     add_run(const Config&, Sums&, const RunPoints&, double z_ref_m)  add a run to the sums
//     reference_z(const Cell&) -> float                               accumulator reference
//     weights(const PointChunk&) -> const float*                      per-point weights
//     merge_frame(const Config&, Cell&, const Sums&, double z_ref_m, double cell_m)
//                                                    merge a frame's sums into a cell
//
// The other traits:
//   kStampInCell: the cell holds its last-merge frame as `std::uint32_t stamp` (else the
//     layer keeps it beside the cells)
//   kHeightGate: the SPEC 4 consistency gate
//       Config::gate_sigma (double; 0 = off)
//       gate_state(const Config&, const Cell&, std::uint32_t owed, double* mu, double* var)
//         -> bool
//   kHasPlane (needs per_frame: the cell-centred x, y reach the rule via add_run only):
//     the cell fits a plane (CCM) and the layer exports the plane grids:
//       evaluable(const Config&, const Cell&, double cell_m) -> bool
//       slopes(const Config&, const Cell&, double* a, double* b)
//       height_at(const Config&, const Cell&, double qx, double qy) -> number
//       mean_z(const Cell&) -> number
//       published_variance(const Config&, const Cell&, double cell_m, bool evaluable) -> number
//       roughness(const Config&, const Cell&) -> number
//       coverage(const Cell&, double cell_m) -> number
//       occupied(const Cell&) -> std::uint16_t         4 x 4 sub-cells that held a point
//                                                      (map/moments.hpp: occupancy_bit)
//       cell_values(const Cell&) -> PlaneCellValues   count, noise and lateral grids
//     else (piecewise-constant cells):
//       height(const Cell&) -> float, variance(const Cell&) -> float   NaN when unknown
//
// Optional (not checked here; read by rules/rule_registry.hpp, not by the layer):
//   static constexpr const char* kPoolFamily   the family of rules whose layers
//     finest_then_pool may pool together (SPEC 5); without it a rule pools only with
//     itself (its kName). OMG declares "kalman": both pool as a weighted height.
//
//   static void derive_config(Config&, const HazardConfig&)   values of its Config the
//     rule derives from the hazard section (CCM: max_slope_rad), after its settings are
//     copied (rules/rule_registry.hpp: rule_config).
//
// Members a rule may have that the layer does not use (update, mean, ...) are not checked.

#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "hazmap/map/moments.hpp"
#include "hazmap/map/plane_cell_values.hpp"
#include "hazmap/map/point_chunk.hpp"
#include "hazmap/rules/merge_policy.hpp"
#include "hazmap/rules/run_view.hpp"

namespace hazmap {

namespace update_rule_detail {

// ---- Detection idiom (std::experimental::is_detected, written out for C++17). ----

struct Nonesuch {
  Nonesuch() = delete;
  ~Nonesuch() = delete;
};

template <class Default, class AlwaysVoid, template <class...> class Op, class... Args>
struct Detector {
  static constexpr bool value = false;
  using type = Default;
};
template <class Default, template <class...> class Op, class... Args>
struct Detector<Default, std::void_t<Op<Args...>>, Op, Args...> {
  static constexpr bool value = true;
  using type = Op<Args...>;
};

/// Whether Op<Args...> is well-formed.
template <template <class...> class Op, class... Args>
constexpr bool is_detected_v = Detector<Nonesuch, void, Op, Args...>::value;
/// Op<Args...>, or Default if it is ill-formed.
template <class Default, template <class...> class Op, class... Args>
using detected_or_t = typename Detector<Default, void, Op, Args...>::type;
/// Whether Op<Args...> is well-formed and implicitly converts to To.
template <class To, template <class...> class Op, class... Args>
constexpr bool is_detected_convertible_v =
    std::is_convertible_v<detected_or_t<Nonesuch, Op, Args...>, To>;

// ---- Nested types. ----

template <class R>
using config_t = typename R::Config;
template <class R>
using cell_t = typename R::Cell;
template <class R>
using sums_t = typename R::Sums;

// ---- Constants: a bool trait is a constant expression of type bool. ----

#define HAZMAP_RULE_BOOL_TRAIT(name)                                                           \
  template <class R>                                                                           \
  using name##_t = std::enable_if_t<std::is_same_v<std::remove_cv_t<decltype(R::name)>, bool>, \
                                    std::bool_constant<R::name>>;
HAZMAP_RULE_BOOL_TRAIT(kHasPlane)
HAZMAP_RULE_BOOL_TRAIT(kStampInCell)
HAZMAP_RULE_BOOL_TRAIT(kHeightGate)
#undef HAZMAP_RULE_BOOL_TRAIT
// The merge policy is a constant expression of type MergePolicy.
template <class R>
using kMerge_t = std::enable_if_t<std::is_same_v<std::remove_cv_t<decltype(R::kMerge)>, MergePolicy>,
                                  std::integral_constant<MergePolicy, R::kMerge>>;
template <class R>
using name_t = decltype(R::kName);  // RollingLayer::rule_name returns it

// ---- Every rule: the layer's call expressions (call site in the comment). ----

template <class T>
T& lv();  // an lvalue of T in decltype (std::declval gives an xvalue)

// export_cells, pool_into: Rule::known(c) on a `const Cell` (also on cells_[s]).
template <class R>
using known_t = decltype(R::known(lv<const cell_t<R>>()));
// clear(range): Rule::clear(cells_[slot]).
template <class R>
using clear_t = decltype(R::clear(lv<cell_t<R>>()));
// current() / catch_up / begin_frame: Rule::age(config_, c, owed_frames(slot)).
template <class R>
using age_t = decltype(R::age(lv<const config_t<R>>(), lv<cell_t<R>>(), std::uint32_t{}));
// ages_exports() const: return Rule::ages_exports(config_).
template <class R>
using ages_exports_t = decltype(R::ages_exports(lv<const config_t<R>>()));
// (per_frame) FrameAccumulators::merge_into: Rule::merge_frame(config_, cells_[slot], a.sums, a.z_ref, r) with a a
// `const Accumulator&` (Sums sums; float z_ref).
template <class R>
using merge_frame_t =
    decltype(R::merge_frame(lv<const config_t<R>>(), lv<cell_t<R>>(), lv<const sums_t<R>>(),
                            lv<const float>(), lv<const double>()));
// pool_into, rebuild_covered, cell_moments: Moments m = Rule::to_moments(c).
template <class R>
using to_moments_t = decltype(R::to_moments(lv<const cell_t<R>>()));
// rebuild_covered: Rule::from_moments(config_, cells_[slot], m) with `Moments m`.
template <class R>
using from_moments_t =
    decltype(R::from_moments(lv<const config_t<R>>(), lv<cell_t<R>>(), lv<Moments>()));
// FrameAccumulators::add_runs: fresh.sums = typename Rule::Sums{}.
template <class R>
using sums_assign_t = decltype(lv<sums_t<R>>() = sums_t<R>{});

// ---- MergePolicy::per_run, per_chunk (layer_insertion::merge_runs, merge_run_list). ----

// layer_insertion::merge_run_list: Rule::run_sums(chunk, runs_, k).
template <class R>
using run_sums_t = decltype(R::run_sums(lv<const PointChunk>(), lv<ChunkRuns>(), lv<int>()));
// layer_insertion::merge_run_list: Rule::merge_run(cfg, cells[s], Rule::run_sums(...), z[first],
// owed_frames(frame, last, kPooled), max_precision), cfg a `const Config`.
template <class R>
using merge_run_t = decltype(R::merge_run(lv<const config_t<R>>(), lv<cell_t<R>>(),
                                          std::declval<detected_or_t<sums_t<R>, run_sums_t, R>>(),
                                          lv<const float>(), std::uint32_t{}, lv<const double>()));
// layer_insertion::merge_run_list: const double max_precision = Rule::max_precision(cfg).
template <class R>
using max_precision_t = decltype(R::max_precision(lv<const config_t<R>>()));
// layer_insertion::merge_runs: return Rule::merge_chunk_runs(config_, cells_.data(), frame_, runs_).
template <class R>
using merge_chunk_runs_t = decltype(R::merge_chunk_runs(
    lv<const config_t<R>>(), std::declval<cell_t<R>*>(), lv<std::uint32_t>(), lv<ChunkRuns>()));

// ---- MergePolicy::per_frame (FrameAccumulators), and per_chunk (merge_runs). ----

// FrameAccumulators::add_runs: const float* const w = Rule::weights(chunk); merge_runs:
// runs_.sum_heights(Rule::weights(chunk), chunk.z).
template <class R>
using weights_t = decltype(R::weights(lv<const PointChunk>()));
// FrameAccumulators::add_runs: fresh.z_ref = Rule::known(cells_[s]) ? Rule::reference_z(cells_[s]) : z.
template <class R>
using reference_z_t =
    decltype(lv<float>() = (true ? R::reference_z(lv<cell_t<R>>()) : lv<const float>()));
// FrameAccumulators::add_runs: Rule::add_run(cells.config(), a.sums, RunPoints{...}, a.z_ref).
template <class R>
using add_run_t =
    decltype(R::add_run(lv<const config_t<R>>(), lv<sums_t<R>>(), RunPoints{}, lv<float>()));

// ---- kStampInCell (stamp, last_merge): std::uint32_t& last = cells[slot].stamp. ----

template <class R>
using stamp_t = decltype(lv<cell_t<R>>().stamp);
template <class R>
constexpr bool has_stamp_v = std::is_same_v<detected_or_t<Nonesuch, stamp_t, R>, std::uint32_t>;

// ---- kHeightGate (insert_chunk, gate_heights). ----

// gate_heights: const double g2 = config_.gate_sigma * config_.gate_sigma.
template <class R>
using gate_sigma_t =
    decltype(lv<const config_t<R>>().gate_sigma * lv<const config_t<R>>().gate_sigma);
// gate_heights: known = Rule::gate_state(config_, cells_[s], owed_frames(s), &mu, &var).
template <class R>
using gate_state_t =
    decltype(R::gate_state(lv<const config_t<R>>(), lv<cell_t<R>>(), std::uint32_t{},
                           std::declval<double*>(), std::declval<double*>()));

// ---- kHasPlane (export_cells). ----

// const bool evaluable = Rule::evaluable(config_, c, r).
template <class R>
using evaluable_t =
    decltype(R::evaluable(lv<const config_t<R>>(), lv<const cell_t<R>>(), lv<const double>()));
// Rule::slopes(config_, c, &a, &b).
template <class R>
using slopes_t = decltype(R::slopes(lv<const config_t<R>>(), lv<const cell_t<R>>(),
                                    std::declval<double*>(), std::declval<double*>()));
// static_cast<float>(Rule::height_at(config_, c, 0.0, 0.0)).
template <class R>
using height_at_t = decltype(static_cast<float>(
    R::height_at(lv<const config_t<R>>(), lv<const cell_t<R>>(), 0.0, 0.0)));
// static_cast<float>(Rule::mean_z(c)).
template <class R>
using mean_z_t = decltype(static_cast<float>(R::mean_z(lv<const cell_t<R>>())));
// static_cast<float>(Rule::published_variance(config_, c, r, evaluable)).
template <class R>
using published_variance_t = decltype(static_cast<float>(R::published_variance(
    lv<const config_t<R>>(), lv<const cell_t<R>>(), lv<const double>(), lv<const bool>())));
// static_cast<float>(Rule::roughness(config_, c)).
template <class R>
using roughness_t =
    decltype(static_cast<float>(R::roughness(lv<const config_t<R>>(), lv<const cell_t<R>>())));
// static_cast<float>(Rule::coverage(c, r)).
template <class R>
using coverage_t =
    decltype(static_cast<float>(R::coverage(lv<const cell_t<R>>(), lv<const double>())));
// seen_whole->hole_free(..., Rule::occupied(c)).
template <class R>
using occupied_t = decltype(std::uint16_t(R::occupied(lv<const cell_t<R>>())));
// const PlaneCellValues v = Rule::cell_values(c).
template <class R>
using cell_values_t = decltype(PlaneCellValues(R::cell_values(lv<const cell_t<R>>())));

// ---- !kHasPlane (export_cells): out.height.at(row, col) = Rule::height(c), variance. ----

template <class R>
using height_t = decltype(R::height(lv<const cell_t<R>>()));
template <class R>
using variance_t = decltype(R::variance(lv<const cell_t<R>>()));

}  // namespace update_rule_detail

/// Checks that `Rule` is an update rule RollingLayer<Rule> can hold (the interface above):
/// one static_assert per requirement, each naming the missing member. Returns whether every
/// requirement holds, so that `static_assert(check_update_rule<Rule>())` adds one summary
/// failure after the specific ones. Requirements that depend on a missing type or trait
/// are not checked (their messages would only repeat the first one).
template <class Rule>
constexpr bool check_update_rule() {
  using namespace update_rule_detail;

  // Nested types.
  constexpr bool has_config = is_detected_v<config_t, Rule>;
  constexpr bool has_cell = is_detected_v<cell_t, Rule>;
  constexpr bool has_sums = is_detected_v<sums_t, Rule>;
  static_assert(has_config, "update rule: needs a nested type Config -- the rule's parameters");
  static_assert(has_cell, "update rule: needs a nested type Cell -- one cell's state");
  static_assert(has_sums,
                "update rule: needs a nested type Sums -- the points of a run or a frame, summed");

  // Constants.
  constexpr bool has_name = is_detected_convertible_v<const char*, name_t, Rule>;
  static_assert(has_name,
                "update rule: needs static constexpr const char* kName -- the rule's name "
                "(Layer::rule_name)");
  constexpr bool has_plane = is_detected_v<kHasPlane_t, Rule>;
  static_assert(has_plane,
                "update rule: needs static constexpr bool kHasPlane -- whether cells fit a "
                "plane and the layer exports the plane grids");
  constexpr bool has_merge = is_detected_v<kMerge_t, Rule>;
  static_assert(has_merge,
                "update rule: needs static constexpr MergePolicy kMerge -- how runs of points "
                "reach the cells: per_run, per_chunk or per_frame (rules/merge_policy.hpp)");
  constexpr bool has_stamp_trait = is_detected_v<kStampInCell_t, Rule>;
  static_assert(has_stamp_trait,
                "update rule: needs static constexpr bool kStampInCell -- whether the cell "
                "holds its last-merge frame (Cell::stamp)");
  constexpr bool has_gate_trait = is_detected_v<kHeightGate_t, Rule>;
  static_assert(has_gate_trait,
                "update rule: needs static constexpr bool kHeightGate -- whether the rule has "
                "the SPEC 4 consistency gate (gate_state, Config::gate_sigma)");

  constexpr bool base = has_config && has_cell && has_sums && has_name && has_plane &&
                        has_merge && has_stamp_trait && has_gate_trait;
  if constexpr (!base) {
    return false;
  } else {
    // Type properties.
    constexpr bool config_ok = std::is_copy_constructible_v<typename Rule::Config>;
    static_assert(config_ok,
                  "update rule: Config must be copy-constructible -- the layer keeps a copy");
    constexpr bool cell_ok = std::is_default_constructible_v<typename Rule::Cell> &&
                             std::is_copy_constructible_v<typename Rule::Cell> &&
                             std::is_copy_assignable_v<typename Rule::Cell>;
    static_assert(cell_ok,
                  "update rule: Cell must be default-constructible and copyable -- the layer "
                  "allocates its cells and reads copies");
    constexpr bool sums_ok =
        std::is_default_constructible_v<typename Rule::Sums> && is_detected_v<sums_assign_t, Rule>;
    static_assert(sums_ok,
                  "update rule: Sums must be default-constructible and assignable from Sums{} "
                  "-- the layer starts each cell's frame sums from Sums{}");

    // Trait consistency.
    constexpr bool plane_needs_frames = !Rule::kHasPlane || Rule::kMerge == MergePolicy::per_frame;
    static_assert(plane_needs_frames,
                  "update rule: kHasPlane needs kMerge = MergePolicy::per_frame -- the points' "
                  "cell-centred x, y reach the rule through add_run only");

    // Every rule.
    constexpr bool known_ok = is_detected_convertible_v<bool, known_t, Rule>;
    static_assert(known_ok,
                  "update rule: needs static bool known(const Cell&) -- whether a cell holds data");
    constexpr bool clear_ok = is_detected_v<clear_t, Rule>;
    static_assert(clear_ok,
                  "update rule: needs static void clear(Cell&) -- forget a cell (it left the "
                  "window); a cleared cell is not known");
    constexpr bool age_ok = is_detected_v<age_t, Rule>;
    static_assert(age_ok,
                  "update rule: needs static void age(const Config&, Cell&, std::uint32_t "
                  "frames) -- that many frames of ageing at once (the layer ages lazily; may do "
                  "nothing)");
    constexpr bool ages_exports_ok = is_detected_convertible_v<bool, ages_exports_t, Rule>;
    static_assert(ages_exports_ok,
                  "update rule: needs static bool ages_exports(const Config&) -- whether age() "
                  "changes what a cell exports");
    constexpr bool to_moments_ok = is_detected_convertible_v<Moments, to_moments_t, Rule>;
    static_assert(to_moments_ok,
                  "update rule: needs static Moments to_moments(const Cell&) -- a cell as "
                  "moments, for pooling (empty if unknown)");
    constexpr bool from_moments_ok = is_detected_v<from_moments_t, Rule>;
    static_assert(from_moments_ok,
                  "update rule: needs static void from_moments(const Config&, Cell&, const "
                  "Moments&) -- store pooled moments in a cell (clear it if empty)");
    constexpr bool every_rule = config_ok && cell_ok && sums_ok && plane_needs_frames &&
                                known_ok && clear_ok && age_ok && ages_exports_ok &&
                                to_moments_ok && from_moments_ok;

    // Merge path: the members of the rule's merge policy.
    bool path_ok = true;
    if constexpr (merges_runs(Rule::kMerge)) {
      constexpr bool run_sums_ok = is_detected_v<run_sums_t, Rule>;
      static_assert(run_sums_ok,
                    "update rule with MergePolicy::per_run or per_chunk: needs static Sums "
                    "run_sums(const PointChunk&, const ChunkRuns&, int r) -- the sums of run r "
                    "of a chunk");
      constexpr bool merge_run_ok = is_detected_v<merge_run_t, Rule>;
      static_assert(merge_run_ok,
                    "update rule with MergePolicy::per_run or per_chunk: needs static void "
                    "merge_run(const Config&, Cell&, const Sums&, double z_first_m, std::uint32_t "
                    "owed_frames, double max_precision) -- age a cell, then merge one run's sums "
                    "into it");
      constexpr bool max_precision_ok = is_detected_convertible_v<double, max_precision_t, Rule>;
      static_assert(max_precision_ok,
                    "update rule with MergePolicy::per_run or per_chunk: needs static double "
                    "max_precision(const Config&) -- the cap merge_run takes (computed once per "
                    "chunk)");
      path_ok = run_sums_ok && merge_run_ok && max_precision_ok;
    } else {
      constexpr bool add_run_ok = is_detected_v<add_run_t, Rule>;
      static_assert(add_run_ok,
                    "update rule with MergePolicy::per_frame: needs static void add_run(const "
                    "Config&, Sums&, const RunPoints&, double z_ref_m) -- add a run of points to "
                    "a cell's frame sums");
      constexpr bool reference_ok = is_detected_v<reference_z_t, Rule>;
      static_assert(reference_ok,
                    "update rule with MergePolicy::per_frame: needs static float "
                    "reference_z(const Cell&) -- the height a known cell's frame sums are taken "
                    "relative to");
      constexpr bool merge_frame_ok = is_detected_v<merge_frame_t, Rule>;
      static_assert(merge_frame_ok,
                    "update rule with MergePolicy::per_frame: needs static void merge_frame(const "
                    "Config&, Cell&, const Sums&, double z_ref_m, double cell_m) -- merge a "
                    "frame's sums (z relative to z_ref_m) into a cell");
      path_ok = add_run_ok && reference_ok && merge_frame_ok;
    }
    bool weights_ok = true;
    if constexpr (Rule::kMerge != MergePolicy::per_run) {
      constexpr bool ok = is_detected_convertible_v<const float*, weights_t, Rule>;
      static_assert(ok,
                    "update rule with MergePolicy::per_chunk or per_frame: needs static const "
                    "float* weights(const PointChunk&) -- the points' weights (null: all 1 where "
                    "the rule's add_run allows it)");
      weights_ok = ok;
    }
    bool chunks_ok = true;
    if constexpr (Rule::kMerge == MergePolicy::per_chunk) {
      constexpr bool ok = is_detected_convertible_v<std::size_t, merge_chunk_runs_t, Rule>;
      static_assert(ok,
                    "update rule with MergePolicy::per_chunk: needs static std::size_t "
                    "merge_chunk_runs(const Config&, Cell*, std::uint32_t frame, const "
                    "ChunkRuns&) -- merge a chunk's runs into an unpooled layer's cells, "
                    "returning the points merged");
      chunks_ok = ok;
    }
    bool stamp_ok = true;
    if constexpr (Rule::kStampInCell) {
      constexpr bool ok = has_stamp_v<Rule>;
      static_assert(ok,
                    "update rule with kStampInCell: needs a field std::uint32_t Cell::stamp -- "
                    "the frame of the cell's last merge");
      stamp_ok = ok;
    }
    bool gate_ok = true;
    if constexpr (Rule::kHeightGate) {
      constexpr bool sigma_ok = is_detected_convertible_v<double, gate_sigma_t, Rule>;
      static_assert(sigma_ok,
                    "update rule with kHeightGate: needs a field double Config::gate_sigma -- the "
                    "SPEC 4 consistency gate's width in standard deviations (0 = off)");
      constexpr bool state_ok = is_detected_convertible_v<bool, gate_state_t, Rule>;
      static_assert(state_ok,
                    "update rule with kHeightGate: needs static bool gate_state(const Config&, "
                    "const Cell&, std::uint32_t owed_frames, double* mu, double* var) -- the "
                    "height and variance a point is gated against (false: unknown, no gate)");
      gate_ok = sigma_ok && state_ok;
    }
    bool export_ok = true;
    if constexpr (Rule::kHasPlane) {
      constexpr bool evaluable_ok = is_detected_convertible_v<bool, evaluable_t, Rule>;
      static_assert(evaluable_ok,
                    "update rule with kHasPlane: needs static bool evaluable(const Config&, const "
                    "Cell&, double cell_m) -- whether the cell publishes its plane");
      constexpr bool slopes_ok = is_detected_v<slopes_t, Rule>;
      static_assert(slopes_ok,
                    "update rule with kHasPlane: needs static void slopes(const Config&, const "
                    "Cell&, double* a, double* b) -- the plane's dz/dx, dz/dy");
      constexpr bool height_at_ok = is_detected_v<height_at_t, Rule>;
      static_assert(height_at_ok,
                    "update rule with kHasPlane: needs static double height_at(const Config&, "
                    "const Cell&, double qx_m, double qy_m) -- the plane's height at a "
                    "cell-centric point");
      constexpr bool mean_z_ok = is_detected_v<mean_z_t, Rule>;
      static_assert(mean_z_ok,
                    "update rule with kHasPlane: needs static double mean_z(const Cell&) -- the "
                    "points' mean height, published where the cell is not evaluable");
      constexpr bool published_ok = is_detected_v<published_variance_t, Rule>;
      static_assert(published_ok,
                    "update rule with kHasPlane: needs static double published_variance(const "
                    "Config&, const Cell&, double cell_m, bool evaluable) -- the exported height "
                    "variance");
      constexpr bool roughness_ok = is_detected_v<roughness_t, Rule>;
      static_assert(roughness_ok,
                    "update rule with kHasPlane: needs static double roughness(const Config&, "
                    "const Cell&) -- the plane-normal variance");
      constexpr bool coverage_ok = is_detected_v<coverage_t, Rule>;
      static_assert(coverage_ok,
                    "update rule with kHasPlane: needs static double coverage(const Cell&, double "
                    "cell_m) -- how well the points cover the cell laterally");
      constexpr bool occupied_ok = is_detected_v<occupied_t, Rule>;
      static_assert(occupied_ok,
                    "update rule with kHasPlane: needs static std::uint16_t occupied(const Cell&) "
                    "-- which of the cell's 4 x 4 sub-cells held a point");
      constexpr bool fields_ok = is_detected_v<cell_values_t, Rule>;
      static_assert(fields_ok,
                    "update rule with kHasPlane: needs static PlaneCellValues cell_values(const "
                    "Cell&) -- exported as the count, noise and lateral grids");
      export_ok = evaluable_ok && slopes_ok && height_at_ok && mean_z_ok && published_ok &&
                  roughness_ok && coverage_ok && occupied_ok && fields_ok;
    } else {
      constexpr bool height_ok = is_detected_convertible_v<float, height_t, Rule>;
      static_assert(height_ok,
                    "update rule without kHasPlane: needs static float height(const Cell&) -- "
                    "the exported height (NaN if unknown)");
      constexpr bool variance_ok = is_detected_convertible_v<float, variance_t, Rule>;
      static_assert(variance_ok,
                    "update rule without kHasPlane: needs static float variance(const Cell&) -- "
                    "the exported height variance (NaN if unknown)");
      export_ok = height_ok && variance_ok;
    }
    return every_rule && path_ok && weights_ok && chunks_ok && stamp_ok && gate_ok && export_ok;
  }
}

}  // namespace hazmap
