#include "hazmap/hazard/hazard_params.hpp"

#include <algorithm>
#include <cmath>

#include "hazmap/rules/rule_registry.hpp"

namespace hazmap {

HazardFamily hazard_family(RuleKind rule) {
  return rule_info(rule).has_plane ? HazardFamily::plane : HazardFamily::piecewise_constant;
}

LayerHazardParams resolve_layer_hazard(const LayerConfig& layer, const CoreConfig& config) {
  const HazardConfig& hz = config.hazard;
  LayerHazardParams p;
  p.family = hazard_family(layer.rule);
  p.resolution_m = layer.resolution_m;
  p.k_sigma = hz.k_sigma;
  p.max_slope_rad = hz.max_slope_deg * M_PI / 180.0;
  p.wheelbase_m = hz.wheelbase_m;
  p.ring_tests = layer.resolution_m < hz.wheelbase_m;
  p.kernel = layer.hazard.kernel;
  p.min_kernel_fill = hz.min_kernel_fill;
  p.detrended_roughness = hz.roughness == RoughnessStatistic::detrended && p.ring_tests;
  // SPEC 8.1: cell heights sit at cell centres, (D - 1) r apart across the kernel.
  p.roughness_threshold_m = layer.hazard.roughness_threshold_m.value_or(
      (p.kernel - 1) * layer.resolution_m * std::tan(p.max_slope_rad));
  if (layer.hazard.h_min_m) {
    p.h_min_m = *layer.hazard.h_min_m;
    p.h_min_source = "hazard.h_min";
  } else if (p.family == HazardFamily::plane) {
    p.h_min_m = 0.75 * layer.resolution_m;
    p.h_min_source = "0.75 r";
  } else {
    p.h_min_m = p.roughness_threshold_m;
    p.h_min_source = layer.hazard.roughness_threshold_m ? "roughness threshold"
                                                        : "derived roughness threshold";
  }
  p.kernel_face_tan = p.h_min_m / (0.5 * (p.kernel - 1) * layer.resolution_m);
  p.rho_max_m2 = layer.hazard.rho_max_m2.value_or(p.h_min_m * p.h_min_m / 16.0);
  p.tan_face = p.h_min_m / layer.resolution_m;
  p.min_axis_coverage = hz.min_axis_coverage;
  p.partial_ring_proof = hz.partial_ring_proof;
  p.min_points = config.rules.ccm.min_points;
  if (p.family == HazardFamily::plane) p.hole_free_coverage = layer.hole_free_coverage;
  p.hole_free_tolerance_px = hz.hole_free_tolerance_px;
  p.max_effective_count = config.rules.ccm.weighting == CcmWeighting::constant ? config.rules.ccm.max_weight : 1e300;
  if (p.family == HazardFamily::piecewise_constant) {
    const double t = std::tan(p.max_slope_rad);
    p.published_extra_variance_m2 = layer.resolution_m * layer.resolution_m / 6.0 * t * t;
  }
  return p;
}

HazardParams resolve_hazard_params(const CoreConfig& config) {
  HazardParams p;
  double largest = 0.0;
  for (const LayerConfig& layer : config.map.layers) {
    p.layers.push_back(resolve_layer_hazard(layer, config));
    largest = std::max(largest, layer.size * layer.resolution_m);
  }
  p.critical_height_m = config.hazard.critical_height_m.value_or(
      p.layers.empty() ? 0.0 : p.layers.front().h_min_m);
  p.critical_height_source = config.hazard.critical_height_m
                                 ? "hazard.critical_height"
                                 : "critical height (finest layer's h_min)";
  p.footprint_radius_m = config.hazard.footprint_radius_m.value_or(config.hazard.wheelbase_m / 2.0);
  p.fused_extent_m = config.hazard.fused_extent_m.value_or(largest);
  p.finer_proof = config.hazard.finer_proof;
  p.coarse_ring_fill = config.hazard.coarse_ring_fill;
  p.footprint_centre_ring = config.hazard.footprint_centre_ring;
  p.proof_margin_m = config.hazard.proof_margin_m;
  return p;
}

}  // namespace hazmap
