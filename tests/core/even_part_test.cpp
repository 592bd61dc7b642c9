// even_part: the split every parallel loop of the library uses (stereo strips, the kernel
// classifier's bands, HoleMarker, LayerStack's sets). Checked against a count of its own:
// the parts tile [0, n) in order and their sizes are floor(n / parts) or one more.

#include <gtest/gtest.h>

#include <climits>

#include "hazmap/core/parallel_for.hpp"

namespace hazmap {
namespace {

TEST(EvenPart, TilesTheRangeInOrderWithSizesWithinOne) {
  for (int n : {0, 1, 2, 7, 64, 100, 1001}) {
    for (int parts : {1, 2, 3, 4, 7, 16, 200}) {
      int next = 0, total = 0;
      for (int i = 0; i < parts; ++i) {
        const EvenPart p = even_part(n, parts, i);
        EXPECT_EQ(p.begin, next) << "n " << n << " parts " << parts << " part " << i;
        const int size = p.end - p.begin;
        EXPECT_TRUE(size == n / parts || size == n / parts + 1)
            << "n " << n << " parts " << parts << " part " << i << " size " << size;
        next = p.end;
        total += size;
      }
      EXPECT_EQ(next, n);
      EXPECT_EQ(total, n);
    }
  }
}

// n * (i + 1) overflows int for large ranges (a full-resolution image's pixels times a
// part index): the split is computed in 64 bits.
TEST(EvenPart, LargeRangesDoNotOverflow) {
  const int n = INT_MAX - 1, parts = 3;
  EXPECT_EQ(even_part(n, parts, 0).begin, 0);
  EXPECT_EQ(even_part(n, parts, 0).end, 715827882);
  EXPECT_EQ(even_part(n, parts, 1).end, 1431655764);
  EXPECT_EQ(even_part(n, parts, 2).end, n);
}

}  // namespace
}  // namespace hazmap
