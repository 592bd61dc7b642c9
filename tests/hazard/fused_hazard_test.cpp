#include "hazmap/hazard/fused_hazard.hpp"

#include <gtest/gtest.h>

namespace hazmap {
namespace {

TEST(FusedHazard, HazardWinsThenKnowledgeThenUnknown) {
  // Fine 4 x 4 at 1 m and coarse 2 x 2 at 2 m, both centred on the origin.
  DenseGrid fine, coarse, fused;
  fine.reset(4, 4, 1.0, 0, 0, float(HazardClass::unknown));
  coarse.reset(2, 2, 2.0, 0, 0, float(HazardClass::unknown));
  fine.at(0, 0) = float(HazardClass::traversable);
  fine.at(0, 1) = float(HazardClass::hazard);
  coarse.at(0, 0) = float(HazardClass::traversable);  // covers fine rows 0-1, cols 0-1
  coarse.at(1, 1) = float(HazardClass::hazard);       // covers fine rows 2-3, cols 2-3
  fine.at(3, 3) = float(HazardClass::traversable);    // coarse says hazard: hazard wins
  fuse_hazards({&fine, &coarse}, fused);
  EXPECT_EQ(fused.at(0, 0), float(HazardClass::traversable));
  EXPECT_EQ(fused.at(0, 1), float(HazardClass::hazard));
  EXPECT_EQ(fused.at(1, 0), float(HazardClass::traversable));  // only the coarse layer knows
  EXPECT_EQ(fused.at(0, 2), float(HazardClass::unknown));
  EXPECT_EQ(fused.at(2, 2), float(HazardClass::hazard));
  EXPECT_EQ(fused.at(3, 3), float(HazardClass::hazard));
}

TEST(FusedHazard, CoarseLayerCoversBeyondTheFineExtentOnlyWhereItIsDefined) {
  DenseGrid fine, coarse, fused;
  fine.reset(2, 2, 1.0, 10, 0, float(HazardClass::unknown));  // x in [9, 11]
  coarse.reset(2, 2, 1.0, 0, 0, float(HazardClass::hazard));  // x in [-1, 1]: disjoint
  fuse_hazards({&fine, &coarse}, fused);
  for (float v : fused.values) EXPECT_EQ(v, float(HazardClass::unknown));
}

}  // namespace
}  // namespace hazmap
