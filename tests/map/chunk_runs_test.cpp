// find_runs (both versions) and run_height_sums against plain scalar double versions.

#include "hazmap/map/internal/chunk_runs.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

namespace hazmap {
namespace {

/// Slots in runs of random length (1 to ~60, some -1), then garbage past `count`.
std::vector<int> random_runs(int count, std::uint64_t seed) {
  std::vector<int> slot(PointChunk::kStride, 7);
  std::mt19937_64 rng(seed);
  std::geometric_distribution<int> run_length(0.12);
  for (int i = 0, value = 0; i < count; ++value) {
    const int len = 1 + run_length(rng);
    const int s = value % 5 == 4 ? -1 : value;  // outside cells make runs too
    for (int k = i; k < std::min(count, i + len); ++k) slot[k] = s;
    i += len;
  }
  return slot;
}

std::vector<int> scalar_starts(const std::vector<int>& slot, int count) {
  std::vector<int> starts;
  for (int i = 0; i < count; ++i)
    if (i == 0 || slot[i] != slot[i - 1]) starts.push_back(i);
  starts.push_back(count);
  return starts;
}

TEST(FindRuns, ListsEveryRunStartBothVersions) {
  for (int count : {0, 1, 7, 8, 9, 17, 1000, PointChunk::kCapacity}) {
    const std::vector<int> slot = random_runs(count, 100 + count);
    const std::vector<int> want = scalar_starts(slot, count);
    for (auto* find : {&find_runs, &find_runs_portable}) {
      std::vector<int> starts(PointChunk::kStride + 8, -5), run_slot(starts.size(), -5);
      const int runs = find(slot.data(), count, starts.data(), run_slot.data());
      if (count == 0) {
        EXPECT_EQ(runs, 0);
        continue;
      }
      ASSERT_EQ(runs + 1, static_cast<int>(want.size())) << "count " << count;
      for (int r = 0; r <= runs; ++r)
        ASSERT_EQ(starts[r], want[r]) << "count " << count << " run " << r;
      for (int r = 0; r < runs; ++r)
        ASSERT_EQ(run_slot[r], slot[want[r]]) << "count " << count << " run " << r;
    }
  }
}

TEST(FindRuns, OneRunAndAllDifferent) {
  std::vector<int> same(PointChunk::kStride, 3), distinct(PointChunk::kStride);
  for (int i = 0; i < PointChunk::kStride; ++i) distinct[i] = i;
  std::vector<int> starts(PointChunk::kStride + 8), run_slot(starts.size());
  EXPECT_EQ(find_runs(same.data(), 1000, starts.data(), run_slot.data()), 1);
  EXPECT_EQ(starts[1], 1000);
  ASSERT_EQ(find_runs(distinct.data(), 1000, starts.data(), run_slot.data()), 1000);
  for (int r = 0; r <= 1000; ++r) ASSERT_EQ(starts[r], r);
  for (int r = 0; r < 1000; ++r) ASSERT_EQ(run_slot[r], r);
}

TEST(RunHeightSums, EqualsScalarDoubleSums) {
  const int count = 1000;
  const std::vector<int> slot = random_runs(count, 21);
  std::vector<int> starts(PointChunk::kStride + 8), run_slot(starts.size());
  const int runs = find_runs(slot.data(), count, starts.data(), run_slot.data());
  ASSERT_GT(runs, 17);  // several blocks of eight runs and a partial one
  ASSERT_NE(runs % 8, 0);
  std::mt19937_64 rng(22);
  std::normal_distribution<double> nz(0.0, 0.001);
  std::uniform_real_distribution<double> wd(1e4, 4e4);
  std::vector<float> w(PointChunk::kStride, std::numeric_limits<float>::quiet_NaN());
  std::vector<float> z(PointChunk::kStride, std::numeric_limits<float>::quiet_NaN());
  for (int i = 0; i < count; ++i) {  // |z| ~ 80 m, 1 mm spread, a 5 cm step every 100
    z[i] = float(-80.0 + 0.05 * ((i / 100) % 2) + nz(rng));
    w[i] = float(wd(rng));
  }
  std::vector<float> sum_w(PointChunk::kStride + 8, -1), sum_wz(PointChunk::kStride + 8, -1);
  std::vector<float> first_z(PointChunk::kStride + 8, -1);
  run_height_sums(starts.data(), runs, w.data(), z.data(), sum_w.data(), sum_wz.data(),
                  first_z.data());
  int longest = 0;
  for (int r = 0; r < runs; ++r) {
    const double zb = z[starts[r]];
    double W = 0, WZ = 0;
    for (int k = starts[r]; k < starts[r + 1]; ++k) {
      W += w[k];
      WZ += double(w[k]) * (double(z[k]) - zb);
    }
    longest = std::max(longest, starts[r + 1] - starts[r]);
    ASSERT_EQ(first_z[r], z[starts[r]]) << "run " << r;
    ASSERT_NEAR(sum_w[r], W, 1e-6 * W) << "run " << r;
    // The mean about the run's first height, in metres (float lanes keep ~1e-10 m).
    ASSERT_NEAR(double(sum_wz[r]) / sum_w[r], WZ / W, 1e-8) << "run " << r;
  }
  EXPECT_GT(longest, 24);  // the loop past two vectors ran
}

}  // namespace
}  // namespace hazmap
