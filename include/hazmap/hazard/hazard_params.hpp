#pragma once
// Every derived hazard parameter of a run, resolved once from the configuration
// (SPEC 8): each layer's h_min, roughness threshold and kernel, CCM thresholds, the
// fused map's critical height and the footprint radius. Pipeline, outputs and
// evaluation read them from here instead of re-deriving them.

#include <string>
#include <vector>

#include "hazmap/core/core_config.hpp"

namespace hazmap {

/// Which family of hazard tests a layer's rule supports.
enum class HazardFamily {
  piecewise_constant,  ///< Bananas, Kalman, OMG: roughness kernel (SPEC 8.1)
  plane,               ///< CCM: plane tests (SPEC 8.2)
};

HazardFamily hazard_family(RuleKind rule);

struct LayerHazardParams {
  HazardFamily family = HazardFamily::piecewise_constant;
  double resolution_m = 0.01;
  double h_min_m = 0.03;         ///< smallest obstacle this layer vouches for
  std::string h_min_source;      ///< how h_min was obtained ("hazard.h_min", "0.75 r", ...)
  double k_sigma = 3.0;
  double max_slope_rad = 0.349;
  double wheelbase_m = 0.30;
  PartialRingProof partial_ring_proof = PartialRingProof::off;  ///< hazard.partial_ring_proof
  /// Ring tests (vehicle slope, step above the ring; SPEC 8.2-8.3) apply to cells
  /// smaller than the wheelbase.
  bool ring_tests = true;
  // Piecewise constant (SPEC 8.1)
  int kernel = 5;
  double roughness_threshold_m = 0.025;
  double min_kernel_fill = 0.5;
  /// Roughness from the residuals of the kernel's plane, with the wheel ring's
  /// vehicle-slope test (SPEC 8.2) for slopes: hazard.roughness = detrended, on layers
  /// finer than the wheelbase (coarser ones have no ring and keep the range).
  bool detrended_roughness = false;
  /// Detrended: tan of a kernel plane rising h_min within the kernel's radius (a face).
  double kernel_face_tan = 0.0;
  // CCM (SPEC 8.2)
  double rho_max_m2 = 5.6e-5;
  double tan_face = 0.75;        ///< tan of the rock-face inclination, h_min / r
  /// A partly covered cell's axis gives slope evidence only if its coverage
  /// lambda / (r^2 / 12) reaches this (hazard.min_axis_coverage).
  double min_axis_coverage = 0.0;
  int min_points = 10;
  /// CCM: a cell spread over at least this share is evaluable when a frame's disparity
  /// image saw it whole (map.layers.N.hole_free_coverage; HoleMarker); 0 off.
  double hole_free_coverage = 0.0;
  double hole_free_tolerance_px = 1.0;  ///< hazard.hole_free_tolerance (HoleMarker)
  /// Points a CCM cell's statistics can count on at most (its weight cap, for constant
  /// weights: older points are discounted beyond it); infinity otherwise.
  double max_effective_count = 1e300;
  /// Added to a piecewise-constant cell's variance where it is published (SPEC 10: every
  /// published height within 3 sigma at any point of its cell): (r^2/6) tan^2(max_slope),
  /// the spread over the cell of ground up to max_slope about the points' centroid, itself
  /// anywhere in the cell. The classifier uses the estimate's variance. 0 for CCM, whose
  /// planes (or published variance of cells without one) carry it already.
  double published_extra_variance_m2 = 0.0;
};

struct HazardParams {
  std::vector<LayerHazardParams> layers;  ///< finest first
  double critical_height_m = 0.03;        ///< SPEC 8.4
  std::string critical_height_source;     ///< how it was obtained
  double footprint_radius_m = 0.15;       ///< SPEC 8.5
  double fused_extent_m = 10.24;          ///< side of the fused and footprint maps
  bool finer_proof = false;               ///< hazard.finer_proof (HazardFusion)
  bool coarse_ring_fill = false;          ///< hazard.coarse_ring_fill (HazardStage)
  bool footprint_centre_ring = false;     ///< hazard.footprint_centre_ring (HazardFusion)
  double proof_margin_m = 0.0;            ///< hazard.proof_margin (HazardFusion)
};

/// From the map core's configuration; a run's Config (io/config.hpp) is one.
LayerHazardParams resolve_layer_hazard(const LayerConfig& layer, const CoreConfig& config);
HazardParams resolve_hazard_params(const CoreConfig& config);

}  // namespace hazmap
