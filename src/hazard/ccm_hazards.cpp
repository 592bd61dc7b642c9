#include "hazmap/hazard/ccm_hazards.hpp"

#include <cmath>
#include <limits>

namespace hazmap {

CcmHazardParams ccm_hazard_params(double resolution_m, double h_min_m, double rho_max_m2,
                                  double max_slope_deg, double wheelbase_m) {
  CcmHazardParams p;
  p.rho_max_m2 = rho_max_m2 > 0 ? rho_max_m2 : h_min_m * h_min_m / 16.0;
  p.max_face_rad = std::atan(h_min_m / resolution_m);
  p.max_slope_rad = max_slope_deg * M_PI / 180.0;
  p.wheelbase_m = wheelbase_m;
  return p;
}

double ccm_surface_height(const LayerGrids& g, double x_m, double y_m) {
  int row = 0, col = 0;
  if (!g.height.cell_at(x_m, y_m, &row, &col)) return std::numeric_limits<double>::quiet_NaN();
  if (g.evaluable.at(row, col) != 1.0f) return std::numeric_limits<double>::quiet_NaN();
  return g.height.at(row, col) + g.slope_x.at(row, col) * (x_m - g.height.x_of_col(col)) +
         g.slope_y.at(row, col) * (y_m - g.height.y_of_row(row));
}

void classify_ccm(const LayerGrids& g, const CcmHazardParams& p, DenseGrid& hazard) {
  const DenseGrid& h = g.height;
  hazard.reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m,
               static_cast<float>(HazardClass::unknown));
  const bool small_cells = h.resolution_m < p.wheelbase_m;
  const double radius = p.wheelbase_m / 2.0;
  const double tan_slope = std::tan(p.max_slope_rad), tan_face = std::tan(p.max_face_rad);
  // 8 samples on the wheelbase circle; for symmetric samples the least-squares plane
  // slope is sum(z dx) / sum(dx^2) (and the same in y), sum(dx^2) = 4 radius^2.
  double dx[8], dy[8];
  for (int k = 0; k < 8; ++k) {
    dx[k] = radius * std::cos(k * M_PI / 4.0);
    dy[k] = radius * std::sin(k * M_PI / 4.0);
  }
  const double norm = 4.0 * radius * radius;
  for (int row = 0; row < h.rows; ++row)
    for (int col = 0; col < h.cols; ++col) {
      if (g.evaluable.at(row, col) != 1.0f) continue;
      const double sx = g.slope_x.at(row, col), sy = g.slope_y.at(row, col);
      const double tan_incl = std::hypot(sx, sy);
      bool is_hazard = g.roughness.at(row, col) > p.rho_max_m2 || tan_incl > tan_face;
      bool slope_known = true;
      if (!is_hazard) {
        if (small_cells) {
          const double cx = h.x_of_col(col), cy = h.y_of_row(row);
          double a = 0, b = 0;
          for (int k = 0; k < 8 && slope_known; ++k) {
            const double z = ccm_surface_height(g, cx + dx[k], cy + dy[k]);
            if (std::isnan(z)) slope_known = false;
            a += z * dx[k];
            b += z * dy[k];
          }
          if (slope_known) is_hazard = std::hypot(a / norm, b / norm) > tan_slope;
        } else {
          is_hazard = tan_incl > tan_slope;
        }
      }
      hazard.at(row, col) = static_cast<float>(is_hazard      ? HazardClass::hazard
                                               : slope_known ? HazardClass::traversable
                                                             : HazardClass::unknown);
    }
}

}  // namespace hazmap
