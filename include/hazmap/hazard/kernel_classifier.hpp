#pragma once
// The piecewise-constant family's classifier (SPEC 8.1 + 8.3; Bananas, Kalman, OMG
// layers): each cell's roughness kernel statistics (RoughnessFilter) and wheel ring,
// judged by the family's list of hazard tests (PiecewiseConstantTests below).

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

#include "hazmap/hazard/hazard_classifier.hpp"
#include "hazmap/hazard/kernel_tests.hpp"
#include "hazmap/hazard/ring_tests.hpp"
#include "hazmap/hazard/roughness_filter.hpp"

namespace hazmap {

/// What a piecewise-constant layer's tests read of cell (row, col): its height, its
/// kernel's statistics (HazardDiagnostics) and its wheel ring, sampled on first use.
class KernelCell {
 public:
  KernelCell(const LayerGrids& g, const HazardDiagnostics& d, const WheelRing& w, int r, int c,
             const int* ring_dr, const int* ring_dc, double tan_slope,
             const RingFallback* fallback = nullptr, const DenseGrid* viewed = nullptr)
      : grids(g), diag(d), wheel(w), row(r), col(c), z(g.height.at(r, c)),
        ring_dr_(ring_dr), ring_dc_(ring_dc), tan_slope_(tan_slope), fallback_(fallback),
        viewed_(viewed) {}

  const LayerGrids& grids;
  const HazardDiagnostics& diag;
  const WheelRing& wheel;
  const int row, col;
  const float z;  ///< the cell's height, NaN where unobserved
  bool kernel_complete = false;  ///< the cell observed, the kernel filled enough
  double range_k = 0;            ///< the kernel range's hazard-side k (kernel_k_sigma)

  float range() const { return diag.kernel_range.at(row, col); }
  float range_sigma() const { return diag.kernel_sigma.at(row, col); }
  float kernel_slope() const { return diag.kernel_slope.at(row, col); }
  float kernel_slope_sigma() const { return diag.kernel_slope_sigma.at(row, col); }
  double step_variance() const { return grids.variance.at(row, col); }

  /// The wheel ring's samples: for each, the cell holding the sample point, or if it is
  /// unobserved (a fine layer has holes) the nearest observed of its 8 neighbours, whose
  /// height stands d away from the point, which ground up to max_slope can shift by
  /// d tan(max_slope) (added as variance); failing both, the fallback's sample at the
  /// holding cell's centre, if there is a fallback.
  const RingSample (&ring() const)[WheelRing::kSamples] {
    if (!ring_ready_) {
      for (int k = 0; k < WheelRing::kSamples; ++k) {
        const int r = row + ring_dr_[k], c = col + ring_dc_[k];
        ring_[k] = sample(r, c);
        if (!ring_[k].known && fallback_)
          ring_[k] = fallback_->at(grids.height.x_of_col(c), grids.height.y_of_row(r));
        ring_[k].unseen = !ring_[k].exact && detail::outside_view(viewed_, r, c);
      }
      ring_ready_ = true;
    }
    return ring_;
  }

 private:
  RingSample sample(int row0, int col0) const {
    const DenseGrid& h = grids.height;
    const auto cells2 = [&](int r, int c) {
      return double((r - row0) * (r - row0) + (c - col0) * (c - col0));
    };
    int r = 0, c = 0;
    if (!detail::nearest_in_3x3(
            h, row0, col0, [&](int rr, int cc) { return !std::isnan(h.at(rr, cc)); }, cells2, &r,
            &c))
      return RingSample{};
    const double lever2 = cells2(r, c) * h.resolution_m * h.resolution_m * tan_slope_ * tan_slope_;
    return {h.at(r, c), grids.variance.at(r, c) + lever2, true, true};
  }

  const int* ring_dr_;
  const int* ring_dc_;
  double tan_slope_;
  const RingFallback* fallback_;
  const DenseGrid* viewed_;
  mutable bool ring_ready_ = false;
  mutable RingSample ring_[WheelRing::kSamples];
};

/// The piecewise-constant family's tests, in the order they run.
using PiecewiseConstantTests = HazardTests<KernelRoughness, KernelFace, RingSlope, RingStep>;

/// Classifies a piecewise-constant layer with the list `Tests` (a HazardTests).
template <class Tests>
class KernelFamilyClassifier final : public HazardClassifier {
 public:
  explicit KernelFamilyClassifier(const LayerHazardParams& params)
      : HazardClassifier(params), tests_(params) {
    filters_.resize(1);
    filters_[0].set_detrended(params.detrended_roughness);
    for (int w : kernel_half_widths(params.kernel)) kernel_cells_ += 2 * w + 1;
    for (int n = 0; n <= kernel_cells_; ++n) kernel_k_.push_back(kernel_k_sigma(params.k_sigma, n));
  }
  using HazardClassifier::classify;

  void set_parallel(const ParallelFor* pool) override {
    HazardClassifier::set_parallel(pool);
    // Two parts per thread, so that a thread done early takes another; each its filter.
    filters_.resize(pool ? static_cast<std::size_t>(2 * pool->threads()) : 1);
    for (RoughnessFilter& f : filters_) f.set_detrended(params_.detrended_roughness);
  }

  void classify(const LayerGrids& g, const GridRect& region, DenseGrid& hazard,
                HazardDiagnostics& diag) override {
    const GridRect cells = region.clipped(g.height.rows, g.height.cols);
    if (cells.empty()) return;
    ring_offsets(g.height.resolution_m, ring_dr_, ring_dc_);  // read by every part
    // Bands of rows on the pool: a cell's tests read only its own kernel statistics
    // (written by its band's filter) and the layer's grids, so bands are independent.
    const int rows = cells.row1 - cells.row0;
    const int parts = std::clamp(rows / kRowsPerPart, 1, static_cast<int>(filters_.size()));
    parallel_for(pool_, parts, [&](int begin, int end) {
      for (int k = begin; k < end; ++k) {
        const EvenPart part = even_part(rows, parts, k);
        GridRect band = cells;
        band.row0 = cells.row0 + part.begin;
        band.row1 = cells.row0 + part.end;
        classify_band(g, band, hazard, diag, filters_[static_cast<std::size_t>(k)]);
      }
    });
  }

  /// The kernel's half width, and a ring sample's cell offset + 1 (it may come from a
  /// neighbour), as far as the enabled tests read.
  int reach_cells() const override {
    int dr[WheelRing::kSamples], dc[WheelRing::kSamples];
    ring_offsets(params_.resolution_m, dr, dc);
    int ring = 0;
    for (int k = 0; k < WheelRing::kSamples; ++k)
      ring = std::max({ring, std::abs(dc[k]) + 1, std::abs(dr[k]) + 1});
    return tests_.reach_cells(TestReach{ring});
  }

 private:
  /// The cell offset (row, col) that holds each wheel-ring sample: the sample point
  /// rounded to a cell centre.
  void ring_offsets(double resolution_m, int* dr, int* dc) const {
    for (int k = 0; k < WheelRing::kSamples; ++k) {
      dc[k] = static_cast<int>(std::lround(ring_.dx(k) / resolution_m));
      dr[k] = -static_cast<int>(std::lround(ring_.dy(k) / resolution_m));  // row 0 = max y
    }
  }

  void reset_diagnostics(const DenseGrid& h, HazardDiagnostics& diag) const override {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    diag.kernel_range.reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m, nan);
    diag.kernel_sigma.reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m, nan);
    diag.kernel_fill.reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m, 0.0f);
    if (params_.detrended_roughness) {
      diag.kernel_slope.reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m, nan);
      diag.kernel_slope_sigma.reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m, nan);
    }
  }

  /// Fewest rows worth a band of their own on the pool.
  static constexpr int kRowsPerPart = 8;

  /// classify() over `cells` (within the grid) with `filter`'s scratch.
  void classify_band(const LayerGrids& g, const GridRect& cells, DenseGrid& hazard,
                     HazardDiagnostics& diag, RoughnessFilter& filter) {
    const DenseGrid& h = g.height;
    const LayerHazardParams& p = params_;
    const bool detrended = p.detrended_roughness;
    filter.compute(h, g.variance, p.kernel, cells, diag.kernel_range, diag.kernel_sigma,
                   diag.kernel_fill, detrended ? &diag.kernel_slope : nullptr,
                   detrended ? &diag.kernel_slope_sigma : nullptr);
    const double tan_slope = std::tan(p.max_slope_rad);
    for (int row = cells.row0; row < cells.row1; ++row)
      for (int col = cells.col0; col < cells.col1; ++col) {
        hazard.at(row, col) = static_cast<float>(HazardClass::unknown);
        if (std::isnan(diag.kernel_range.at(row, col))) {  // kernel off the layer or empty
          record(row, col, kReasonNoHeight);
          continue;
        }
        KernelCell cell(g, diag, ring_, row, col, ring_dr_, ring_dc_, tan_slope, fallback_,
                        viewed_);
        const float fill = diag.kernel_fill.at(row, col);
        cell.kernel_complete = !std::isnan(cell.z) && fill >= p.min_kernel_fill;
        const int observed = static_cast<int>(std::lround(double(fill) * kernel_cells_));
        cell.range_k = kernel_k_[std::clamp(observed, 0, kernel_cells_)];
        Evidence ev(p.k_sigma);
        tests_.run(cell, ev);
        hazard.at(row, col) = static_cast<float>(ev.result());
        record(row, col, ev);
      }
  }

  Tests tests_;
  std::vector<RoughnessFilter> filters_;  ///< one per band (set_parallel); one without a pool
  int kernel_cells_ = 0;
  std::vector<double> kernel_k_;  ///< kernel_k_sigma(k, n) for n observed kernel cells
  /// Ring samples as cell offsets (the cell that holds each sample point).
  int ring_dr_[WheelRing::kSamples], ring_dc_[WheelRing::kSamples];
};

using PiecewiseConstantClassifier = KernelFamilyClassifier<PiecewiseConstantTests>;
extern template class KernelFamilyClassifier<PiecewiseConstantTests>;

}  // namespace hazmap
