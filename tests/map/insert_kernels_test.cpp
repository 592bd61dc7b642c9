// The per-point kernels of a layer's insertion against plain scalar double versions:
// locate_points (slot and cell-centred position), add_plane_run and height_run (a run's
// sums).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "hazmap/map/grid_math.hpp"
#include "hazmap/map/internal/chunk_slots.hpp"
#include "hazmap/map/internal/run_sums.hpp"
#include "hazmap/map/rolling_grid.hpp"

namespace hazmap {
namespace {

/// Writable arrays behind a PointChunk view (kStride entries each).
struct ChunkArrays {
  std::vector<float> x, y, z, inv_var_z, ccm_weight, lateral_var, var_z;
  ChunkArrays() {
    for (auto* v : {&x, &y, &z, &inv_var_z, &ccm_weight, &lateral_var, &var_z})
      v->assign(PointChunk::kStride, 0.0f);
  }
  PointChunk view(int size) const {
    PointChunk c;
    c.x = x.data();
    c.y = y.data();
    c.z = z.data();
    c.inv_var_z = inv_var_z.data();
    c.ccm_weight = ccm_weight.data();
    c.lateral_var = lateral_var.data();
    c.var_z = var_z.data();
    c.size = size;
    return c;
  }
};

TEST(LocatePoints, MatchesScalarFloorAndModulo) {
  std::mt19937_64 rng(5);
  // Both versions; N = 40000 takes the portable one in locate_points too (N >= 2^15).
  for (const auto locate : {&locate_points, &locate_points_portable})
    for (const auto& [n, r, robot_x, robot_y] :
         {std::tuple{250, 0.04, 3.3, -7.9}, std::tuple{1000, 0.01, -123.45, 56.78},
          std::tuple{16, 0.64, 0.0, 0.0}, std::tuple{5000, 0.002, 0.7, 1.1},
          std::tuple{40000, 0.001, -2.5, 9.0}}) {
      RollingGrid grid(n, r);
      grid.move_to(robot_x, robot_y);
      grid.move_to(robot_x + 0.37 * n * r, robot_y - 0.21 * n * r);  // wrapped ring
      WindowIndex w;
      w.x0_m = double(grid.origin_x()) * r;
      w.y0_m = double(grid.origin_y()) * r;
      w.inv_resolution = 1.0 / r;
      w.size = n;
      w.wrap_x = wrap_index(grid.origin_x(), n);
      w.wrap_y = wrap_index(grid.origin_y(), n);
      std::uniform_real_distribution<double> u(-0.2, 1.2);  // some points outside
      ChunkArrays chunk;
      const int size = PointChunk::kCapacity;
      for (int i = 0; i < size; ++i) {
        chunk.x[i] = float(w.x0_m + u(rng) * n * r);
        chunk.y[i] = float(w.y0_m + u(rng) * n * r);
        chunk.lateral_var[i] = float(i % 3) * 1e-6f;
      }
      chunk.x[7] = std::numeric_limits<float>::quiet_NaN();
      chunk.y[9] = std::numeric_limits<float>::infinity();
      std::vector<int> slot(PointChunk::kStride);
      std::vector<float> cx(PointChunk::kStride), cy(PointChunk::kStride);
      const float gate = 1.5e-6f;
      const int gated = locate(chunk.view(size), w, gate, slot.data(), cx.data(), cy.data());
      int inside = 0, boundary = 0, gated_want = 0, gated_boundary = 0;
      for (int i = 0; i < size; ++i) {
        const double fx = (double(chunk.x[i]) - w.x0_m) / r, fy = (double(chunk.y[i]) - w.y0_m) / r;
        // Points within 1e-4 cell of a cell edge may fall either way in float arithmetic.
        const bool wide = chunk.lateral_var[i] > gate;
        if (std::abs(fx - std::round(fx)) < 1e-4 || std::abs(fy - std::round(fy)) < 1e-4) {
          ++boundary;
          gated_boundary += wide;
          continue;
        }
        const double lx = std::floor(fx), ly = std::floor(fy);
        const bool in_window =
            std::isfinite(fx) && std::isfinite(fy) && lx >= 0 && lx < n && ly >= 0 && ly < n;
        gated_want += in_window && wide;
        const bool in = in_window && !wide;
        if (!in) {
          EXPECT_EQ(slot[i], -1) << "point " << i;
          continue;
        }
        ++inside;
        const CellIndex ix = grid.origin_x() + CellIndex(lx), iy = grid.origin_y() + CellIndex(ly);
        ASSERT_EQ(slot[i], grid.slot(ix, iy)) << "point " << i;
        EXPECT_NEAR(cx[i], fx - lx - 0.5, 2e-4 * n / 1000.0 + 1e-6) << "point " << i;
        EXPECT_NEAR(cy[i], fy - ly - 0.5, 2e-4 * n / 1000.0 + 1e-6) << "point " << i;
      }
      EXPECT_GT(inside, size / 4);  // (1/1.4)^2 inside, 2/3 of those pass the gate
      EXPECT_LT(boundary, 20);
      // The count is of gated points inside the window (boundary points either way).
      EXPECT_GE(gated, gated_want);
      EXPECT_LE(gated, gated_want + gated_boundary);
      EXPECT_GT(gated_want, size / 8);
      // Without position outputs (piecewise-constant rules) the same slots and gate.
      std::vector<int> cell_slot(PointChunk::kStride);
      EXPECT_EQ(locate(chunk.view(size), w, gate, cell_slot.data(), nullptr, nullptr), gated);
      for (int i = 0; i < size; ++i) ASSERT_EQ(cell_slot[i], slot[i]) << "point " << i;
      // No gate (+infinity): the gated points come back, none counted.
      const float open = std::numeric_limits<float>::infinity();
      EXPECT_EQ(locate(chunk.view(size), w, open, cell_slot.data(), nullptr, nullptr), 0);
      int back = 0;
      for (int i = 0; i < size; ++i) {
        if (slot[i] >= 0) {
          ASSERT_EQ(cell_slot[i], slot[i]);
        }
        back += slot[i] < 0 && cell_slot[i] >= 0;
      }
      EXPECT_EQ(back, gated);
      EXPECT_EQ(cell_slot[7], -1);
      EXPECT_EQ(cell_slot[9], -1);
    }
}

TEST(LocatePoints, GateCountIgnoresLanesPastTheChunk) {
  // A chunk of 13 points inside a window; the points after it (the next chunk's, read
  // by whole vectors) are all wide: only the chunk's own wide points count.
  ChunkArrays chunk;
  for (int i = 0; i < PointChunk::kStride; ++i) {
    chunk.x[i] = chunk.y[i] = 0.5f;
    chunk.lateral_var[i] = i < 13 ? float(i % 2) : 1.0f;  // 6 wide among the 13
  }
  WindowIndex w;
  w.inv_resolution = 1.0;
  w.size = 4;
  std::vector<int> slot(PointChunk::kStride);
  std::vector<float> cx(PointChunk::kStride), cy(PointChunk::kStride);
  for (const auto locate : {&locate_points, &locate_points_portable}) {
    EXPECT_EQ(locate(chunk.view(13), w, 0.5f, slot.data(), cx.data(), cy.data()), 6);
    EXPECT_EQ(locate(chunk.view(13), w, 0.5f, slot.data(), nullptr, nullptr), 6);
  }
}

TEST(AddPlaneRun, EqualsScalarDoubleSumsForEveryRunLengthAndOffset) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.5, 0.5), wd(0.5, 2.0);
  std::normal_distribution<double> nz(0.0, 0.002);
  ChunkArrays c;
  std::vector<float> cx(PointChunk::kStride), cy(PointChunk::kStride);
  for (int i = 0; i < PointChunk::kStride; ++i) {
    cx[i] = float(u(rng));
    cy[i] = float(u(rng));
    c.z[i] = float(35.0 + 0.1 * cx[i] + nz(rng));  // far from the reference, mm spread
    c.ccm_weight[i] = float(wd(rng));
    c.var_z[i] = float(1e-6 * wd(rng));
  }
  // Weighted, and unit weights (w null: constant weighting reads no weight array).
  for (const bool unit : {false, true}) {
    for (int begin : {0, 1, 3, 5}) {
      for (int len = 1; len <= 23; ++len) {
        const int end = begin + len;
        // A NaN just past the run must not leak into the masked vector lanes.
        const float saved = c.z[end], saved_var = c.var_z[end], saved_x = cx[end];
        c.z[end] = std::numeric_limits<float>::quiet_NaN();
        c.var_z[end] = std::numeric_limits<float>::quiet_NaN();
        cx[end] = std::numeric_limits<float>::quiet_NaN();
        const double z_ref = 34.99;
        FrameSums got, want;
        got.w = 1.0;  // runs add to what is there
        want.w = 1.0;
        const RunPoints run{unit ? nullptr : c.ccm_weight.data(),
                            cx.data(),
                            cy.data(),
                            c.z.data(),
                            begin,
                            end,
                            c.var_z.data()};
        add_plane_run(run, z_ref, got, /*occupancy=*/true);
        FrameSums without;  // a layer that keeps no occupancy mask
        add_plane_run(run, z_ref, without);
        for (int k = begin; k < end; ++k)
          want.add(unit ? 1.0 : c.ccm_weight[k], cx[k], cy[k], double(c.z[k]) - z_ref, c.var_z[k]);
        c.z[end] = saved;
        c.var_z[end] = saved_var;
        cx[end] = saved_x;
        ASSERT_EQ(got.count, want.count);
        // The run's 4 x 4 occupancy, from the same points one by one (lanes past the run
        // set no bit).
        EXPECT_EQ(got.occupied, want.occupied) << begin << "+" << len;
        EXPECT_EQ(without.occupied, 0u);
        EXPECT_EQ(without.count, got.count);
        const double tol = 1e-6;
        EXPECT_NEAR(got.w, want.w, tol * want.w);
        EXPECT_NEAR(got.x, want.x, tol * want.w);
        EXPECT_NEAR(got.y, want.y, tol * want.w);
        EXPECT_NEAR(got.xx, want.xx, tol * want.w);
        EXPECT_NEAR(got.xy, want.xy, tol * want.w);
        EXPECT_NEAR(got.v, want.v, 1e-6 * want.v) << begin << "+" << len;  // sum w Sigma_zz
        // z sums relative to z_ref: compare the centred spread, which is what cancels.
        const Moments mg = got.to_moments(1.0, z_ref), mw = want.to_moments(1.0, z_ref);
        EXPECT_NEAR(mg.mz, mw.mz, 1e-7) << begin << "+" << len;
        if (len > 1) {
          EXPECT_NEAR(mg.szz, mw.szz, 1e-4 * mw.szz + 1e-12) << begin << "+" << len;
          EXPECT_NEAR(mg.sxz, mw.sxz, 1e-4 * std::sqrt(mw.sxx * mw.szz) + 1e-12);
          EXPECT_NEAR(mg.syz, mw.syz, 1e-4 * std::sqrt(mw.syy * mw.szz) + 1e-12);
        }
      }
    }
  }
}

// A point's sub-cell in the 4 x 4 occupancy mask, against floor() in double: the lower
// borders belong to the sub-cell above them, the cell's far border to the last one.
TEST(OccupancyBit, NamesTheSubCellOfAPoint) {
  auto expected = [](double x, double y) {
    const int i = std::clamp(static_cast<int>(std::floor((x + 0.5) * 4.0)), 0, 3);
    const int j = std::clamp(static_cast<int>(std::floor((y + 0.5) * 4.0)), 0, 3);
    return static_cast<std::uint16_t>(1u << (4 * j + i));
  };
  for (const double x : {-0.5, -0.4999, -0.2501, -0.25, -0.01, 0.0, 0.2499, 0.25, 0.4999, 0.5})
    for (const double y : {-0.5, -0.25, 0.0, 0.3, 0.5})
      EXPECT_EQ(occupancy_bit(float(x), float(y)), expected(x, y)) << x << ", " << y;
  EXPECT_EQ(occupancy_bit(-0.5f, -0.5f), 1u);
  EXPECT_EQ(occupancy_bit(0.49f, 0.49f), 1u << 15);
  EXPECT_EQ(occupancy_bit(0.26f, -0.3f), 1u << 3);  // column 3, row 0
  EXPECT_EQ(occupancy_bit(-0.3f, 0.01f), 1u << 8);  // column 0, row 2
}

TEST(HeightRun, EqualsScalarDoubleSums) {
  std::mt19937_64 rng(13);
  std::normal_distribution<double> nz(0.0, 0.001);
  std::uniform_real_distribution<double> wd(1e4, 4e4);
  ChunkArrays c;
  for (int i = 0; i < PointChunk::kStride; ++i) {
    c.z[i] = float(-80.0 + nz(rng));
    c.inv_var_z[i] = float(wd(rng));
  }
  for (int begin : {0, 2, 7}) {
    for (int len = 1; len <= 19; ++len) {
      const int end = begin + len;
      const float saved = c.z[end];
      c.z[end] = std::numeric_limits<float>::quiet_NaN();
      const double z_ref = -80.002;
      const HeightSums got = height_run(
          RunPoints{c.inv_var_z.data(), nullptr, nullptr, c.z.data(), begin, end}, z_ref);
      c.z[end] = saved;
      double w = 0, wz = 0, wzz = 0;
      for (int k = begin; k < end; ++k) {
        const double dz = double(c.z[k]) - z_ref;
        w += c.inv_var_z[k];
        wz += c.inv_var_z[k] * dz;
        wzz += c.inv_var_z[k] * dz * dz;
      }
      EXPECT_NEAR(got.w, w, 1e-6 * w);
      EXPECT_NEAR(got.wz / got.w, wz / w, 1e-8) << begin << "+" << len;  // mean, m
      const double var_got = got.wzz / got.w - (got.wz / got.w) * (got.wz / got.w);
      const double var_want = wzz / w - (wz / w) * (wz / w);
      EXPECT_NEAR(var_got, var_want, 1e-3 * var_want + 1e-12) << begin << "+" << len;
    }
  }
}

}  // namespace
}  // namespace hazmap
