#include "hazmap/hazard/fused_hazard.hpp"

#include "hazmap/core/error.hpp"

namespace hazmap {

void fuse_hazards(const std::vector<const DenseGrid*>& layers, DenseGrid& fused) {
  check(!layers.empty(), "fuse_hazards: no layers");
  const DenseGrid& finest = *layers.front();
  fused.reset(finest.rows, finest.cols, finest.resolution_m, finest.center_x_m,
              finest.center_y_m, static_cast<float>(HazardClass::unknown));
  for (int row = 0; row < fused.rows; ++row) {
    const double y = fused.y_of_row(row);
    for (int col = 0; col < fused.cols; ++col) {
      const double x = fused.x_of_col(col);
      bool known = false, hazard = false;
      for (const DenseGrid* layer : layers) {
        int r = 0, c = 0;
        if (!layer->cell_at(x, y, &r, &c)) continue;
        const auto cls = static_cast<HazardClass>(static_cast<int>(layer->at(r, c)));
        known |= cls != HazardClass::unknown;
        hazard |= cls == HazardClass::hazard;
      }
      fused.at(row, col) = static_cast<float>(hazard  ? HazardClass::hazard
                                              : known ? HazardClass::traversable
                                                      : HazardClass::unknown);
    }
  }
}

}  // namespace hazmap
