#pragma once
// One hazard classifier per layer, chosen once from the layer's rule family (SPEC 8):
// piecewise-constant layers (Bananas, Kalman, OMG) by their roughness kernel, CCM layers
// by their plane tests; both add the step-above-the-wheel-ring test on layers finer than
// the wheelbase. Every test follows Evidence's rule (evidence.hpp).

#include <memory>

#include "hazmap/hazard/hazard_params.hpp"
#include "hazmap/hazard/roughness_filter.hpp"
#include "hazmap/hazard/wheel_ring.hpp"
#include "hazmap/map/layer.hpp"

namespace hazmap {

/// Intermediate grids a classifier leaves for output and inspection.
struct HazardDiagnostics {
  DenseGrid kernel_range;  ///< piecewise constant: max - min in the kernel [m]
  DenseGrid kernel_sigma;  ///< its standard deviation [m]
  DenseGrid kernel_fill;   ///< observed fraction of the kernel
  /// Detrended kernels only (empty otherwise): tan of the kernel plane's inclination and
  /// its standard deviation.
  DenseGrid kernel_slope;
  DenseGrid kernel_slope_sigma;
};

class HazardClassifier {
 public:
  explicit HazardClassifier(const LayerHazardParams& params)
      : params_(params), ring_(params.wheelbase_m / 2.0, params.k_sigma) {}
  virtual ~HazardClassifier() = default;

  /// Classifies every cell of `grids` (a layer's export) into `hazard` (HazardClass),
  /// giving `hazard` and the diagnostics the layer's geometry.
  void classify(const LayerGrids& grids, DenseGrid& hazard, HazardDiagnostics& diagnostics);

  /// Classifies the cells of `region` only (SPEC 8.6) and leaves every other cell as it
  /// is. `hazard` and the diagnostics must have the layer's geometry already: an earlier
  /// classification of this window, shifted with it (DenseGrid::shift). A cell's result
  /// is the same as in a whole-layer classification.
  virtual void classify(const LayerGrids& grids, const GridRect& region, DenseGrid& hazard,
                        HazardDiagnostics& diagnostics) = 0;

  /// How far a cell's result reads, in cells along rows and columns (kernel, wheel ring):
  /// it can change only where a cell at most this far away changed (SPEC 8.6).
  virtual int reach_cells() const = 0;

  const LayerHazardParams& params() const { return params_; }

  /// A diagnostic pass (issue 34; `output.unknown_reasons`, for `hazmap evaluate`): a
  /// whole-layer classification of `grids` that writes into `reasons` (given the layer's
  /// geometry) the UnknownReason bits of each unknown cell, 0 at known cells. Separate
  /// from classify() so that the per-frame path writes no such grid; it allocates.
  void explain(const LayerGrids& grids, DenseGrid& reasons);

 protected:
  /// Records a cell's reasons when explain() asked for them.
  void record(int row, int col, const Evidence& ev) {
    if (reasons_) reasons_->at(row, col) = ev.result() == HazardClass::unknown ? ev.reasons() : 0;
  }
  void record(int row, int col, std::uint16_t reasons) {
    if (reasons_) reasons_->at(row, col) = reasons;
  }

  /// Gives the diagnostics the geometry of `height` before a whole-layer classification.
  virtual void reset_diagnostics(const DenseGrid& /*height*/, HazardDiagnostics& /*diag*/) const {}

  LayerHazardParams params_;
  WheelRing ring_;
  DenseGrid* reasons_ = nullptr;  ///< set during explain() only
};

/// SPEC 8.1 + 8.3: roughness kernel and step above the ring, on cell heights.
class PiecewiseConstantClassifier final : public HazardClassifier {
 public:
  explicit PiecewiseConstantClassifier(const LayerHazardParams& params);
  using HazardClassifier::classify;
  void classify(const LayerGrids& grids, const GridRect& region, DenseGrid& hazard,
                HazardDiagnostics& diag) override;
  int reach_cells() const override;

 private:
  void reset_diagnostics(const DenseGrid& height, HazardDiagnostics& diag) const override;

  /// The observed height nearest the ring sample in cell (row, col) (itself or one of its
  /// 8 neighbours, with the lever as extra variance); unknown if none.
  RingSample ring_sample(const LayerGrids& g, int row, int col, double tan_slope) const;

  RoughnessFilter filter_;
  int kernel_cells_ = 0;
  std::vector<double> kernel_k_;  ///< kernel_k_sigma(k, n) for n observed kernel cells
};

/// SPEC 8.2 + 8.3: roughness over noise, rock face, vehicle slope, step above the ring, on
/// the cells' planes.
class PlaneClassifier final : public HazardClassifier {
 public:
  using HazardClassifier::HazardClassifier;
  using HazardClassifier::classify;
  void classify(const LayerGrids& grids, const GridRect& region, DenseGrid& hazard,
                HazardDiagnostics& diag) override;
  int reach_cells() const override;

  /// Sub-cell height of the plane surface at W point (x, y) and its variance (exact): the
  /// holding cell's plane, or if that cell is not evaluable the plane of its nearest
  /// evaluable neighbour extrapolated to the point; failing both, on a known cell its
  /// mu_z with the published and sensor variance (known, not exact: evidence only);
  /// unknown outside the grid or on an empty cell.
  RingSample surface_at(const LayerGrids& grids, double x_m, double y_m) const;

 private:
  /// A cell's noise statistics: its roughness rho, the sensor part of it, the residual
  /// variance about the plane and the number of points it rests on.
  struct CellNoise {
    double rho, sensor, res_var, n_eff;
  };
  CellNoise cell_noise(const LayerGrids& g, int row, int col) const;
  /// The evaluable cell (row, col)'s plane at (x, y) with its prediction variance.
  RingSample plane_sample(const LayerGrids& g, int row, int col, double x_m, double y_m) const;
  /// The wheel ring's samples around cell (row, col)'s centre (surface_at each).
  void ring_around(const LayerGrids& g, int row, int col,
                   RingSample (&s)[WheelRing::kSamples]) const;
};

std::unique_ptr<HazardClassifier> make_hazard_classifier(const LayerHazardParams& params);

}  // namespace hazmap
