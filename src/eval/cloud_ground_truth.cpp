#include "hazmap/eval/cloud_ground_truth.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include <Eigen/Dense>
#include <opencv2/imgproc.hpp>

#include "hazmap/core/error.hpp"
#include "hazmap/core/number_text.hpp"
#include "hazmap/eval/ground_truth.hpp"
#include "hazmap/io/atomic_file.hpp"

namespace hazmap {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

/// Least-squares plane z = a + b dx + c dy through points given relative to a centre;
/// returns a (the height at the centre) clamped to the points' z range, or their mean
/// when they are too few or too little spread to fix a plane.
class PlaneAtCenter {
 public:
  void add(double dx, double dy, double z) {
    const Eigen::Vector3d v(1.0, dx, dy);
    A_ += v * v.transpose();
    b_ += v * z;
    zmin_ = std::min(zmin_, z);
    zmax_ = std::max(zmax_, z);
  }
  double n() const { return A_(0, 0); }
  double value(double spread_floor_m2) const {
    const double n = A_(0, 0);
    const double mean = b_(0) / n;
    if (n < 3) return mean;
    // Lateral covariance of the points: a plane needs them spread along both axes.
    const double mx = A_(0, 1) / n, my = A_(0, 2) / n;
    Eigen::Matrix2d cov;
    cov << A_(1, 1) / n - mx * mx, A_(1, 2) / n - mx * my, A_(1, 2) / n - mx * my,
        A_(2, 2) / n - my * my;
    if (Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov).eigenvalues()(0) < spread_floor_m2)
      return mean;
    const Eigen::Vector3d x = A_.ldlt().solve(b_);
    if (!std::isfinite(x(0))) return mean;
    return std::clamp(x(0), zmin_, zmax_);
  }

 private:
  Eigen::Matrix3d A_ = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b_ = Eigen::Vector3d::Zero();
  double zmin_ = std::numeric_limits<double>::infinity();
  double zmax_ = -std::numeric_limits<double>::infinity();
};

std::string num(double v) { return printf_double(v, "%.9g"); }

}  // namespace

void validate(const CloudGroundTruthOptions& o) {
  check(std::isfinite(o.resolution_m) && o.resolution_m >= 1e-4 && o.resolution_m <= 100.0,
        "--resolution must be in [1e-4, 100] m");
  check(std::isfinite(o.fill_radius_m) && o.fill_radius_m <= 1000.0 * o.resolution_m,
        "--fill-radius must be finite and at most 1000 cells");
  check(std::isfinite(o.ground_radius_m) && o.ground_radius_m >= o.resolution_m &&
            o.ground_radius_m <= 1000.0 * o.resolution_m,
        "--ground-radius must be between one and 1000 cells");
  check(std::isfinite(o.ground_tolerance_m) && o.ground_tolerance_m >= 0.0,
        "--ground-tolerance must be >= 0");
  const bool crop = o.x0_m != 0.0 || o.x1_m != 0.0 || o.y0_m != 0.0 || o.y1_m != 0.0;
  check(!crop || (std::isfinite(o.x0_m) && std::isfinite(o.x1_m) && std::isfinite(o.y0_m) &&
                  std::isfinite(o.y1_m) && o.x0_m < o.x1_m && o.y0_m < o.y1_m),
        "--crop: expected x0 < x1 and y0 < y1");
}

namespace {

/// The cloud's points binned by grid cell (a counting sort): the points of cell k are
/// order[start[k]] .. order[start[k + 1] - 1].
struct CellBins {
  std::vector<std::size_t> start;
  std::vector<std::uint32_t> order;
  std::size_t points = 0;  ///< points inside the grid (or crop)
};

/// Bins the points inside the grid (or, with `crop`, inside [x0, x1] x [y0, y1]).
CellBins bin_points(const std::vector<Eigen::Vector3d>& points, const JdemGrid& H, bool crop,
                    double x0, double x1, double y0, double y1) {
  const int rows = H.rows, cols = H.cols;
  const double r = H.resolution_m;
  const double left_m = H.center_x_m - 0.5 * cols * r, bottom_m = H.center_y_m - 0.5 * rows * r;
  const std::size_t n_cells = static_cast<std::size_t>(rows) * cols;
  CellBins bins;
  std::vector<std::int64_t> cell_of(points.size(), -1);
  bins.start.assign(n_cells + 1, 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    if (crop && (p.x() < x0 || p.x() > x1 || p.y() < y0 || p.y() > y1)) continue;
    // Points on the grid's upper border belong to its last cell.
    const long long c = std::clamp<long long>(static_cast<long long>(std::floor((p.x() - left_m) / r)),
                                              0, cols - 1);
    const long long rb = std::clamp<long long>(
        static_cast<long long>(std::floor((p.y() - bottom_m) / r)), 0, rows - 1);
    cell_of[i] = static_cast<std::int64_t>((rows - 1 - rb) * cols + c);
    ++bins.start[static_cast<std::size_t>(cell_of[i]) + 1];
    ++bins.points;
  }
  check(bins.points > 0, "ground truth: no point of the cloud lies inside --crop");
  for (std::size_t k = 0; k < n_cells; ++k) bins.start[k + 1] += bins.start[k];
  bins.order.resize(bins.points);
  std::vector<std::size_t> fill(bins.start.begin(), bins.start.end() - 1);
  for (std::size_t i = 0; i < points.size(); ++i)
    if (cell_of[i] >= 0)
      bins.order[fill[static_cast<std::size_t>(cell_of[i])]++] = static_cast<std::uint32_t>(i);
  return bins;
}

/// Heights of the cells with points (a plane through them, at the cell centre); NaN in
/// the others. Returns the number of cells measured.
std::size_t measure_cells(const std::vector<Eigen::Vector3d>& points, const CellBins& bins,
                          double spread_floor, JdemGrid& H) {
  std::size_t measured = 0;
  for (int row = 0; row < H.rows; ++row)
    for (int col = 0; col < H.cols; ++col) {
      const std::size_t k = static_cast<std::size_t>(row) * H.cols + col;
      if (bins.start[k] == bins.start[k + 1]) {
        H.at(row, col) = kNaN;
        continue;
      }
      const Eigen::Vector2d c = cell_center_W(H, row, col);
      PlaneAtCenter plane;
      for (std::size_t j = bins.start[k]; j < bins.start[k + 1]; ++j) {
        const auto& p = points[bins.order[j]];
        plane.add(p.x() - c.x(), p.y() - c.y(), p.z());
      }
      H.at(row, col) = static_cast<float>(plane.value(spread_floor));
      ++measured;
    }
  return measured;
}

/// Gaps: a cell without points takes the plane through the measured points within
/// fill_radius of its centre, when they surround it (one in each quadrant). Returns the
/// number of cells filled.
std::size_t fill_gaps(const std::vector<Eigen::Vector3d>& points, const CellBins& bins,
                      double fill_radius, double spread_floor, JdemGrid& H) {
  const int rows = H.rows, cols = H.cols;
  const int reach = static_cast<int>(std::ceil(fill_radius / H.resolution_m));
  std::size_t filled_cells = 0;
  std::vector<float> filled = H.values;
  for (int row = 0; row < rows; ++row)
    for (int col = 0; col < cols; ++col) {
      if (!std::isnan(H.at(row, col))) continue;
      const Eigen::Vector2d c = cell_center_W(H, row, col);
      PlaneAtCenter plane;
      unsigned quadrants = 0;
      for (int rr = std::max(0, row - reach); rr <= std::min(rows - 1, row + reach); ++rr)
        for (int cc = std::max(0, col - reach); cc <= std::min(cols - 1, col + reach); ++cc) {
          const std::size_t k = static_cast<std::size_t>(rr) * cols + cc;
          for (std::size_t j = bins.start[k]; j < bins.start[k + 1]; ++j) {
            const auto& p = points[bins.order[j]];
            const double dx = p.x() - c.x(), dy = p.y() - c.y();
            if (dx * dx + dy * dy > fill_radius * fill_radius) continue;
            quadrants |= 1u << ((dx >= 0 ? 1 : 0) + (dy >= 0 ? 2 : 0));
            plane.add(dx, dy, p.z());
          }
        }
      if (quadrants == 0xFu) {
        filled[static_cast<std::size_t>(row) * cols + col] = static_cast<float>(plane.value(spread_floor));
        ++filled_cells;
      }
    }
  H.values = std::move(filled);
  return filled_cells;
}

/// Lower envelope: opening by a disc of radius k cells; unknown cells take no part (+inf
/// in the erosion; cells whose disc saw nothing, -inf in the dilation). The map is padded
/// by the radius so that discs may be centred beyond the scan's edge or in a shadow: then
/// the opening of a plane is the plane up to the edge, not lowered near it.
cv::Mat lower_envelope(JdemGrid& H, int k) {
  cv::Mat h(H.rows, H.cols, CV_32F, H.values.data());
  cv::Mat padded;
  cv::copyMakeBorder(h, padded, k, k, k, k, cv::BORDER_CONSTANT, cv::Scalar(FLT_MAX));
  cv::patchNaNs(padded, FLT_MAX);  // (cv::compare does not flag NaN)
  const cv::Mat disc = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * k + 1, 2 * k + 1));
  cv::Mat eroded, dilated;
  cv::erode(padded, eroded, disc);
  eroded.setTo(-FLT_MAX, eroded == FLT_MAX);
  cv::dilate(eroded, dilated, disc);
  return dilated(cv::Rect(k, k, H.cols, H.rows));
}

/// The 4-neighbours of cell i of a rows x cols grid.
struct Neighbours {
  int rows, cols;
  template <class F>
  void operator()(std::size_t i, F&& f) const {
    const int row = static_cast<int>(i / cols), col = static_cast<int>(i % cols);
    if (row > 0) f(i - cols);
    if (row + 1 < rows) f(i + cols);
    if (col > 0) f(i - 1);
    if (col + 1 < cols) f(i + 1);
  }
};

enum CellState : unsigned char { kUnknownCell = 0, kGroundCell = 1, kObstacleCell = 2 };

/// Obstacle cells reached from a ground cell through obstacle cells, in index order: the
/// cells the harmonic ground is solved for.
std::vector<std::size_t> reachable_obstacles(const std::vector<unsigned char>& state,
                                             const Neighbours& neighbours) {
  std::vector<std::size_t> active, stack;
  std::vector<unsigned char> reached(state.size(), 0);
  for (std::size_t i = 0; i < state.size(); ++i) {
    if (state[i] != kObstacleCell || reached[i]) continue;
    bool touches_ground = false;
    neighbours(i, [&](std::size_t j) { touches_ground |= state[j] == kGroundCell; });
    if (!touches_ground) continue;
    reached[i] = 1;
    stack.push_back(i);
    while (!stack.empty()) {
      const std::size_t a = stack.back();
      stack.pop_back();
      active.push_back(a);
      neighbours(a, [&](std::size_t j) {
        if (state[j] == kObstacleCell && !reached[j]) reached[j] = 1, stack.push_back(j);
      });
    }
  }
  std::sort(active.begin(), active.end());
  return active;
}

/// Harmonic ground under the obstacles: Laplace's equation on the `active` cells, the
/// known cells around them fixed (SOR Gauss-Seidel).
void solve_harmonic(const std::vector<std::size_t>& active, const std::vector<unsigned char>& state,
                    const Neighbours& neighbours, std::vector<float>& G) {
  constexpr double kOmega = 1.8;  // over-relaxation: Laplace on holes of tens of cells
  for (int sweep = 0; sweep < 20000 && !active.empty(); ++sweep) {
    double largest_change = 0.0;
    for (std::size_t i : active) {
      double sum = 0.0;
      int n = 0;
      neighbours(i, [&](std::size_t j) {
        if (state[j] != kUnknownCell) sum += G[j], ++n;
      });
      const double update = kOmega * (sum / n - G[i]);
      G[i] = static_cast<float>(G[i] + update);
      largest_change = std::max(largest_change, std::abs(update));
    }
    if (largest_change < 1e-7) break;
  }
}

}  // namespace

CloudGroundTruth cloud_ground_truth(const std::vector<Eigen::Vector3d>& points,
                                    const CloudGroundTruthOptions& o) {
  validate(o);
  const double r = o.resolution_m;
  const bool crop = o.x0_m != 0.0 || o.x1_m != 0.0 || o.y0_m != 0.0 || o.y1_m != 0.0;
  double x0 = o.x0_m, x1 = o.x1_m, y0 = o.y0_m, y1 = o.y1_m;
  if (!crop) {
    check(!points.empty(), "ground truth: the cloud has no points");
    x0 = y0 = std::numeric_limits<double>::infinity();
    x1 = y1 = -std::numeric_limits<double>::infinity();
    for (const auto& p : points) {
      x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x());
      y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
    }
  }
  CloudGroundTruth gt;
  gt.height = aligned_ground_truth_grid("height", x0, x1, y0, y1, r);
  JdemGrid& H = gt.height;
  const std::size_t n_cells = static_cast<std::size_t>(H.rows) * H.cols;

  // Heights of cells with points; then gaps, from the measured points only.
  const CellBins bins = bin_points(points, H, crop, x0, x1, y0, y1);
  gt.points = bins.points;
  const double spread_floor = (0.05 * r) * (0.05 * r);
  gt.cells_measured = measure_cells(points, bins, spread_floor, H);
  const double fill_radius = o.fill_radius_m > 0.0 ? o.fill_radius_m : 3.0 * r;
  gt.cells_filled = fill_gaps(points, bins, fill_radius, spread_floor, H);

  // 1. Lower envelope; 2. ground cells (within the tolerance of it), the others obstacles
  // on the envelope; 3. harmonic ground under the obstacles.
  const int k = std::max(1, static_cast<int>(std::lround(o.ground_radius_m / r)));
  const cv::Mat envelope = lower_envelope(H, k);
  JdemGrid ground = H;
  ground.quantity = "ground";
  std::vector<unsigned char> state(n_cells, kUnknownCell);
  for (std::size_t i = 0; i < n_cells; ++i) {
    const float z = H.values[i];
    if (std::isnan(z)) continue;
    const float env = envelope.at<float>(static_cast<int>(i / H.cols), static_cast<int>(i % H.cols));
    if (env == -FLT_MAX || z - env <= o.ground_tolerance_m) {
      state[i] = kGroundCell;
    } else {
      state[i] = kObstacleCell;
      ground.values[i] = env;
    }
  }
  const Neighbours neighbours{H.rows, H.cols};
  solve_harmonic(reachable_obstacles(state, neighbours), state, neighbours, ground.values);

  gt.hazard = obstacle_height_grid(H, ground);
  for (std::size_t i = 0; i < n_cells; ++i) {
    if (std::isnan(H.values[i])) ++gt.cells_unknown;
    else if (gt.hazard.values[i] > 0.0f) ++gt.cells_obstacle;
  }
  return gt;
}

void write_cloud_ground_truth(const std::filesystem::path& dir, const CloudGroundTruth& gt,
                              const CloudGroundTruthOptions& o, const std::string& source_cloud) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw Error(dir.string() + ": cannot create folder: " + ec.message());
  const std::vector<std::pair<std::string, std::string>> metadata = {
      {"source", "hazmap ground-truth"}, {"cloud", source_cloud}};
  JdemGrid height = gt.height, hazard = gt.hazard;
  height.metadata = metadata;
  hazard.metadata = metadata;
  write_jdem(dir / "gt_height.jdem", height);
  write_jdem(dir / "gt_hazard.jdem", hazard);
  const double fill = o.fill_radius_m > 0.0 ? o.fill_radius_m : 3.0 * o.resolution_m;
  std::ostringstream y;
  y << "# How this ground truth was made (hazmap ground-truth); see\n"
    << "# include/hazmap/eval/cloud_ground_truth.hpp for the method.\n"
    << "cloud: \"" << source_cloud << "\"\n"
    << "resolution_m: " << num(o.resolution_m) << "\n"
    << "fill_radius_m: " << num(fill) << "   # empty cells filled only with points on all four sides\n"
    << "ground_radius_m: " << num(o.ground_radius_m) << "   # obstacles narrower than twice this\n"
    << "ground_tolerance_m: " << num(o.ground_tolerance_m) << "\n"
    << "grid: {rows: " << gt.height.rows << ", cols: " << gt.height.cols
    << ", center: [" << num(gt.height.center_x_m) << ", " << num(gt.height.center_y_m) << "]}\n"
    << "points_used: " << gt.points << "\n"
    << "cells: {measured: " << gt.cells_measured << ", filled: " << gt.cells_filled
    << ", unknown: " << gt.cells_unknown << ", obstacle: " << gt.cells_obstacle << "}\n"
    << "ground_truth: {height: gt_height.jdem, hazard: gt_hazard.jdem}   # hazard: obstacle "
       "height above the local ground, 0 elsewhere\n";
  write_file_atomically(dir / "ground_truth.yaml", y.str());
}

}  // namespace hazmap
