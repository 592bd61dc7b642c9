#pragma once
// The map core's configuration: plain structs with defaults for the layers (map), their
// update rules (rules) and the hazard tests (hazard), the part of the run configuration
// (io/config.hpp, SPEC 13) that LayerStack and the hazard parameters read. No parsing
// here: YAML loading and validation live with the rest of the configuration in io/.

#include <optional>
#include <string>
#include <vector>

#include "hazmap/core/enum_names.hpp"

namespace hazmap {

/// The update rules, in the registry's order (rules/rule_registry.hpp: each kind's struct,
/// its name rule_name(kind), and its YAML name).
enum class RuleKind { bananas, kalman, omg, ccm };

/// map.insertion (SPEC 5): every point into every layer, or into the finest layer holding
/// it with the coarser layers' covered cells pooled from their children.
enum class Insertion { all_layers, finest_then_pool };
template <>
struct EnumNames<Insertion> {
  static constexpr const char* names[] = {"all_layers", "finest_then_pool"};
};

/// CCM point weighting (SPEC 4, rules.ccm.weighting).
enum class CcmWeighting { constant, trace, det };
template <>
struct EnumNames<CcmWeighting> {
  static constexpr const char* names[] = {"constant", "trace", "det"};
};

/// hazard.roughness: the piecewise-constant kernel statistic (SPEC 8.1).
enum class RoughnessStatistic { range, detrended };
template <>
struct EnumNames<RoughnessStatistic> {
  static constexpr const char* names[] = {"range", "detrended"};
};

/// When a wheel ring cut short proves from its exact samples' plane (WheelRing,
/// hazard.partial_ring_proof): never; only when every missing sample lies where the
/// stereo pair has never looked (view_edge: SensorView); or always. The YAML names keep
/// the key's earlier boolean spelling.
enum class PartialRingProof { off, view_edge, any };
template <>
struct EnumNames<PartialRingProof> {
  static constexpr const char* names[] = {"false", "view_edge", "true"};
};

// A setting the user may leave to the program is a std::optional: empty is YAML's `auto`
// (derived from other settings, or measured), resolved once where it is used
// (hazard/hazard_params.hpp, gate_std_m, create_stereo_matcher, StereoFrontEnd).

struct LayerHazardConfig {
  int kernel = 5;                    ///< roughness kernel diameter in cells (odd)
  /// auto: derived as (kernel - 1) r tan(max_slope).
  std::optional<double> roughness_threshold_m;
  /// Smallest obstacle the layer vouches for (SPEC 8.1-8.4); auto: derived (CCM 0.75 r,
  /// piecewise constant: its roughness threshold).
  std::optional<double> h_min_m;
  std::optional<double> rho_max_m2;  ///< CCM roughness threshold; auto: h_min^2 / 16
};

struct LayerConfig {
  double resolution_m = 0.01;
  int size = 128;  ///< cells per side, even
  RuleKind rule = RuleKind::kalman;
  /// SPEC 4 gating: drop points whose lateral std exceeds max_std_ratio * r / sqrt(12);
  /// 0 off, auto: rules.ccm.max_std_ratio.
  std::optional<double> max_std_ratio;
  /// CCM (issue 34): a cell whose points spread over at least this share of it (kappa)
  /// has a plane for its own tests when some frame's disparity image saw all of it
  /// without a hole (hazard/hole_marker.hpp); 0: off, only rules.ccm.min_coverage.
  double hole_free_coverage = 0.0;
  LayerHazardConfig hazard;
};

struct MapConfig {
  Insertion insertion = Insertion::all_layers;
  std::vector<LayerConfig> layers;
};

/// Kalman's settings are the rule's own configuration (rules/kalman.hpp: KalmanRule::Config).
struct KalmanConfig {
  double time_inflation_m2 = 1.0e-6;  ///< q added to var once per frame [m^2]
  double min_variance_m2 = 1.0e-6;    ///< convergence floor [m^2]
  double gate_sigma = 0.0;            ///< SPEC 4 consistency gate (0 = off)
};

/// OMG's settings are the rule's own configuration (rules/omg.hpp: OmgRule::Config).
struct OmgConfig {
  double max_weight = 1.0e7;  ///< S cap [1/m^2]
  double decay = 1.0;         ///< S *= decay once per frame
  double gate_sigma = 0.0;  ///< SPEC 4 consistency gate (0 = off)
};

/// CCM's settings are the rule's own configuration (rules/ccm.hpp: CcmRule::Config extends
/// it with the slope its layer derives from hazard.max_slope_deg).
struct CcmConfig {
  CcmWeighting weighting = CcmWeighting::constant;  ///< point weights (MapPoints, before the rule)
  bool full_plane = true;     ///< use Sxy (SPEC 6.4); false: the thesis' 9-float forms
  double max_weight = 500;    ///< W_l: weight cap applied once per frame
  int min_points = 10;        ///< evaluable needs at least this many points
  double min_coverage = 0.8;  ///< evaluable needs kappa >= this
  double max_std_ratio = 0.0; ///< SPEC 4 lateral gate of layers without their own (0 off)
};

struct RulesConfig {
  KalmanConfig kalman;
  OmgConfig omg;
  CcmConfig ccm;
};

struct HazardConfig {
  double max_slope_deg = 20.0;
  double wheelbase_m = 0.30;
  double min_kernel_fill = 0.5;  ///< fraction of kernel cells that must be observed
  /// Piecewise-constant kernel statistic (SPEC 8.1): range (max - min of the heights,
  /// the thesis') or detrended (max - min of the residuals from the kernel's
  /// least-squares plane, with the wheel ring's vehicle-slope test taking over slopes).
  RoughnessStatistic roughness = RoughnessStatistic::range;
  /// CCM: slope evidence from one axis of a partly covered cell needs that axis' coverage
  /// (points' variance along it over r^2/12; a strip w wide has (w / r)^2) at least this:
  /// 0.1, the axis spans a third of the cell.
  double min_axis_coverage = 0.1;
  double k_sigma = 3.0;          ///< SPEC 8: hazard when s - k sigma > T, traversable when s + k sigma <= T
  std::optional<double> critical_height_m;   ///< SPEC 8.4; auto: the finest layer's h_min
  std::optional<double> footprint_radius_m;  ///< SPEC 8.5; auto: wheelbase / 2
  /// Side of the fused/footprint maps; auto: the largest layer's extent.
  std::optional<double> fused_extent_m;
  /// Fused map (issue 34): a finer layer's proof of traversability outweighs a coarser
  /// layer's hazard on the fine cell (HazardFusion::set_finer_proof); false: SPEC 8.4.
  bool finer_proof = false;
  /// Wheel ring (issue 34): when a ring cut short proves from its exact samples' plane
  /// (WheelRing). `any` is unsafe under low sun: the missing part of a ring is often the
  /// rock that hid it, and rim cells with ground-level heights were proven; `view_edge`
  /// excuses only samples the cameras never looked at (docs/hazards.md).
  PartialRingProof partial_ring_proof = PartialRingProof::off;
  /// Wheel ring (issue 34): a sample this layer has not measured is taken from the next
  /// coarser layer's plane where that layer measured it (HazardStage, CoarseRingFill).
  bool coarse_ring_fill = false;
  /// Footprint map (issue 34): a cell under the body that is unknown only because its own
  /// wheel ring was not measured (every other test proved it) counts as clear; the
  /// centre's cell must be proven, its ring included (HazardFusion::footprint).
  bool footprint_centre_ring = false;
  /// Fused map (issue 34): no proof within this distance [m] of a fused hazard cell
  /// (HazardFusion::set_proof_margin); 0: off.
  double proof_margin_m = 0.0;
  /// Hole-free test (map.layers.N.hole_free_coverage): a pixel's disparity within this of
  /// the cell's level plane [px] saw its ground; off by more, the frame does not judge
  /// that quarter of the cell.
  double hole_free_tolerance_px = 1.0;
  /// SPEC 8.6: re-classify only the cells whose result can have changed (equal to a full
  /// pass; false: every cell of every layer every frame, for comparison).
  bool incremental = true;
};

/// What the map core reads of a run's configuration; io/config.hpp's Config extends it
/// with the stereo, sensor, pose-uncertainty and output sections.
struct CoreConfig {
  MapConfig map;
  RulesConfig rules;
  HazardConfig hazard;
};

}  // namespace hazmap
