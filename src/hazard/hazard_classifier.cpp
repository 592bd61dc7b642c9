#include "hazmap/hazard/hazard_classifier.hpp"

#include "hazmap/hazard/kernel_classifier.hpp"
#include "hazmap/hazard/plane_classifier.hpp"

namespace hazmap {

// The shipped lists, compiled once here (their headers declare them extern).
template class KernelFamilyClassifier<PiecewiseConstantTests>;
template class PlaneFamilyClassifier<PlaneTests, FewPointsTests>;

void HazardClassifier::classify(const LayerGrids& g, DenseGrid& hazard, HazardDiagnostics& diag) {
  const DenseGrid& h = g.height;
  hazard.reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m,
               static_cast<float>(HazardClass::unknown));
  reset_diagnostics(h, diag);
  if (ring_only_) ring_only_->reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m, 0.0f);
  classify(g, GridRect::full(h.rows, h.cols), hazard, diag);
}

void HazardClassifier::explain(const LayerGrids& g, DenseGrid& reasons) {
  const DenseGrid& h = g.height;
  reasons.reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m, 0.0f);
  DenseGrid hazard;
  HazardDiagnostics diag;
  reasons_ = &reasons;
  DenseGrid* ring_only = ring_only_;  // the stage's grid is not this pass's
  ring_only_ = nullptr;
  classify(g, hazard, diag);
  reasons_ = nullptr;
  ring_only_ = ring_only;
}

std::unique_ptr<HazardClassifier> make_hazard_classifier(const LayerHazardParams& params) {
  if (params.family == HazardFamily::plane) return std::make_unique<PlaneClassifier>(params);
  return std::make_unique<PiecewiseConstantClassifier>(params);
}

}  // namespace hazmap
