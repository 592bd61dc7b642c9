#include "hazmap/hazard/fused_hazard.hpp"

#include <array>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace hazmap {
namespace {

constexpr float kU = float(HazardClass::unknown), kT = float(HazardClass::traversable),
                kH = float(HazardClass::hazard);

TEST(FusedHazard, HazardFromAnyLayerTraversableOnlyFromLayersFineEnoughForCriticalHeight) {
  // Fine 4 x 4 at 1 m (h_min 3 cm) and coarse 2 x 2 at 2 m (h_min 12 cm), centred on 0.
  DenseGrid fine, coarse, fused, clearance;
  fine.reset(4, 4, 1.0, 0, 0, kU);
  coarse.reset(2, 2, 2.0, 0, 0, kU);
  fine.at(0, 0) = kT;
  fine.at(0, 1) = kH;
  coarse.at(0, 0) = kT;  // covers fine rows 0-1, cols 0-1
  coarse.at(1, 1) = kH;  // covers fine rows 2-3, cols 2-3
  fine.at(3, 3) = kT;    // coarse says hazard: hazard wins
  HazardFusion fusion;
  fusion.fuse({{&fine, 0.03}, {&coarse, 0.12}}, 0.03, 4, 1.0, 0, 0, fused, clearance);
  EXPECT_EQ(fused.at(0, 0), kT);
  EXPECT_FLOAT_EQ(clearance.at(0, 0), 0.03f);
  EXPECT_EQ(fused.at(0, 1), kH);
  EXPECT_TRUE(std::isnan(clearance.at(0, 1)));
  // Only the coarse layer vouches: it cannot see a 3 cm rock, so unknown; its clearance
  // says what could still hide there.
  EXPECT_EQ(fused.at(1, 0), kU);
  EXPECT_FLOAT_EQ(clearance.at(1, 0), 0.12f);
  EXPECT_EQ(fused.at(0, 2), kU);
  EXPECT_TRUE(std::isnan(clearance.at(0, 2)));
  EXPECT_EQ(fused.at(2, 2), kH);
  EXPECT_EQ(fused.at(3, 3), kH);
  // A rover that must avoid only 12 cm obstacles may trust the coarse layer.
  fusion.fuse({{&fine, 0.03}, {&coarse, 0.12}}, 0.12, 4, 1.0, 0, 0, fused, clearance);
  EXPECT_EQ(fused.at(1, 0), kT);
}

TEST(FusedHazard, FinerProofOutweighsACoarserHazardOnlyFromAVouchingLayer) {
  // Layers at 1, 2 and 4 m; h_min 3, 3 and 12 cm; critical 3 cm. The 4 m layer's one
  // cell says hazard everywhere, the 2 m layer's NE cell says hazard too.
  DenseGrid fine, mid, coarse, fused, clearance;
  fine.reset(4, 4, 1.0, 0, 0, kU);
  mid.reset(2, 2, 2.0, 0, 0, kU);
  coarse.reset(1, 1, 4.0, 0, 0, kH);
  mid.at(0, 1) = kH;                           // fine rows 0-1, cols 2-3
  fine.at(3, 0) = kT;                          // under coarse hazard only
  fine.at(0, 3) = kT;                          // under mid and coarse hazards
  mid.at(1, 1) = kT;                           // fine rows 2-3, cols 2-3
  fine.at(2, 2) = kH;                          // fine hazard under a mid proof
  DenseGrid coarse_proof;                      // a 12 cm layer cannot vouch
  coarse_proof.reset(4, 4, 1.0, 0, 0, kU);
  coarse_proof.at(1, 0) = kT;
  HazardFusion fusion;
  const std::vector<FusionInput> layers = {{&fine, 0.03}, {&mid, 0.03}, {&coarse, 0.12}};
  fusion.fuse(layers, 0.03, 4, 1.0, 0, 0, fused, clearance);  // SPEC 8.4: any hazard
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_EQ(fused.at(r, c), kH) << r << " " << c;
  fusion.set_finer_proof(true);
  fusion.fuse(layers, 0.03, 4, 1.0, 0, 0, fused, clearance);
  EXPECT_EQ(fused.at(3, 0), kT);  // fine proof under the coarse hazard
  EXPECT_FLOAT_EQ(clearance.at(3, 0), 0.03f);
  EXPECT_EQ(fused.at(0, 3), kT);  // ... and under two coarser hazards
  EXPECT_EQ(fused.at(2, 3), kT);  // the mid layer's proof outweighs the coarse hazard
  EXPECT_EQ(fused.at(2, 2), kH);  // a finer hazard is never outweighed by a coarser proof
  EXPECT_EQ(fused.at(0, 2), kH);  // no proof finer than the mid hazard
  EXPECT_EQ(fused.at(1, 1), kH);  // only hazards
  // A proof from a layer that cannot vouch (h_min > critical) outweighs nothing, even
  // when it is finer than the hazard.
  fusion.fuse({{&coarse_proof, 0.12}, {&coarse, 0.12}}, 0.03, 4, 1.0, 0, 0, fused, clearance);
  EXPECT_EQ(fused.at(1, 0), kH);
}

TEST(FusedHazard, GridExtendsBeyondTheFinestLayerWhereCoarseLayersReach) {
  DenseGrid fine, coarse, fused, clearance;
  fine.reset(2, 2, 1.0, 0, 0, kT);      // x, y in [-1, 1]
  coarse.reset(4, 4, 2.0, 0, 0, kH);    // x, y in [-4, 4]
  coarse.at(1, 1) = kT;                 // [-2, 0] x [0, 2]: holds the fine layer's NW cell
  coarse.at(1, 2) = kT;
  coarse.at(2, 1) = kT;
  coarse.at(2, 2) = kT;
  HazardFusion fusion;
  fusion.fuse({{&fine, 0.03}, {&coarse, 0.5}}, 0.03, 8, 1.0, 0, 0, fused, clearance);
  ASSERT_EQ(fused.rows, 8);
  EXPECT_EQ(fused.at(0, 0), kH);  // only the coarse layer, which says hazard
  EXPECT_EQ(fused.at(3, 3), kT);  // the fine layer's cell
  EXPECT_EQ(fused.at(2, 2), kU);  // coarse traversable, h_min too large
  EXPECT_EQ(fused_cells(10.24, 0.01), 1024);
  EXPECT_EQ(fused_cells(1.0, 0.3), 4);  // rounded to an even count
}

/// Brute force: nearest source cell centre by exhaustive search.
double nearest(const std::vector<unsigned char>& src, int rows, int cols, int r, int c) {
  double best = 1e30;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j)
      if (src[static_cast<size_t>(i) * cols + j]) best = std::min(best, double((i - r) * (i - r) + (j - c) * (j - c)));
  return best;
}

TEST(DistanceTransform, EqualsBruteForceOnRandomSources) {
  DistanceTransform edt;
  std::vector<float> d2;
  std::mt19937 rng(3);
  for (const double density : {0.0, 0.002, 0.02, 0.3}) {
    const int rows = 37, cols = 53;
    std::vector<unsigned char> src(static_cast<size_t>(rows) * cols);
    std::bernoulli_distribution b(density);
    for (auto& s : src) s = b(rng);
    edt.compute(src.data(), rows, cols, d2);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        const double ref = nearest(src, rows, cols, r, c);
        const float got = d2[static_cast<size_t>(r) * cols + c];
        if (ref >= 1e29) ASSERT_GE(got, kNoSourceSquared) << r << "," << c;
        else ASSERT_EQ(got, float(ref)) << "density " << density << " at " << r << "," << c;
      }
  }
}

TEST(Footprint, HazardWithinRadiusThenUnknownThenTraversableAndDistanceInMetres) {
  // 40 x 40 at 1 cm, all traversable but one hazard cell and one unknown cell.
  DenseGrid fused, footprint, distance;
  fused.reset(40, 40, 0.01, 0, 0, kT);
  fused.at(10, 10) = kH;
  fused.at(30, 30) = kU;
  HazardFusion fusion;
  fusion.footprint(fused, 0.05, footprint, distance);
  EXPECT_EQ(footprint.at(10, 15), kH);  // 5 cm away: inside the footprint
  EXPECT_EQ(footprint.at(14, 13), kH);  // (4, 3): 5 cm
  EXPECT_EQ(footprint.at(10, 16), kT);  // 6 cm: beyond 5 cm + half a diagonal (0.71 cm)
  EXPECT_EQ(footprint.at(14, 14), kH);  // 5.66 cm: the hazard cell's corner is 4.95 cm away
  EXPECT_EQ(footprint.at(14, 15), kT);  // 6.40 cm
  EXPECT_EQ(footprint.at(30, 26), kU);  // 4 cm from the unknown cell
  EXPECT_EQ(footprint.at(2, 20), kU);   // the map's edge is 3 cm away: nothing known beyond
  EXPECT_EQ(footprint.at(5, 20), kT);   // the edge is 6 cm away
  EXPECT_NEAR(distance.at(14, 13), 0.05, 1e-6);
  EXPECT_NEAR(distance.at(10, 10), 0.0, 1e-9);
  EXPECT_NEAR(distance.at(39, 39), std::min(0.2, std::hypot(0.29, 0.29)), 1e-6);  // capped at half the side
}

TEST(Footprint, EqualsBruteForceOnRandomMapsAndOnARegion) {
  std::mt19937 rng(11);
  for (const double radius_m : {0.03, 0.05, 0.055, 0.15}) {
    DenseGrid fused;
    fused.reset(45, 38, 0.01, 0.3, -0.2, kT);
    std::discrete_distribution<int> kind({0.9, 0.08, 0.02});  // traversable, unknown, hazard
    for (float& v : fused.values) v = std::array<float, 3>{kT, kU, kH}[kind(rng)];
    HazardFusion fusion;
    DenseGrid footprint, distance;
    fusion.footprint(fused, radius_m, footprint, distance);
    const double rc = radius_m / 0.01 + std::sqrt(0.5), radius2 = rc * rc * (1.0 + 1e-9);
    for (int row = 0; row < fused.rows; ++row)
      for (int col = 0; col < fused.cols; ++col) {
        bool hazard = false, unknown = false;
        for (int r = 0; r < fused.rows; ++r)
          for (int c = 0; c < fused.cols; ++c) {
            if (double(r - row) * (r - row) + double(c - col) * (c - col) > radius2) continue;
            hazard |= fused.at(r, c) == kH;
            unknown |= fused.at(r, c) == kU;
          }
        const int edge = std::min({row + 1, fused.rows - row, col + 1, fused.cols - col});
        unknown |= double(edge) * edge <= radius2;
        const float want = hazard ? kH : unknown ? kU : kT;
        ASSERT_EQ(footprint.at(row, col), want) << radius_m << " at " << row << "," << col;
      }
    // On a region: the same values there, the other cells untouched.
    DenseGrid part = footprint;
    std::fill(part.values.begin(), part.values.end(), -1.0f);
    DirtyRegion region;
    region.add({3, 11, 30, 38});
    region.add({20, 45, 0, 9});
    fusion.footprint(fused, radius_m, region, part, distance);
    for (int row = 0; row < fused.rows; ++row)
      for (int col = 0; col < fused.cols; ++col)
        ASSERT_EQ(part.at(row, col), region.contains(row, col) ? footprint.at(row, col) : -1.0f)
            << radius_m << " at " << row << "," << col;
  }
}

TEST(FusedHazard, ClearCellsAreProvenOrUnknownOnlyForAVouchingLayersRing) {
  // Fine 4 x 4 at 1 m (h_min 3 cm) with its ring-only flags, coarse 2 x 2 (12 cm) likewise.
  DenseGrid fine, coarse, fine_ring, coarse_ring, fused, clearance, clear;
  fine.reset(4, 4, 1.0, 0, 0, kU);
  coarse.reset(2, 2, 2.0, 0, 0, kU);
  fine_ring.reset(4, 4, 1.0, 0, 0, 0.0f);
  coarse_ring.reset(2, 2, 2.0, 0, 0, 0.0f);
  fine.at(0, 0) = kT;
  fine_ring.at(0, 1) = 1.0f;  // unknown for its ring only: clear
  fine_ring.at(0, 2) = 1.0f;
  fine.at(0, 2) = kH;         // (a flag on a hazard cell cannot make it clear)
  coarse_ring.at(1, 0) = 1.0f;  // the coarse layer does not vouch: not clear
  HazardFusion fusion;
  fusion.fuse({{&fine, 0.03, &fine_ring}, {&coarse, 0.12, &coarse_ring}}, 0.03, 4, 1.0, 0, 0,
              fused, clearance, &clear);
  EXPECT_EQ(clear.at(0, 0), 1.0f);
  EXPECT_EQ(clear.at(0, 1), 1.0f);
  EXPECT_EQ(fused.at(0, 1), kU);  // the fused map itself is unchanged
  EXPECT_EQ(clear.at(0, 2), 0.0f);
  EXPECT_EQ(clear.at(2, 0), 0.0f);
  EXPECT_EQ(clear.at(3, 3), 0.0f);
  // A region refuses only its cells.
  std::fill(clear.values.begin(), clear.values.end(), -1.0f);
  DirtyRegion region;
  region.add({0, 1, 0, 2});
  fusion.fuse({{&fine, 0.03, &fine_ring}, {&coarse, 0.12, &coarse_ring}}, 0.03, region, fused,
              clearance, &clear);
  EXPECT_EQ(clear.at(0, 1), 1.0f);
  EXPECT_EQ(clear.at(1, 1), -1.0f);
}

TEST(Footprint, WithClearCellsTheCentreMustBeProvenAndEveryCellInTheDiscClear) {
  // Brute force on random maps: hazard within the radius; else traversable iff the centre
  // is traversable, every cell within the radius is clear and the edge is beyond it.
  std::mt19937 rng(12);
  for (const double radius_m : {0.03, 0.055, 0.15}) {
    DenseGrid fused, clear;
    fused.reset(45, 38, 0.01, 0.3, -0.2, kT);
    clear.reset(45, 38, 0.01, 0.3, -0.2, 0.0f);
    std::discrete_distribution<int> kind({0.85, 0.13, 0.02});  // traversable, unknown, hazard
    std::bernoulli_distribution ring_only(0.8);                 // an unknown cell's flag
    for (size_t i = 0; i < fused.values.size(); ++i) {
      fused.values[i] = std::array<float, 3>{kT, kU, kH}[kind(rng)];
      clear.values[i] = fused.values[i] == kT || (fused.values[i] == kU && ring_only(rng)) ? 1.0f : 0.0f;
    }
    HazardFusion fusion;
    DenseGrid footprint, plain, distance;
    fusion.footprint(fused, radius_m, footprint, distance, &clear);
    fusion.footprint(fused, radius_m, plain, distance);
    const double rc = radius_m / 0.01 + std::sqrt(0.5), radius2 = rc * rc * (1.0 + 1e-9);
    long more = 0;
    for (int row = 0; row < fused.rows; ++row)
      for (int col = 0; col < fused.cols; ++col) {
        bool hazard = false, blocked = false;
        for (int r = 0; r < fused.rows; ++r)
          for (int c = 0; c < fused.cols; ++c) {
            if (double(r - row) * (r - row) + double(c - col) * (c - col) > radius2) continue;
            hazard |= fused.at(r, c) == kH;
            blocked |= clear.at(r, c) != 1.0f;
          }
        const int edge = std::min({row + 1, fused.rows - row, col + 1, fused.cols - col});
        blocked |= double(edge) * edge <= radius2 || fused.at(row, col) != kT;
        const float want = hazard ? kH : blocked ? kU : kT;
        ASSERT_EQ(footprint.at(row, col), want) << radius_m << " at " << row << "," << col;
        // Never less than the plain rule proves, and the same hazards.
        if (plain.at(row, col) == kT) {
          ASSERT_EQ(want, kT);
        }
        ASSERT_EQ(plain.at(row, col) == kH, want == kH);
        more += want == kT && plain.at(row, col) != kT;
      }
    if (radius_m < 0.1) {  // at 15 cm nearly every disc holds a hazard
      EXPECT_GT(more, 0) << radius_m;
    }
    // On a region: the same values there, the other cells untouched.
    DenseGrid part = footprint;
    std::fill(part.values.begin(), part.values.end(), -1.0f);
    DirtyRegion region;
    region.add({3, 11, 30, 38});
    region.add({20, 45, 0, 9});
    fusion.footprint(fused, radius_m, region, part, distance, &clear);
    for (int row = 0; row < fused.rows; ++row)
      for (int col = 0; col < fused.cols; ++col)
        ASSERT_EQ(part.at(row, col), region.contains(row, col) ? footprint.at(row, col) : -1.0f)
            << radius_m << " at " << row << "," << col;
  }
}

TEST(Footprint, EveryPointWithinTheRadiusLiesInACellTheFootprintCounted) {
  // The footprint's promise to a planner: a traversable footprint cell has no hazard or
  // unknown cell anywhere within the radius, whatever the fused map's resolution. Random
  // 4 cm maps; points sampled in every traversable cell's disc must fall in traversable
  // fused cells.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const double radius_m : {0.05, 0.15, 0.17}) {
    DenseGrid fused;
    fused.reset(40, 40, 0.04, 0, 0, kT);
    std::discrete_distribution<int> kind({0.97, 0.015, 0.015});
    for (float& v : fused.values) v = std::array<float, 3>{kT, kU, kH}[kind(rng)];
    HazardFusion fusion;
    DenseGrid footprint, distance;
    fusion.footprint(fused, radius_m, footprint, distance);
    int traversable = 0;
    for (int row = 0; row < fused.rows; ++row)
      for (int col = 0; col < fused.cols; ++col) {
        if (footprint.at(row, col) != kT) continue;
        ++traversable;
        for (int k = 0; k < 400; ++k) {
          const double dx = u(rng) * radius_m, dy = u(rng) * radius_m;
          if (std::hypot(dx, dy) > radius_m) continue;
          int r = 0, c = 0;
          ASSERT_TRUE(fused.cell_at(fused.x_of_col(col) + dx, fused.y_of_row(row) + dy, &r, &c));
          ASSERT_EQ(fused.at(r, c), kT) << radius_m << " at " << row << "," << col;
        }
      }
    EXPECT_GT(traversable, 50) << radius_m;  // the test saw traversable cells
  }
}

}  // namespace
}  // namespace hazmap
