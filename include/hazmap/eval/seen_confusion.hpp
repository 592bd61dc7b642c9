#pragma once
// "Does the map see?" (issue 34, SPEC 10): over the ground-truth cells the cameras have
// seen so far, a confusion table per map, and why its unknown cells stayed unknown.
//
// Seen: a GT pixel is seen from the first frame in which a left-camera depth pixel (the
// simulator's `--depth` output: Z in the left camera, NaN where no terrain) with
// 0 < Z <= stereo.z_max falls in it, the depth pixel's point placed in W with the true
// pose. SeenMap keeps that first frame's index per GT pixel (never: -1), so a written
// frame f sees the pixels whose index is <= f.
//
// Confusion, per map and frame over seen GT pixels inside the map's window (optionally
// within R of the rover):
//   GT free (obstacle height 0)        -> traversable / unknown / hazard
//   GT obstacle (height >= h_min)      -> hazard / unknown / traversable
//   GT tall obstacle (>= 2 h_min)      -> the same (issue 34's rock target)
// Obstacles lower than h_min are scored neither way (as SPEC 10's missed / false alarm).
// For the footprint map the truth is the GT dilated by the footprint radius
// (dilate_obstacles) and a pixel counts as seen once every GT pixel within that radius is
// (SeenMap::whole_disc): "the whole footprint seen".
//
// Reasons: each unknown pixel's UnknownReason bits (hazard/unknown_reason.hpp), from the
// run's L<i>_unknown_reason grids (`output.unknown_reasons`); for the fused map
// fused_unknown_reasons combines the layers'. Counted per truth class: `any` (the bit is
// set) and `sole` (the only bit set, i.e. what alone kept the pixel unknown).

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "hazmap/core/types.hpp"
#include "hazmap/eval/metrics.hpp"
#include "hazmap/hazard/unknown_reason.hpp"
#include "hazmap/map/dense_grid.hpp"

namespace hazmap::eval {

/// A pinhole camera as the simulator renders depth: K with OpenCV's pixel convention
/// (pixel centres at integer u, v), optional Brown-Conrady distortion (k1 k2 p1 p2 k3).
struct DepthCamera {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::vector<double> distortion;  ///< empty or OpenCV order
};

/// Seen by the stereo pair within the layers' lateral gate (issue 34: what the sensor
/// could give a vouching layer at best): a depth pixel counts only if its point is in the
/// right image too (u - d >= `edge_margin_px`, d = f B / Z at the true depth: 0, or the
/// block size for bm and sgbm with stereo.match_left_border, which keep a match only with
/// a window to spare), outside the columns the block matchers leave blank (u >=
/// `blank_columns`: min_disparity + num_disparities for bm and sgbm without
/// match_left_border), and its stereo point's lateral standard deviation in W (largest of its
/// xy covariance, SPEC 4's sensor model) is within `max_std_m`: the gate of the most
/// permissive vouching layer (gate_std_m), beyond which no vouching layer takes it.
struct LateralGate {
  double baseline_m = 0.0;
  bool ray_model = false;  ///< sensor.model: ray (else axis)
  double pointing_px = 0.5, matching_px = 0.25;
  double max_std_m = 0.0;  ///< <= 0 or infinite: no gate
  int blank_columns = 0;
  int edge_margin_px = 0;
};

class SeenMap {
 public:
  /// Over `gt`'s geometry (rows, columns, resolution, centre), nothing seen.
  explicit SeenMap(const DenseGrid& gt);

  /// Marks the GT pixels holding the points of `depth` (CV_32FC1 Z [m] in the camera)
  /// with 0 < Z <= z_max_m, placed by T_W_C, as seen at `frame` unless seen earlier.
  /// With `gate`, only the pixels whose point passes it (LateralGate).
  void add_depth(const cv::Mat& depth, const DepthCamera& camera, const Pose3d& T_W_C,
                 double z_max_m, int frame, const LateralGate* gate = nullptr);

  /// The first frame index that saw pixel (row, col); -1 never.
  int first(int row, int col) const { return first_[static_cast<size_t>(row) * cols_ + col]; }
  bool seen(int row, int col, int frame) const {
    const int f = first(row, col);
    return f >= 0 && f <= frame;
  }
  /// The frame from which every pixel within `radius_m` (pixel centres compared, as
  /// dilate_obstacles) of each pixel is seen; -1 where one never is (or lies off the grid).
  SeenMap whole_disc(double radius_m) const;
  /// The frame from which each pixel and the pixels under `samples` points evenly spaced
  /// on the circle of `radius_m` about it (a wheel ring's samples, the first at +x) are
  /// seen; -1 where one never is (or lies off the grid).
  SeenMap with_ring(double radius_m, int samples) const;

  int rows() const { return rows_; }
  int cols() const { return cols_; }

 private:
  SeenMap() = default;
  DenseGrid geometry_;  ///< values empty
  int rows_ = 0, cols_ = 0;
  std::vector<int> first_;
};

/// Truth classes of the confusion table.
enum SeenTruth { kTruthFree = 0, kTruthHazard = 1, kTruthTall = 2 };

struct SeenSums {
  /// [truth][label], label = HazardClass (0 unknown, 1 traversable, 2 hazard): GT pixels.
  std::size_t count[3][3] = {};
  /// Unknown pixels per reason bit, [truth][bit]: the bit set / the only bit set.
  std::size_t reason_any[3][kUnknownReasonCount] = {};
  std::size_t reason_sole[3][kUnknownReasonCount] = {};
  std::size_t reason_unrecorded[3] = {};  ///< unknown pixels without a reason grid or bits
  double pixel_area_m2 = 0.0;

  SeenSums& operator+=(const SeenSums& o);
  std::size_t total(int truth) const { return count[truth][0] + count[truth][1] + count[truth][2]; }
  /// count[truth][label] / total(truth); NaN when there is no such pixel.
  double fraction(int truth, int label) const;
  double area_m2(int truth) const { return static_cast<double>(total(truth)) * pixel_area_m2; }
};

/// Scores one map's hazard classes (`hazard`, in the map frame) over the GT pixels seen
/// at `frame` (and, with `near`, whose centre lies in it), against `gt` (obstacle
/// heights; h_min_m > 0). `reasons`: the map's UnknownReason bits on `hazard`'s geometry,
/// or null. Throws Error when `seen` and `gt` differ in size or h_min <= 0.
SeenSums score_seen(const DenseGrid& hazard, const DenseGrid* reasons, const GroundTruth& gt,
                    const SeenMap& seen, int frame, const Pose3d& T_map_W, double h_min_m,
                    const NearRegion* near = nullptr);

/// The figures of SeenSums by name, for CSV columns and JSON keys (areas in m^2, the rest
/// fractions): free_m2, free_traversable, free_unknown, free_hazard, the same for hazard_
/// and tall_ (hazard_hazard ... ), then per reason unknown_free_<reason> and
/// unknown_free_<reason>_sole: the share of the free pixels left unknown that have the
/// reason / have it alone. Always the same names in the same order.
std::vector<std::pair<std::string, double>> seen_fields(const SeenSums& sums);

/// One layer's part in the fused map's reasons.
struct ReasonLayer {
  const DenseGrid* hazard = nullptr;
  const DenseGrid* reasons = nullptr;  ///< may be null (no L<i>_unknown_reason grid)
  double h_min_m = 0.0;
};

/// Why each unknown cell of the fused map (SPEC 8.4) is unknown: the bits of every
/// vouching layer (h_min <= critical) that covers the cell and calls it unknown,
/// kReasonNoVouchingLayer where a layer with a larger h_min calls it traversable, and
/// kReasonOutside where no vouching layer covers it. 0 at known cells.
DenseGrid fused_unknown_reasons(const std::vector<ReasonLayer>& layers, double critical_height_m,
                                const DenseGrid& fused);

}  // namespace hazmap::eval
