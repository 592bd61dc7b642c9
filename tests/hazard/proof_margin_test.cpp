// hazard.proof_margin (issue 34): no fused proof within the margin of a fused hazard cell.
// Checked against a hand-made case (which neighbours a 1 cm and a 1.5 cm margin reach)
// and against a brute force over random layers, whole and per region.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "hazmap/hazard/dirty_region.hpp"
#include "hazmap/hazard/fused_hazard.hpp"

namespace hazmap {
namespace {

constexpr float kU = float(HazardClass::unknown), kT = float(HazardClass::traversable),
                kH = float(HazardClass::hazard);

TEST(ProofMargin, CellsWithinTheMarginOfAHazardAreUnknownAndNotClear) {
  // One 1 cm layer, 9 x 9, traversable but for a hazard in the middle; the ring-only
  // flags set everywhere (so an unknown cell would be clear without the margin).
  DenseGrid layer, ring_only, fused, clearance, clear;
  layer.reset(9, 9, 0.01, 0, 0, kT);
  layer.at(4, 4) = kH;
  layer.at(0, 8) = kU;  // unknown, ring only, far from the hazard: stays clear
  ring_only.reset(9, 9, 0.01, 0, 0, 1.0f);
  FusionInput in{&layer, 0.03, &ring_only};

  HazardFusion off;
  off.fuse({in}, 0.03, 9, 0.01, 0, 0, fused, clearance, &clear);
  EXPECT_EQ(fused.at(4, 5), kT);
  EXPECT_EQ(fused.at(0, 8), kU);
  EXPECT_EQ(clear.at(0, 8), 1.0f);

  HazardFusion one;  // 1 cm: the four edge neighbours (their centres 1 cm away)
  one.set_proof_margin(0.01, 0.01);
  EXPECT_EQ(one.proof_margin_cells(), 1);
  one.fuse({in}, 0.03, 9, 0.01, 0, 0, fused, clearance, &clear);
  for (int r = 0; r < 9; ++r)
    for (int c = 0; c < 9; ++c) {
      SCOPED_TRACE("cell " + std::to_string(r) + "," + std::to_string(c));
      const int d2 = (r - 4) * (r - 4) + (c - 4) * (c - 4);
      if (d2 == 0) {
        EXPECT_EQ(fused.at(r, c), kH);
      } else if (d2 == 1) {
        EXPECT_EQ(fused.at(r, c), kU);
        EXPECT_TRUE(std::isnan(clearance.at(r, c)));
        EXPECT_EQ(clear.at(r, c), 0.0f);  // unknown, its ring flag notwithstanding
      } else if (r == 0 && c == 8) {
        EXPECT_EQ(fused.at(r, c), kU);
        EXPECT_EQ(clear.at(r, c), 1.0f);
      } else {
        EXPECT_EQ(fused.at(r, c), kT);
        EXPECT_FLOAT_EQ(clearance.at(r, c), 0.03f);
        EXPECT_EQ(clear.at(r, c), 1.0f);
      }
    }

  HazardFusion diag;  // 1.5 cm: the diagonals too (1.41 cm), not two cells away (2 cm)
  diag.set_proof_margin(0.015, 0.01);
  diag.fuse({in}, 0.03, 9, 0.01, 0, 0, fused, clearance, &clear);
  EXPECT_EQ(fused.at(3, 3), kU);
  EXPECT_EQ(fused.at(5, 5), kU);
  EXPECT_EQ(fused.at(4, 6), kT);
  EXPECT_EQ(fused.at(2, 4), kT);

  // A resolution other than the one the margin was set for is refused.
  EXPECT_ANY_THROW(one.fuse({in}, 0.03, 9, 0.02, 0, 0, fused, clearance, &clear));
}

/// The margin by hand: fuse without it, then demote every traversable cell with a hazard
/// centre within `margin_cells` (and drop such cells from the clear grid).
void brute_force(const DenseGrid& fused0, const DenseGrid& clearance0, const DenseGrid& clear0,
                 double margin_cells, DenseGrid& fused, DenseGrid& clearance, DenseGrid& clear) {
  fused = fused0;
  clearance = clearance0;
  clear = clear0;
  const int n = fused0.rows, k = static_cast<int>(margin_cells);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      bool near = false;
      for (int dr = -k; dr <= k; ++dr)
        for (int dc = -k; dc <= k; ++dc) {
          const int rr = r + dr, cc = c + dc;
          if ((dr || dc) && dr * dr + dc * dc <= margin_cells * margin_cells && rr >= 0 &&
              rr < n && cc >= 0 && cc < n && fused0.at(rr, cc) == kH)
            near = true;
        }
      if (!near) continue;
      if (fused0.at(r, c) == kT) {
        fused.at(r, c) = kU;
        clearance.at(r, c) = std::numeric_limits<float>::quiet_NaN();
      }
      if (fused.at(r, c) != kT) clear.at(r, c) = 0.0f;
    }
}

bool same(const DenseGrid& a, const DenseGrid& b) {
  if (a.values.size() != b.values.size()) return false;
  for (size_t i = 0; i < a.values.size(); ++i)
    if (!(a.values[i] == b.values[i] || (std::isnan(a.values[i]) && std::isnan(b.values[i]))))
      return false;
  return true;
}

TEST(ProofMargin, EqualsBruteForceOnRandomLayersWholeAndPerRegion) {
  std::mt19937 rng(34);
  std::uniform_int_distribution<int> cls(0, 9);
  for (int trial = 0; trial < 20; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    // A 1 cm layer (40 x 40) and a 4 cm one (10 x 10) over the same square; classes
    // drawn with hazards rare, ring-only flags on half the cells.
    DenseGrid fine, coarse, ring;
    fine.reset(40, 40, 0.01, 0, 0, kU);
    coarse.reset(10, 10, 0.04, 0, 0, kU);
    ring.reset(40, 40, 0.01, 0, 0, 0.0f);
    auto draw = [&](DenseGrid& g) {
      for (float& v : g.values) {
        const int k = cls(rng);
        v = k == 0 ? kH : k < 7 ? kT : kU;
      }
    };
    draw(fine);
    draw(coarse);
    for (float& v : ring.values) v = cls(rng) < 5 ? 1.0f : 0.0f;
    const std::vector<FusionInput> layers = {{&fine, 0.03, &ring}, {&coarse, 0.03, nullptr}};
    const double margin_m = trial % 2 ? 0.01 : 0.025;
    const double margin_cells = margin_m / 0.01;

    HazardFusion plain, margin;
    plain.set_finer_proof(true);
    margin.set_finer_proof(true);
    margin.set_proof_margin(margin_m, 0.01);
    DenseGrid f0, c0, k0, f, c, k, fb, cb, kb;
    plain.fuse(layers, 0.03, 40, 0.01, 0, 0, f0, c0, &k0);
    margin.fuse(layers, 0.03, 40, 0.01, 0, 0, f, c, &k);
    brute_force(f0, c0, k0, margin_cells, fb, cb, kb);
    EXPECT_TRUE(same(f, fb));
    EXPECT_TRUE(same(c, cb));
    EXPECT_TRUE(same(k, kb));

    // Change the fine layer inside a rectangle, re-fuse that rectangle grown by the
    // margin: equal to a whole pass over the changed layers.
    const int r0 = trial % 30, c0i = (7 * trial) % 30;
    const GridRect changed{r0, r0 + 8, c0i, c0i + 6};
    for (int r = changed.row0; r < changed.row1; ++r)
      for (int cc = changed.col0; cc < changed.col1; ++cc) {
        const int kk = cls(rng);
        fine.at(r, cc) = kk < 2 ? kH : kk < 7 ? kT : kU;
      }
    DirtyRegion region;
    region.add(changed);
    region.dilate(margin.proof_margin_cells(), 40, 40);
    margin.fuse(layers, 0.03, region, f, c, &k);
    DenseGrid fw, cw, kw;
    HazardFusion whole;
    whole.set_finer_proof(true);
    whole.set_proof_margin(margin_m, 0.01);
    whole.fuse(layers, 0.03, 40, 0.01, 0, 0, fw, cw, &kw);
    EXPECT_TRUE(same(f, fw));
    EXPECT_TRUE(same(c, cw));
    EXPECT_TRUE(same(k, kw));
  }
}

}  // namespace
}  // namespace hazmap
