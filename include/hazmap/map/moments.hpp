#pragma once
// Weighted first and second moments of a point set, and their exact merge (SPEC 6.5).
// Used for per-frame merges into a cell, pooling children into a parent, and the
// per-layer prior. Arithmetic is double; cells store float (see rules/).
//
//   W = sum W_i,  mu = sum W_i mu_i / W,
//   S_ab = sum ( S_ab,i + W_i (mu_i,a - mu_a)(mu_i,b - mu_b) )
//
// S is the weighted co-moment (sum of w (d - mu)(d - mu)^T), so Sigma = S / W
// (population normalisation, SPEC 12). Beside them, the weighted mean of the points'
// measurement height variances (CCM's noise variance), merged like the other means.

#include <algorithm>
#include <cstdint>

namespace hazmap {

struct Moments {
  double w = 0.0;
  double mx = 0.0, my = 0.0, mz = 0.0;
  double sxx = 0.0, syy = 0.0, szz = 0.0, sxy = 0.0, sxz = 0.0, syz = 0.0;
  /// Weighted mean of the points' Sigma_zz [m^2] (same weights as the means).
  double noise_var = 0.0;
  std::uint32_t count = 0;  ///< number of points behind the moments

  bool empty() const { return !(w > 0.0); }

  /// Moves the moments' x, y origin: the same points expressed relative to an origin
  /// shifted by (-dx, -dy), i.e. mu_x += dx, mu_y += dy.
  void shift(double dx, double dy) {
    mx += dx;
    my += dy;
  }

  /// this <- this (+) other, exactly (order-independent up to rounding).
  void merge(const Moments& o) {
    if (o.empty()) return;
    if (empty()) {
      *this = o;
      return;
    }
    const double W = w + o.w;
    const double f = o.w / W;
    const double dx = o.mx - mx, dy = o.my - my, dz = o.mz - mz;
    // W_a W_b / W (delta delta^T) is the combined spread of the two means.
    const double c = w * f;
    sxx += o.sxx + c * dx * dx;
    syy += o.syy + c * dy * dy;
    szz += o.szz + c * dz * dz;
    sxy += o.sxy + c * dx * dy;
    sxz += o.sxz + c * dx * dz;
    syz += o.syz + c * dy * dz;
    mx += f * dx;
    my += f * dy;
    mz += f * dz;
    noise_var += f * (o.noise_var - noise_var);
    w = W;
    count += o.count;
  }

  /// Scales the weight and co-moments by 1/psi (means, noise_var included, unchanged): the
  /// CCM weight cap.
  void scale_weight(double inv_psi) {
    w *= inv_psi;
    sxx *= inv_psi;
    syy *= inv_psi;
    szz *= inv_psi;
    sxy *= inv_psi;
    sxz *= inv_psi;
    syz *= inv_psi;
  }
};

/// Raw weighted sums of points: sum w, sum w p and sum w p p^T (upper triangle). T is
/// double for a frame's sums, or a SIMD vector of floats for lanes of a run.
template <class T>
struct WeightedSums {
  T w{}, x{}, y{}, z{}, xx{}, yy{}, zz{}, xy{}, xz{}, yz{};

  // Always inlined: GCC does not otherwise inline into an AVX2 clone (HAZMAP_KERNEL).
  [[gnu::always_inline]] void add(T wt, T px, T py, T pz) {
    w += wt;
    const T wx = wt * px, wy = wt * py, wz = wt * pz;
    x += wx;
    y += wy;
    z += wz;
    xx += wx * px;
    yy += wy * py;
    zz += wz * pz;
    xy += wx * py;
    xz += wx * pz;
    yz += wy * pz;
  }
  /// add() with weight 1 (`live`: 1, or 0 for a lane to leave out, whose p must be 0).
  [[gnu::always_inline]] void add_unit(T live, T px, T py, T pz) {
    w += live;
    x += px;
    y += py;
    z += pz;
    xx += px * px;
    yy += py * py;
    zz += pz * pz;
    xy += px * py;
    xz += px * pz;
    yz += py * pz;
  }
};

/// The bit of a cell's 4 x 4 occupancy mask for a point at (x, y) in cell units from the
/// cell's centre ([-0.5, 0.5); clamped: a point on the far border counts in the last
/// sub-cell): bit 4 j + i for sub-cell column i, row j.
inline std::uint16_t occupancy_bit(float x, float y) {
  const int i = std::min(3, std::max(0, static_cast<int>((x + 0.5f) * 4.0f)));
  const int j = std::min(3, std::max(0, static_cast<int>((y + 0.5f) * 4.0f)));
  return static_cast<std::uint16_t>(1u << (4 * j + i));
}
constexpr std::uint16_t kAllOccupied = 0xFFFF;

/// Raw weighted sums of one frame's points in one cell, relative to a reference point
/// (x, y in cell units from the cell centre, z in metres from a per-cell reference
/// height). Shifting by a reference inside the data keeps the raw-sum form exact enough
/// in double; to_moments() converts to centred moments. No division per point.
struct FrameSums : WeightedSums<double> {
  double v = 0;  ///< sum w Sigma_zz (noise variance)
  std::uint32_t count = 0;
  std::uint16_t occupied = 0;  ///< bit 4 j + i: a point in sub-cell (i, j) of the 4 x 4

  void add(double wt, double px, double py, double pz, double var_z = 0.0) {
    WeightedSums<double>::add(wt, px, py, pz);
    v += wt * var_z;
    ++count;
    occupied |= occupancy_bit(static_cast<float>(px), static_cast<float>(py));
  }

  /// Centred moments with x, y in metres (cell units times `cell_m`) relative to the cell
  /// centre and z relative to `z_ref_m` added back (absolute).
  Moments to_moments(double cell_m, double z_ref_m) const {
    Moments m;
    if (!(w > 0)) return m;
    const double ux = x / w, uy = y / w, uz = z / w;
    const double r2 = cell_m * cell_m;
    m.w = w;
    m.mx = ux * cell_m;
    m.my = uy * cell_m;
    m.mz = uz + z_ref_m;
    m.sxx = (xx - w * ux * ux) * r2;
    m.syy = (yy - w * uy * uy) * r2;
    m.szz = zz - w * uz * uz;
    m.sxy = (xy - w * ux * uy) * r2;
    m.sxz = (xz - w * ux * uz) * cell_m;
    m.syz = (yz - w * uy * uz) * cell_m;
    m.noise_var = v / w;
    // Rounding can leave tiny negative variances for single points.
    if (m.sxx < 0) m.sxx = 0;
    if (m.syy < 0) m.syy = 0;
    if (m.szz < 0) m.szz = 0;
    m.count = count;
    return m;
  }
};

}  // namespace hazmap
