// KalmanRule::merge_chunk_runs (eight runs per SIMD batch) against the same runs merged
// one after another with merge_run (merge_chunk_runs_scalar, itself tested against an
// explicit double merge in kalman_test.cpp).

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "hazmap/map/internal/chunk_runs.hpp"
#include "hazmap/rules/kalman.hpp"

namespace hazmap {
namespace {

TEST(KalmanChunkRuns, BatchedMergeEqualsRunByRun) {
  constexpr int kCells = 64;  // few cells: runs of one cell meet inside a batch of eight
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> cell(0, kCells - 1), len(1, 12);
  int batches_with_repeats = 0, batches = 0;
  for (const KalmanRule::Config cfg :
       {KalmanRule::Config{1e-6, 1e-6}, KalmanRule::Config{2e-3, 0.0}, KalmanRule::Config{0, 0}}) {
    for (int trial = 0; trial < 20; ++trial) {
      // Slots in runs: mostly a fresh cell, sometimes the cell two runs back (a scan line
      // jittering over a cell edge), sometimes outside the window (-1).
      std::vector<int> slot(PointChunk::kStride, 0);
      std::vector<int> run_cells;
      const int count = 200 + 800 * (trial % 2) + trial;
      for (int i = 0; i < count;) {
        int s = cell(rng);
        const double pick = u(rng);
        if (pick < 0.1 && run_cells.size() >= 2) s = run_cells[run_cells.size() - 2];
        if (pick > 0.93) s = -1;
        if (!run_cells.empty() && s == run_cells.back()) continue;
        run_cells.push_back(s);
        for (int k = len(rng); k > 0 && i < count; --k) slot[i++] = s;
      }
      std::vector<float> w(PointChunk::kStride), z(PointChunk::kStride);
      for (int i = 0; i < count; ++i) {
        z[i] = float(-80.0 + 0.05 * u(rng));  // far from 0, a few cm of terrain
        w[i] = u(rng) < 0.02 ? 0.0f : float(1e3 + 1e5 * u(rng));  // some weightless points
      }
      ChunkRuns runs(true);
      runs.find(slot.data(), count);
      runs.sum_heights(w.data(), z.data());
      // Cells: cleared, known and at the floor; stamps behind, at and ahead of the frame.
      const std::uint32_t frame = 10;
      std::vector<KalmanRule::Cell> cells(kCells);
      for (int s = 0; s < kCells; ++s) {
        if (s % 5 != 0) KalmanRule::update(cfg, cells[s], -80.0 + 0.05 * u(rng), 1e-6 + 1e-4 * u(rng));
        cells[s].stamp = static_cast<std::uint32_t>(s % 13);
      }
      std::vector<KalmanRule::Cell> want_cells = cells;
      const std::size_t used = KalmanRule::merge_chunk_runs(cfg, cells.data(), frame, runs);
      const std::size_t want_used =
          KalmanRule::merge_chunk_runs_scalar(cfg, want_cells.data(), frame, runs);
      std::size_t inside = 0;
      for (int i = 0; i < count; ++i) inside += slot[i] >= 0;
      EXPECT_EQ(used, inside);
      EXPECT_EQ(want_used, inside);
      for (int s = 0; s < kCells; ++s) {
        EXPECT_EQ(cells[s].stamp, want_cells[s].stamp) << "cell " << s;
        EXPECT_EQ(KalmanRule::known(cells[s]), KalmanRule::known(want_cells[s])) << "cell " << s;
        if (!KalmanRule::known(want_cells[s])) continue;
        // Same double steps in both: the mean to 1e-12 m, the float precision to 1 ulp.
        EXPECT_NEAR(KalmanRule::mean(cells[s]), KalmanRule::mean(want_cells[s]), 1e-12)
            << "cell " << s;
        EXPECT_NEAR(cells[s].precision, want_cells[s].precision, 1.2e-7 * want_cells[s].precision)
            << "cell " << s;
      }
      for (int b = 0; b + 8 <= runs.size(); b += 8) {
        ++batches;
        bool repeat = false;
        for (int i = b; i < b + 8; ++i)
          for (int j = i + 1; j < b + 8; ++j) repeat |= runs.slot(i) == runs.slot(j);
        batches_with_repeats += repeat;
      }
    }
  }
  // Both kinds of batch were exercised.
  EXPECT_GT(batches_with_repeats, 50);
  EXPECT_GT(batches - batches_with_repeats, 50);
}

}  // namespace
}  // namespace hazmap
