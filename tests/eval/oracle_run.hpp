#pragma once
// Test worlds with known answers for the evaluation: an analytic ground truth (a tilted
// plane with hemispherical rocks) written as SPEC 9 JDEMs, and a run folder whose map is
// built directly from that ground truth ("oracle" map), in the layout `hazmap run`
// writes: summary.json with settings_yaml, frames/<frame>/L<i>_*.jdem, fused_hazard.jdem.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hazmap/io/config.hpp"
#include "hazmap/io/jdem.hpp"
#include "hazmap/map/dense_grid.hpp"
#include "hazmap/pipeline/output_writer.hpp"

namespace hazmap::testing {

struct TestRock {
  double x_m, y_m, radius_m;  ///< hemisphere: obstacle height sqrt(r^2 - d^2)
};

/// Ground truth z = offset + a x + b y plus hemispherical rocks, 1 cm pixels.
struct TestWorld {
  double a = 0.1, b = -0.05, offset_m = 0.02;
  std::vector<TestRock> rocks;
  double resolution_m = 0.01;
  int rows = 300, cols = 300;       ///< 3 m x 3 m
  double center_x_m = 1.0, center_y_m = 0.0;

  double ground(double x, double y) const { return offset_m + a * x + b * y; }
  double obstacle(double x, double y) const {
    double h = 0.0;
    for (const TestRock& r : rocks) {
      const double d2 = (x - r.x_m) * (x - r.x_m) + (y - r.y_m) * (y - r.y_m);
      if (d2 < r.radius_m * r.radius_m) h = std::max(h, std::sqrt(r.radius_m * r.radius_m - d2));
    }
    return h;
  }
  DenseGrid grid() const {
    DenseGrid g;
    g.reset(rows, cols, resolution_m, center_x_m, center_y_m, 0.0f);
    return g;
  }
  /// GT pixels of rock k whose obstacle height is at least h_min (the area a map that
  /// ignores the rock misses).
  int rock_pixels_at_least(size_t k, double h_min) const {
    const DenseGrid g = grid();
    int n = 0;
    for (int r = 0; r < g.rows; ++r)
      for (int c = 0; c < g.cols; ++c) {
        const double x = g.x_of_col(c), y = g.y_of_row(r);
        const TestRock& rock = rocks[k];
        const double d2 = (x - rock.x_m) * (x - rock.x_m) + (y - rock.y_m) * (y - rock.y_m);
        if (d2 < rock.radius_m * rock.radius_m &&
            std::sqrt(rock.radius_m * rock.radius_m - d2) >= h_min)
          ++n;
      }
    return n;
  }
};

/// gt_height.jdem, gt_hazard.jdem and poses.txt (+ poses_true.txt when `true_poses`) in
/// `seq`. Poses: one frame per entry of `frames`, body at (x_m, y_m) of `used_xy`
/// (what the map used) and `true_xy`.
inline void write_ground_truth(const std::filesystem::path& seq, const TestWorld& w) {
  std::filesystem::create_directories(seq);
  DenseGrid h = w.grid(), z = w.grid();
  for (int r = 0; r < h.rows; ++r)
    for (int c = 0; c < h.cols; ++c) {
      const double x = h.x_of_col(c), y = h.y_of_row(r);
      z.at(r, c) = static_cast<float>(w.obstacle(x, y));
      h.at(r, c) = static_cast<float>(w.ground(x, y) + w.obstacle(x, y));
    }
  write_jdem(seq / "gt_height.jdem", to_jdem(h, "height", "m", ""));
  write_jdem(seq / "gt_hazard.jdem", to_jdem(z, "hazard", "m", ""));
}

inline void write_poses(const std::filesystem::path& file, const std::vector<std::string>& frames,
                        const std::vector<Eigen::Vector2d>& xy) {
  std::ofstream out(file);
  out << "# name t x y z qx qy qz qw\n";
  for (size_t i = 0; i < frames.size(); ++i)
    out << frames[i] << " " << i << " " << xy[i].x() << " " << xy[i].y() << " 0 0 0 0 1\n";
}

/// A layer of the oracle map: cells over [center +- size r / 2] in the *world*; written
/// with its centre moved by `shift` (the map frame of drifted poses).
struct OracleLayer {
  DenseGrid height, variance, hazard, slope_x, slope_y;
};

/// Builds a layer straight from the ground truth: height = mean GT ground height of the
/// cell's obstacle-free pixels (CCM: the analytic plane at the cell centre, slopes a, b),
/// hazard where any pixel has an obstacle >= h_min, traversable otherwise; unknown outside
/// the ground truth. `variance_m2` everywhere known.
inline OracleLayer build_oracle_layer(const TestWorld& w, double resolution_m, int size,
                                      double center_x_m, double center_y_m, double h_min_m,
                                      bool plane, double variance_m2) {
  OracleLayer L;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (DenseGrid* g : {&L.height, &L.variance, &L.slope_x, &L.slope_y})
    g->reset(size, size, resolution_m, center_x_m, center_y_m, nan);
  L.hazard.reset(size, size, resolution_m, center_x_m, center_y_m, 0.0f);
  const DenseGrid gt = w.grid();
  const int k = static_cast<int>(std::lround(resolution_m / w.resolution_m));
  for (int r = 0; r < size; ++r)
    for (int c = 0; c < size; ++c) {
      const double cx = L.height.x_of_col(c), cy = L.height.y_of_row(r);
      double sum = 0;
      int n = 0, inside = 0;
      bool hazard = false;
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
          const double x = cx - resolution_m / 2 + (i + 0.5) * w.resolution_m;
          const double y = cy - resolution_m / 2 + (j + 0.5) * w.resolution_m;
          int gr, gc;
          if (!gt.cell_at(x, y, &gr, &gc)) continue;
          ++inside;
          const double o = w.obstacle(x, y);
          hazard |= o >= h_min_m;
          if (o <= 0.0) sum += w.ground(x, y), ++n;
        }
      if (inside < k * k) continue;  // leaves the ground truth: unknown
      L.hazard.at(r, c) = hazard ? 2.0f : 1.0f;
      L.variance.at(r, c) = static_cast<float>(variance_m2);
      if (plane) {
        L.height.at(r, c) = static_cast<float>(w.ground(cx, cy));
        L.slope_x.at(r, c) = static_cast<float>(w.a);
        L.slope_y.at(r, c) = static_cast<float>(w.b);
      } else {
        L.height.at(r, c) = static_cast<float>(n ? sum / n : w.ground(cx, cy));
      }
    }
  return L;
}

/// Turns every hazard cell whose centre is within `radius_m` of (x, y) traversable:
/// "deletes" a rock from the map.
inline void delete_rock(OracleLayer& L, double x_m, double y_m, double radius_m) {
  for (int r = 0; r < L.hazard.rows; ++r)
    for (int c = 0; c < L.hazard.cols; ++c) {
      const double dx = L.hazard.x_of_col(c) - x_m, dy = L.hazard.y_of_row(r) - y_m;
      if (L.hazard.at(r, c) == 2.0f && std::hypot(dx, dy) <= radius_m) L.hazard.at(r, c) = 1.0f;
    }
}

inline void shift_layer(OracleLayer& L, double dx_m, double dy_m) {
  for (DenseGrid* g : {&L.height, &L.variance, &L.hazard, &L.slope_x, &L.slope_y}) {
    g->center_x_m += dx_m;
    g->center_y_m += dy_m;
  }
}

inline std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char ch : s) {
    if (ch == '"' || ch == '\\') out += '\\', out += ch;
    else if (ch == '\n') out += "\\n";
    else out += ch;
  }
  return out + "\"";
}

/// Writes RUN/summary.json (settings_yaml = to_yaml(config)) and, per frame, the layers'
/// JDEMs, fused_hazard.jdem (= layer 0's hazard) and a small mosaic PNG.
inline void write_oracle_run(const std::filesystem::path& run, const Config& config,
                             const std::vector<std::string>& frames,
                             const std::vector<std::vector<OracleLayer>>& layers_per_frame) {
  std::filesystem::create_directories(run / "mosaic");
  std::ofstream(run / "summary.json") << "{\n  \"finished\": true,\n  \"settings_yaml\": "
                                      << json_string(to_yaml(config)) << "\n}\n";
  for (size_t f = 0; f < frames.size(); ++f) {
    const auto dir = run / "frames" / frames[f];
    std::filesystem::create_directories(dir);
    const auto& layers = layers_per_frame[f];
    for (size_t i = 0; i < layers.size(); ++i) {
      const std::string p = "L" + std::to_string(i) + "_";
      // The same conversion and units as the pipeline's writer.
      const std::string& name = frames[f];
      write_jdem(dir / (p + "height.jdem"), to_jdem(layers[i].height, "height", "m", name));
      write_jdem(dir / (p + "variance.jdem"), to_jdem(layers[i].variance, "variance", "m^2", name));
      write_jdem(dir / (p + "hazard.jdem"), to_jdem(layers[i].hazard, "hazard", "class", name));
      if (config.map.layers[i].rule == RuleKind::ccm) {
        write_jdem(dir / (p + "slope_x.jdem"), to_jdem(layers[i].slope_x, "slope_x", "m/m", name));
        write_jdem(dir / (p + "slope_y.jdem"), to_jdem(layers[i].slope_y, "slope_y", "m/m", name));
      }
    }
    write_jdem(dir / "fused_hazard.jdem", to_jdem(layers[0].hazard, "hazard", "class", frames[f]));
    cv::Mat mosaic(120, 200, CV_8UC3, cv::Scalar(40, 170, 70));
    cv::rectangle(mosaic, cv::Rect(20 + 10 * static_cast<int>(f), 30, 40, 40),
                  cv::Scalar(40, 40, 220), cv::FILLED);
    cv::imwrite((run / "mosaic" / (frames[f] + ".png")).string(), mosaic);
  }
}

/// Writes a hazard-only map of a frame, e.g. footprint_hazard.jdem (what the pipeline
/// writes beside fused_hazard.jdem).
inline void write_hazard_map(const std::filesystem::path& run, const std::string& frame,
                             const std::string& file, const DenseGrid& hazard) {
  write_jdem(run / "frames" / frame / file, to_jdem(hazard, "hazard", "class", frame));
}

/// Two layers: CCM 4 cm x 40 (h_min 3 cm) and Kalman 8 cm x 20 (roughness threshold
/// 5 cm, so h_min 5 cm), insertion all_layers.
inline Config oracle_config() {
  Config c = parse_config(
      "map:\n"
      "  insertion: all_layers\n"
      "  layers:\n"
      "    - {resolution: 0.04, size: 40, rule: ccm, hazard: {h_min: 0.03}}\n"
      "    - {resolution: 0.08, size: 20, rule: kalman, hazard: {kernel: 3, roughness_threshold: 0.05}}\n",
      "oracle_config");
  return c;
}

}  // namespace hazmap::testing
