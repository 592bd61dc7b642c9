#pragma once
// One layer of the map: a rolling ring buffer of cells updated by one rule. The
// type-erased interface is called once per frame and layer (never per point); the
// rule's per-point work is inlined in RollingLayer<Rule>::insert.

#include <cstdint>
#include <vector>

#include "hazmap/map/dense_grid.hpp"
#include "hazmap/map/grid_rect.hpp"
#include "hazmap/map/map_points.hpp"
#include "hazmap/map/moments.hpp"
#include "hazmap/map/point_chunk.hpp"
#include "hazmap/map/pose_uncertainty.hpp"
#include "hazmap/map/rolling_grid.hpp"
#include "hazmap/map/seen_whole.hpp"

namespace hazmap {

/// Everything a layer can tell about its window, in image order (row 0 = largest y).
/// Plane grids (slope, roughness, coverage, evaluable) are filled by CCM layers only and
/// left empty (rows = 0) otherwise.
struct LayerGrids {
  /// At the cell centre [m]; NaN unknown. CCM: its plane there when evaluable, else mu_z
  /// (SPEC 6.4).
  DenseGrid height;
  /// Height variance [m^2], inflated by pose uncertainty if enabled. Bananas: the sensor
  /// variance of the cell's last point; CCM: Szz/W, plus (r^2/12) tan^2(max_slope) on
  /// cells that are not evaluable (the tilt nobody measured, SPEC 6.4).
  DenseGrid variance;
  DenseGrid count;      ///< points behind the cell
  DenseGrid slope_x;    ///< dz/dx of the cell plane; NaN when not evaluable
  DenseGrid slope_y;    ///< dz/dy
  DenseGrid roughness;  ///< plane-normal variance rho [m^2]
  DenseGrid coverage;   ///< kappa
  /// 1 evaluable, 0 not, kEvaluableOwnCell: a plane for the cell's own tests only
  /// (map/seen_whole.hpp)
  DenseGrid evaluable;
  /// Mean measurement height variance Sigma_W(2,2) of the cell's points [m^2] (weighted
  /// like the points): the part of rho that is sensor noise (SPEC 8.2).
  DenseGrid noise_variance;
  /// Lateral covariance of the cell's points, S/W [m^2]: how well x and y are spread,
  /// for the uncertainty of the slopes.
  DenseGrid lateral_xx;
  DenseGrid lateral_yy;
  DenseGrid lateral_xy;
  /// Lateral-height covariance Sxz/W, Syz/W [m^2]: with the lateral covariance, the
  /// plane's slope along each principal axis, even where the other axis is unobserved.
  DenseGrid lateral_xz;
  DenseGrid lateral_yz;
};

/// Per-parent-cell pooled moments of a finer layer (finest_then_pool), indexed by the
/// parent's storage slot; allocated once.
struct PoolGrid {
  std::vector<Moments> cells;
};

/// Points a layer's SPEC 4 gates dropped in its last insertion (begin_insert resets).
struct GateCounts {
  /// Inside the window, lateral std above max_std_ratio * r / sqrt(12). In
  /// finest_then_pool mode a coarser layer also counts such points in its covered cells
  /// (the finer layer, whose gate is tighter, counts them too).
  std::size_t std_gate = 0;
  /// |z - mu| > gate_sigma sqrt(var + sigma_m^2) against a known cell (Kalman, OMG).
  std::size_t consistency_gate = 0;

  GateCounts& operator+=(const GateCounts& o) {
    std_gate += o.std_gate;
    consistency_gate += o.consistency_gate;
    return *this;
  }
};

class Layer {
 public:
  virtual ~Layer() = default;

  /// Rolls the window to the robot (clearing cells that left) and starts frame `frame`:
  /// the rule's per-frame ageing (Kalman inflation, OMG decay) counts from it.
  virtual void begin_frame(double robot_x_m, double robot_y_m, std::uint32_t frame) = 0;

  /// A frame's insertion: begin_insert, insert_chunk over consecutive chunks of the
  /// frame's points (so a chunk stays in cache while every layer reads it), end_insert
  /// (merges the frame into the touched cells). insert_chunk takes every point whose
  /// cell is inside the window (and not covered by the finer layer, in pooling mode) and
  /// returns how many it used.
  virtual void begin_insert() = 0;
  virtual std::size_t insert_chunk(const PointChunk& chunk) = 0;
  virtual void end_insert() = 0;
  /// What the gates dropped since the last begin_insert.
  virtual GateCounts gate_counts() const = 0;

  /// The whole frame at once (tests; LayerStack::insert shares chunks between layers).
  std::size_t insert(const MapPoints& points) {
    begin_insert();
    std::size_t used = 0;
    points.for_each_chunk([&](const PointChunk& chunk) { used += insert_chunk(chunk); });
    end_insert();
    return used;
  }

  /// Pooling (SPEC 5, 6.5): mark which cells are fully covered by the finer layer's
  /// window; a cell that becomes covered captures its current value as its prior.
  virtual void update_coverage(const RollingGrid& finer) = 0;
  /// Adds this (finer) layer's cells into `pool`, for the parent's covered cells only.
  virtual void pool_into(PoolGrid& pool, const Layer& parent) const = 0;
  /// Rebuilds covered cells as prior (+) pool.
  virtual void rebuild_covered(PoolGrid& pool) = 0;
  virtual bool covered(int slot) const = 0;

  /// Exports the window's grids (buffers reused). With `pose` the variance is inflated
  /// by the pose uncertainty added since each cell's last update. `seen_whole` (CCM
  /// layers): cells evaluable by a hole-free view as well (map/seen_whole.hpp).
  virtual void export_grids(LayerGrids& out, const PoseUncertainty* pose, double robot_x_m,
                            double robot_y_m, const SeenWhole* seen_whole = nullptr) const = 0;
  /// Re-exports the cells of `rect` (image order of the current window) only, for a frame
  /// that changed only them (SPEC 8.6). `out` must hold this window's grids already: an
  /// earlier export, shifted with the window since (DenseGrid::shift). No pose inflation:
  /// it changes every cell's variance, so those layers are exported whole.
  virtual void export_region(LayerGrids& out, const GridRect& rect,
                             const SeenWhole* seen_whole = nullptr) const = 0;
  /// Whether a cell's export changes from frame to frame without an update
  /// (Rule::ages_exports: Kalman time inflation).
  virtual bool ages_exports() const = 0;

  /// Moments of the cell holding global index (ix, iy) (empty if unknown or outside).
  virtual Moments cell_moments(CellIndex ix, CellIndex iy) const = 0;

  virtual const char* rule_name() const = 0;
  virtual bool has_plane() const = 0;
  virtual const RollingGrid& grid() const = 0;
};

}  // namespace hazmap
