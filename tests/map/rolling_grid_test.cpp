#include "hazmap/map/rolling_grid.hpp"

#include <cmath>
#include <map>
#include <string>
#include <random>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"
#include "hazmap/map/rolling_layer.hpp"
#include "hazmap/rules/bananas.hpp"

namespace hazmap {
namespace {

bool robot_in_central_block(const RollingGrid& g, double x, double y) {
  const CellIndex ix = cell_index(x, g.resolution_m()), iy = cell_index(y, g.resolution_m());
  const CellIndex cx = g.origin_x() + g.size() / 2, cy = g.origin_y() + g.size() / 2;
  return (ix == cx - 1 || ix == cx) && (iy == cy - 1 || iy == cy);
}

TEST(GridMath, IndexAndWrapHandleNegativeCoordinates) {
  EXPECT_EQ(cell_index(-0.001, 0.01), -1);
  EXPECT_EQ(cell_index(0.0, 0.01), 0);
  EXPECT_EQ(cell_index(0.0399, 0.04), 0);
  EXPECT_EQ(wrap_index(-1, 8), 7);
  EXPECT_EQ(wrap_index(-8, 8), 0);
  EXPECT_EQ(wrap_index(17, 8), 1);
  EXPECT_DOUBLE_EQ(cell_center(-1, 0.5), -0.25);
}

TEST(RollingGrid, FirstPlacementCentresTheRobot) {
  RollingGrid g(8, 0.1);
  const NewRegions r = g.move_to(0.33, -0.12);
  ASSERT_EQ(r.count, 1);
  EXPECT_EQ(r.ranges[0].x1 - r.ranges[0].x0, 8);
  EXPECT_TRUE(robot_in_central_block(g, 0.33, -0.12));
  EXPECT_NEAR(g.center_x_m(), 0.3, 1e-12);
  EXPECT_NEAR(g.center_y_m(), -0.1, 1e-12);
}

TEST(RollingGrid, RobotAlwaysInCentralBlockOnARandomWalk) {
  RollingGrid g(16, 0.04);
  std::mt19937 rng(3);
  std::normal_distribution<double> step(0.0, 0.03);
  double x = 0.0, y = 0.0;
  g.move_to(x, y);
  for (int i = 0; i < 2000; ++i) {
    x += step(rng);
    y += step(rng);
    g.move_to(x, y);
    ASSERT_TRUE(robot_in_central_block(g, x, y)) << "step " << i;
  }
}

TEST(RollingGrid, JitterOfFourTenthsOfACellNeverMovesTheMap) {
  RollingGrid g(8, 0.1);
  // Drive so the robot has just crossed into a new cell, then jitter around it.
  g.move_to(0.0, 0.0);
  for (double x = 0.0; x < 0.52; x += 0.01) g.move_to(x, 0.0);
  const CellIndex ox = g.origin_x(), oy = g.origin_y();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.04, 0.04);  // +-0.4 cell
  for (int i = 0; i < 500; ++i) {
    const NewRegions r = g.move_to(0.52 + jitter(rng), 0.0 + jitter(rng));
    ASSERT_EQ(r.count, 0);
    ASSERT_EQ(g.origin_x(), ox);
    ASSERT_EQ(g.origin_y(), oy);
  }
}

/// Reference: a map keyed by global index, shifted by copying, cleared outside the window.
TEST(RollingLayer, KeepsCellsInViewAndClearsCellsThatLeaveLikeACopyAndShiftReference) {
  const int n = 10;
  const double r = 0.1;
  RollingLayer<BananasRule> layer(n, r, {});
  std::map<std::pair<CellIndex, CellIndex>, float> reference;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> offset(-0.6, 0.6);
  std::uniform_real_distribution<double> dir(-0.09, 0.09);
  double x = 0.05, y = 0.05;
  for (int frame = 0; frame < 300; ++frame) {
    x += dir(rng) + 0.03;  // drifts forward, sometimes jumps back a little
    y += dir(rng);
    layer.begin_frame(x, y, 0);
    const RollingGrid& g = layer.grid();
    // Reference: forget everything outside the window.
    for (auto it = reference.begin(); it != reference.end();)
      it = g.contains(it->first.first, it->first.second) ? std::next(it) : reference.erase(it);
    PointCloud cloud;
    for (int k = 0; k < 20; ++k) {
      Measurement m{};
      m.p_W = Eigen::Vector3f(float(x + offset(rng)), float(y + offset(rng)), float(frame + k));
      cloud.push_back(m);
      const CellIndex ix = cell_index(m.p_W.x(), r), iy = cell_index(m.p_W.y(), r);
      if (g.contains(ix, iy)) reference[{ix, iy}] = m.p_W.z();
    }
    layer.insert(MapPoints(cloud));
    for (CellIndex iy = g.origin_y(); iy < g.origin_y() + n; ++iy)
      for (CellIndex ix = g.origin_x(); ix < g.origin_x() + n; ++ix) {
        const auto it = reference.find({ix, iy});
        const float h = BananasRule::height(layer.cell(ix, iy));
        if (it == reference.end()) {
          ASSERT_TRUE(std::isnan(h)) << "frame " << frame << " cell " << ix << "," << iy;
        } else {
          ASSERT_EQ(h, it->second) << "frame " << frame << " cell " << ix << "," << iy;
        }
      }
  }
}

TEST(RollingLayer, MovingKCellsKeepsValuesOfCellsStillInView) {
  RollingLayer<BananasRule> layer(8, 1.0, {});
  layer.begin_frame(0.1, 0.1, 0);  // window x, y in [-4, 4)
  ASSERT_EQ(layer.grid().origin_x(), -4);
  PointCloud cloud;
  for (int iy = -4; iy < 4; ++iy)
    for (int ix = -4; ix < 4; ++ix) {
      Measurement m{};
      m.p_W = Eigen::Vector3f(float(ix) + 0.5f, float(iy) + 0.5f, float(100 * ix + iy));
      cloud.push_back(m);
    }
  EXPECT_EQ(layer.insert(MapPoints(cloud)), 64u);
  layer.begin_frame(3.5, 0.1, 0);  // 3 cells east of the block: the window shifts by 3
  EXPECT_EQ(layer.grid().origin_x(), -4 + 3);
  for (int iy = -4; iy < 4; ++iy)
    for (int ix = -1; ix < 7; ++ix) {
      const float h = BananasRule::height(layer.cell(ix, iy));
      if (ix < 4) EXPECT_EQ(h, float(100 * ix + iy));
      else EXPECT_TRUE(std::isnan(h));
    }
}

TEST(RollingLayer, JumpLargerThanTheWindowClearsEverything) {
  RollingLayer<BananasRule> layer(4, 1.0, {});
  layer.begin_frame(0, 0, 0);
  PointCloud cloud(1);
  cloud[0].p_W = Eigen::Vector3f(0.5f, 0.5f, 1.0f);
  layer.insert(MapPoints(cloud));
  layer.begin_frame(100, 0, 0);
  layer.begin_frame(0, 0, 0);
  EXPECT_TRUE(std::isnan(BananasRule::height(layer.cell(0, 0))));
}

// Issue 24: x = 1e300 (or a resolution of 1e-300) made llround(x / r) overflow to
// INT64_MIN and the map was written centred at -9.2e16 m with exit 0. The position is
// refused before any index arithmetic, naming the value and the 2^30-cell limit.
TEST(RollingGrid, PositionBeyondTwoToTheThirtyCellsIsRefused) {
  auto message = [](RollingGrid& g, double x, double y) {
    try {
      g.move_to(x, y);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  RollingGrid g(8, 0.01);
  EXPECT_EQ(message(g, 1e300, 0.0),
            "map: robot position x = 1e+300 m is 1e+302 cells of a 0.01 m layer: |x / "
            "resolution| must stay below 2^30 cells (a pose far outside any traverse, or a bad "
            "pose file)");
  EXPECT_FALSE(g.placed());
  EXPECT_NE(message(g, 0.0, -1.1e7).find("robot position y = -1.1e+07 m"), std::string::npos);
  EXPECT_NE(message(g, std::nan(""), 0.0), "");
  EXPECT_NE(message(g, 0.0, HUGE_VAL), "");
  RollingGrid tiny(8, 1e-300);
  EXPECT_NE(message(tiny, 1.0, 0.0).find("must stay below 2^30 cells"), std::string::npos);
  // Within the limit: placed, and the centre is where the robot is.
  EXPECT_EQ(message(g, 1e7, -1e7), "");
  EXPECT_NEAR(g.center_x_m(), 1e7, 0.01);
  EXPECT_NEAR(g.center_y_m(), -1e7, 0.01);
  // After placement too (the follow path uses floor, not llround).
  EXPECT_NE(message(g, 1e300, 0.0), "");
  EXPECT_NEAR(g.center_x_m(), 1e7, 0.01);
}

}  // namespace
}  // namespace hazmap
