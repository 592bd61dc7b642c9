#pragma once
// Kalman height rule (SPEC 6.2): one scalar Kalman filter per cell on the height.
//
//   first point:  mu = z,  var = vm
//   update:       mu' = (vm mu + var z) / (var + vm),  var' = var vm / (var + vm)
//   floor:        var' = max(var', min_variance)
//   per frame:    var += time_inflation on every known cell (forgetting, so that the
//                 map can re-converge when the terrain or the pose estimate changes)
//
// vm is the measurement's height variance Sigma_W(2,2) (SPEC 4). Without inflation and
// floor, the result equals the inverse-variance weighted mean of all measurements, with
// variance 1 / sum(1/vm).

#include <cmath>
#include <limits>

namespace hazmap {

struct KalmanRule {
  struct Config {
    double time_inflation_m2 = 1.0e-6;  ///< q added to var once per frame [m^2]
    double min_variance_m2 = 1.0e-6;    ///< convergence floor [m^2]
  };

  /// var = NaN marks a cell that has never been observed.
  struct Cell {
    float mean_m = 0.0f;
    float variance_m2 = std::numeric_limits<float>::quiet_NaN();
  };

  static bool known(const Cell& c) { return !std::isnan(c.variance_m2); }
  static void clear(Cell& c) { c = Cell{}; }

  static void update(const Config& cfg, Cell& c, double z_m, double vm_m2) {
    if (!known(c)) {
      c.mean_m = static_cast<float>(z_m);
      c.variance_m2 = static_cast<float>(std::max(vm_m2, cfg.min_variance_m2));
      return;
    }
    const double var = c.variance_m2;
    const double sum = var + vm_m2;
    c.mean_m = static_cast<float>((vm_m2 * c.mean_m + var * z_m) / sum);
    c.variance_m2 = static_cast<float>(std::max(var * vm_m2 / sum, cfg.min_variance_m2));
  }

  static void begin_frame(const Config& cfg, Cell& c) {
    if (known(c)) c.variance_m2 += static_cast<float>(cfg.time_inflation_m2);
  }

  static float height(const Cell& c) { return known(c) ? c.mean_m : NAN; }
  static float variance(const Cell& c) { return c.variance_m2; }
};

}  // namespace hazmap
