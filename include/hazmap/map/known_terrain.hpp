#pragma once
// The terrain a map has already published, for visibility questions about new points
// (the stereo front end's occlusion check, point_cloud_builder.hpp): per layer, finest
// first, its height grid at cell centres (CCM: with the cell plane's slopes) and its
// height variance, as a frame's export left them (LayerGrids). A view: the grids are
// owned elsewhere and must outlive the queries; nothing is copied. prepare_near_field
// derives, for the region a camera's checked rays cover, the assumed heights of unseen
// cells and per-block bounds, in buffers it keeps and reuses.
// Thread safety: const queries may run concurrently; prepare_near_field and clear may not.

#include <limits>
#include <vector>

#include "hazmap/map/dense_grid.hpp"

namespace hazmap {

class KnownTerrain {
 public:
  /// Forgets every layer.
  void clear() {
    layers_.clear();
    fill_.rows = fill_.cols = 0;
    max_top_ = max_unseen_ = -std::numeric_limits<double>::infinity();
  }

  /// Adds a layer; call finest first. `height` at cell centres [m] (NaN unknown),
  /// `variance` [m^2] on the same grid (or empty: taken as 0), `slope_x`/`slope_y` the
  /// cell planes' dz/dx, dz/dy (or empty, or NaN per cell: the cell is flat). Layers
  /// without cells (height.rows == 0) are ignored. Throws Error when the grids differ in
  /// size.
  void add_layer(const DenseGrid& height, const DenseGrid& variance, const DenseGrid& slope_x,
                 const DenseGrid& slope_y);

  bool empty() const { return layers_.empty(); }
  /// Resolution of the finest layer [m]; 0 when empty.
  double finest_resolution_m() const { return layers_.empty() ? 0.0 : layers_.front().height->resolution_m; }

  /// Height of the terrain at W point (x, y) [m] and its variance [m^2]: from the finest
  /// layer whose cell there has a finite height (CCM: its plane at (x, y) when the slopes
  /// are finite, else the cell height). False, outputs untouched, when no layer knows.
  bool height_at(double x_m, double y_m, double* height_m, double* variance_m2) const;

  /// Prepares, for the region [x0, x1] x [y0, y1] of W (and a cell beyond; at most 4096
  /// cells a side) on the finest layer's cells (borders at multiples of its resolution,
  /// SPEC 1): max_top(), and the assumed heights unseen_height_at() reads: a
  /// cell nobody knows takes the highest point of the known cells within fill_m (rounded
  /// up to whole cells) of it in x and y (plane tops over their cells), as if the terrain
  /// seen next to it continued;
  /// none when no known cell is that near. Reuses its buffers; clear() forgets them.
  void prepare_near_field(double x0_m, double y0_m, double x1_m, double y1_m, double fill_m,
                          double k_sigma);
  /// Whether prepare_near_field ran since the last clear() (and found a layer).
  bool prepared() const { return fill_.rows > 0; }
  /// The assumed height [m] of an unseen cell at (x, y); false where the cell is known,
  /// outside the prepared region, or has no known cell within fill_m.
  bool unseen_height_at(double x_m, double y_m, double* height_m) const;
  /// Over the prepared region: the highest point of a known cell's plane plus k_sigma of
  /// its standard deviation [m] (-infinity when nothing is known). It bounds height_at +
  /// k_sigma sigma and unseen_height_at in the region.
  double max_top() const { return max_top_; }
  /// The highest assumed height of an unseen cell in the prepared region [m] (-infinity
  /// when none).
  double max_unseen_height() const { return max_unseen_; }

  /// Upper bounds of max_top() and max_unseen_height() over the axis-aligned box
  /// [x0, x1] x [y0, y1] (any order) inside the prepared region, from blocks of
  /// kBlockCells x kBlockCells cells; the whole region's bounds where the box leaves it.
  struct Levels {
    double top_m;     ///< height + k_sigma sigma of known cells
    double unseen_m;  ///< assumed heights of unseen cells
  };
  Levels max_levels_in(double x0_m, double y0_m, double x1_m, double y1_m) const;
  static constexpr int kBlockCells = 4;

 private:
  struct Layer {
    const DenseGrid* height;
    const DenseGrid* variance;
    const DenseGrid* slope_x;
    const DenseGrid* slope_y;
    double inv_resolution;  ///< 1 / resolution
    double x0_m, y1_m;      ///< W x of column 0's left edge, W y of row 0's top edge
  };
  /// The finest layer whose cell at (x, y) has a finite height, and that cell.
  const Layer* find(double x_m, double y_m, int* row, int* col) const;

  std::vector<Layer> layers_;
  DenseGrid fill_;                       ///< assumed heights of unseen cells (rows 0: none)
  /// Per block of kBlockCells^2 cells of fill_ (row-major, block_rows_ x block_cols_):
  /// the highest known top + k sigma, and the highest assumed height.
  std::vector<float> block_top_, block_unseen_;
  int block_rows_ = 0, block_cols_ = 0;
  std::vector<float> known_, row_max_;  ///< known plane tops, and the fill's row pass
  double max_top_ = -std::numeric_limits<double>::infinity();
  double max_unseen_ = -std::numeric_limits<double>::infinity();
};

}  // namespace hazmap
