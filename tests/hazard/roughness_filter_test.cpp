#include "hazmap/hazard/roughness_filter.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "hazmap/hazard/kernel_classifier.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

DenseGrid random_map(int rows, int cols, double unknown_fraction, unsigned seed) {
  DenseGrid g;
  g.reset(rows, cols, 0.01, 0, 0, 0.0f);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> h(-0.2f, 0.2f);
  std::uniform_real_distribution<double> u(0, 1);
  for (auto& v : g.values) v = u(rng) < unknown_fraction ? NAN : h(rng);
  return g;
}

/// Random variances where the heights are known (NaN elsewhere), to check that the
/// kernel's sigma comes from its extreme cells.
DenseGrid random_variance(const DenseGrid& h, unsigned seed) {
  DenseGrid v = h;
  std::mt19937 rng(seed + 100);
  std::uniform_real_distribution<float> u(1e-6f, 1e-4f);
  for (auto& x : v.values) x = std::isnan(x) ? NAN : u(rng);
  return v;
}

DenseGrid constant_like(const DenseGrid& h, float value) {
  DenseGrid v = h;
  for (auto& x : v.values) x = value;
  return v;
}

/// Piecewise-constant layer parameters for the roughness test alone (no wheel ring).
LayerHazardParams roughness_only(int kernel, double threshold_m, double min_fill, double k_sigma) {
  LayerHazardParams p;
  p.kernel = kernel;
  p.roughness_threshold_m = threshold_m;
  p.h_min_m = threshold_m;
  p.min_kernel_fill = min_fill;
  p.k_sigma = k_sigma;
  p.ring_tests = false;
  return p;
}

DenseGrid classify(const DenseGrid& h, const DenseGrid& var, const LayerHazardParams& p) {
  LayerGrids grids;
  grids.height = h;
  grids.variance = var;
  PiecewiseConstantClassifier classifier(p);
  DenseGrid hazard;
  HazardDiagnostics diag;
  classifier.classify(grids, hazard, diag);
  return hazard;
}

DenseGrid plane(int n, double r, double slope) {
  DenseGrid g;
  g.reset(n, n, r, 0, 0, 0.0f);
  for (int row = 0; row < n; ++row)
    for (int col = 0; col < n; ++col) g.at(row, col) = static_cast<float>(slope * g.x_of_col(col));
  return g;
}

TEST(RoughnessFilter, KernelIsACircleOfDiameterD) {
  EXPECT_EQ(kernel_half_widths(1), (std::vector<int>{0}));
  EXPECT_EQ(kernel_half_widths(3), (std::vector<int>{1, 1, 1}));
  EXPECT_EQ(kernel_half_widths(5), (std::vector<int>{1, 2, 2, 2, 1}));
  EXPECT_EQ(kernel_half_widths(7), (std::vector<int>{1, 2, 3, 3, 3, 2, 1}));
}

class RoughnessAgainstBruteForce : public ::testing::TestWithParam<int> {};

TEST_P(RoughnessAgainstBruteForce, FastPathEqualsTheQuadraticReferenceExactly) {
  const int kernel = GetParam();
  RoughnessFilter filter;
  for (unsigned seed = 0; seed < 5; ++seed) {
    const DenseGrid h = random_map(37, 41, 0.1 * seed, seed);
    const DenseGrid var = random_variance(h, seed);
    DenseGrid fast_r, fast_s, fast_f, ref_r, ref_s, ref_f;
    filter.compute(h, var, kernel, fast_r, fast_s, fast_f);
    roughness_brute_force(h, var, kernel, ref_r, ref_s, ref_f);
    for (size_t i = 0; i < h.values.size(); ++i) {
      if (std::isnan(ref_r.values[i])) {
        ASSERT_TRUE(std::isnan(fast_r.values[i])) << i;
        ASSERT_TRUE(std::isnan(fast_s.values[i])) << i;
      } else {
        ASSERT_EQ(fast_r.values[i], ref_r.values[i]) << "seed " << seed << " cell " << i;
        // Heights are continuous random values: the extreme cells are unique, so the
        // sigma of both paths comes from the same two cells.
        ASSERT_EQ(fast_s.values[i], ref_s.values[i]) << "seed " << seed << " cell " << i;
      }
      ASSERT_EQ(fast_f.values[i], ref_f.values[i]) << i;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Kernels, RoughnessAgainstBruteForce, ::testing::Values(1, 3, 5, 7, 9, 11));

TEST(RoughnessFilter, PlaneBelowMaxSlopeIsTraversableAndBorderIsUnknown) {
  // Derived threshold (D - 1) r tan(20 deg): a 19 deg plane passes, a 21 deg one does not.
  const int n = 40, kernel = 7;
  const double r = 0.01;
  const LayerHazardParams params =
      roughness_only(kernel, (kernel - 1) * r * std::tan(20 * M_PI / 180), 0.5, 3.0);
  for (const double deg : {19.0, 21.0}) {
    const DenseGrid h = plane(n, r, std::tan(deg * M_PI / 180));
    const DenseGrid hazard = classify(h, constant_like(h, 0.0f), params);
    for (int row = 0; row < n; ++row)
      for (int col = 0; col < n; ++col) {
        const bool border = row < 3 || col < 3 || row >= n - 3 || col >= n - 3;
        const auto cls = static_cast<HazardClass>(int(hazard.at(row, col)));
        if (border) ASSERT_EQ(cls, HazardClass::unknown);
        else if (deg < 20) ASSERT_EQ(cls, HazardClass::traversable);
        else ASSERT_EQ(cls, HazardClass::hazard);
      }
  }
}

TEST(RoughnessFilter, StepIsHazardOnlyWithinTheKernelRadius) {
  // A 5 cm step along x = column 20: hazard exactly where the kernel straddles it.
  const int n = 40, kernel = 5;
  DenseGrid h;
  h.reset(n, n, 0.01, 0, 0, 0.0f);
  for (int row = 0; row < n; ++row)
    for (int col = 20; col < n; ++col) h.at(row, col) = 0.05f;
  const DenseGrid hazard = classify(h, constant_like(h, 0.0f), roughness_only(kernel, 0.03, 0.5, 3.0));
  for (int col = 2; col < n - 2; ++col) {
    const auto cls = static_cast<HazardClass>(int(hazard.at(n / 2, col)));
    const bool straddles = col >= 18 && col <= 21;
    EXPECT_EQ(cls, straddles ? HazardClass::hazard : HazardClass::traversable) << col;
  }
}

TEST(RoughnessFilter, SparseKernelsAndUnobservedCellsAreUnknown) {
  const int n = 20, kernel = 5;
  DenseGrid h;
  h.reset(n, n, 0.01, 0, 0, NAN);
  h.at(10, 10) = 0.0f;  // one observed cell: its kernel is 1/21 full
  for (int col = 0; col < n; ++col) h.at(15, col) = 0.0f;  // a full row: kernel 5/21 full
  RoughnessFilter filter;
  DenseGrid rough, sigma, fill;
  filter.compute(h, constant_like(h, 1e-6f), kernel, rough, sigma, fill);
  EXPECT_FLOAT_EQ(fill.at(10, 10), 1.0f / 21.0f);
  EXPECT_FLOAT_EQ(fill.at(15, 10), 5.0f / 21.0f);
  const DenseGrid hazard =
      classify(h, constant_like(h, 1e-6f), roughness_only(kernel, 0.03, 0.2, 3.0));
  EXPECT_EQ(hazard.at(10, 10), float(HazardClass::unknown));   // kernel too empty
  EXPECT_EQ(hazard.at(15, 10), float(HazardClass::traversable));
  EXPECT_EQ(hazard.at(14, 10), float(HazardClass::unknown));   // unobserved cell
}

TEST(RoughnessFilter, NoiseBecomesUnknownNotHazardAndAClearStepStaysAHazard) {
  // A 5 cm step read by cells with 1 cm sigma: range 5 cm - 3 sqrt(2) 1 cm = 0.76 cm is
  // not > 3 cm: no evidence, and 5 + 4.2 > 3: no proof either, so unknown. With 2 mm sigma
  // the step is evidence (5 - 0.85 > 3). Flat cells with 1 cm sigma: 0 + 4.2 cm > 3 cm,
  // unknown; with 2 mm: 0.85 cm <= 3 cm, traversable.
  const int n = 40, kernel = 5;
  DenseGrid h;
  h.reset(n, n, 0.01, 0, 0, 0.0f);
  for (int row = 0; row < n; ++row)
    for (int col = 20; col < n; ++col) h.at(row, col) = 0.05f;
  const LayerHazardParams p = roughness_only(kernel, 0.03, 0.5, 3.0);
  const DenseGrid noisy = classify(h, constant_like(h, 1e-4f), p);
  const DenseGrid sharp = classify(h, constant_like(h, 4e-6f), p);
  EXPECT_EQ(noisy.at(n / 2, 20), float(HazardClass::unknown));
  EXPECT_EQ(noisy.at(n / 2, 10), float(HazardClass::unknown));
  EXPECT_EQ(sharp.at(n / 2, 20), float(HazardClass::hazard));
  EXPECT_EQ(sharp.at(n / 2, 10), float(HazardClass::traversable));
  // k = 0 is the thesis' plain comparison: noise or not, the step is a hazard.
  const DenseGrid plain = classify(h, constant_like(h, 1e-4f), roughness_only(kernel, 0.03, 0.5, 0.0));
  EXPECT_EQ(plain.at(n / 2, 20), float(HazardClass::hazard));
  EXPECT_EQ(plain.at(n / 2, 10), float(HazardClass::traversable));
}

TEST(RoughnessFilter, KernelEvidenceMakesAnUnobservedCellAHazardButNeverTraversable) {
  // The rock's face is observed, the cell itself is not: the kernel's step is evidence.
  const int n = 30, kernel = 5;
  DenseGrid h;
  h.reset(n, n, 0.01, 0, 0, 0.0f);
  for (int row = 0; row < n; ++row)
    for (int col = 16; col < n; ++col) h.at(row, col) = 0.08f;
  h.at(15, 15) = NAN;
  h.at(15, 5) = NAN;
  const DenseGrid hazard = classify(h, constant_like(h, 1e-6f), roughness_only(kernel, 0.03, 0.5, 3.0));
  EXPECT_EQ(hazard.at(15, 15), float(HazardClass::hazard));
  EXPECT_EQ(hazard.at(15, 5), float(HazardClass::unknown));  // flat kernel, but no cell data
}


// ---- Detrended roughness (hazard.roughness: detrended) ----

// The classifier in bands of rows on threads (set_parallel) against one thread: every
// cell's class and kernel statistics bit for bit, raw and detrended roughness, with the
// wheel ring, whole and over a region (the incremental path) on 2 and 3 threads.
TEST(PiecewiseConstantClassifier, BandsOnThreadsEqualOneThread) {
  // A layer with holes: smooth ground (mm noise) on the left, rough (+-2 cm) on the
  // right, so that every class occurs.
  DenseGrid h = random_map(90, 77, 0.1, 17);
  for (int row = 0; row < h.rows; ++row)
    for (int col = 0; col < h.cols; ++col) h.at(row, col) *= col < 40 ? 0.01f : 0.1f;
  LayerGrids grids;
  grids.height = h;
  grids.variance = random_variance(h, 17);
  for (float& v : grids.variance.values) v *= 0.01f;
  for (const bool detrended : {false, true})
    for (const int threads : {2, 3}) {
      LayerHazardParams p = roughness_only(7, 0.02, 0.5, 2.0);
      p.ring_tests = true;
      p.wheelbase_m = 0.2;
      p.detrended_roughness = detrended;
      const std::string what = std::string(detrended ? "detrended" : "raw") + ", " +
                               std::to_string(threads) + " threads";
      PiecewiseConstantClassifier one(p), many(p);
      const testing::ThreadsFor pool(threads);
      many.set_parallel(&pool);
      DenseGrid a, b;
      HazardDiagnostics da, db;
      one.classify(grids, a, da);
      many.classify(grids, b, db);
      // A region: the rows a frame changed, classified again into the same grids.
      const GridRect region{11, 70, 5, 60};
      one.classify(grids, region, a, da);
      many.classify(grids, region, b, db);
      auto same = [&](const DenseGrid& x, const DenseGrid& y, const char* name) {
        ASSERT_EQ(x.values.size(), y.values.size()) << what << ", " << name;
        int differ = 0;
        for (size_t i = 0; i < x.values.size(); ++i)
          differ +=
              !(x.values[i] == y.values[i] || (std::isnan(x.values[i]) && std::isnan(y.values[i])));
        EXPECT_EQ(differ, 0) << what << ", " << name;
      };
      same(a, b, "class");
      same(da.kernel_range, db.kernel_range, "range");
      same(da.kernel_sigma, db.kernel_sigma, "sigma");
      same(da.kernel_fill, db.kernel_fill, "fill");
      if (detrended) {
        same(da.kernel_slope, db.kernel_slope, "slope");
      }
      // Something to compare: each class on many cells.
      int count[3] = {0, 0, 0};
      for (const float v : a.values) ++count[static_cast<int>(v)];
      for (int c = 0; c < 3; ++c) EXPECT_GT(count[c], 200) << what << ", class " << c;
    }
}

TEST(KernelPlane, RecoversAPlaneALineAlongCollinearCellsAndAMean) {
  // Five non-collinear cells on z = 0.3 + 0.02 dx - 0.05 dy.
  const int dx[] = {-1, 0, 1, 0, 2}, dy[] = {0, -1, 0, 1, 2};
  float z[5];
  for (int i = 0; i < 5; ++i) z[i] = static_cast<float>(0.3 + 0.02 * dx[i] - 0.05 * dy[i]);
  KernelPlane p = fit_kernel_plane(dx, dy, z, 5);
  EXPECT_NEAR(p.a, 0.3, 1e-6);
  EXPECT_NEAR(p.b, 0.02, 1e-6);
  EXPECT_NEAR(p.c, -0.05, 1e-6);
  // Cells on the diagonal dx = dy = t with z = 1 + 0.4 t: the minimum-norm plane rises
  // 0.4 per diagonal step, split equally over x and y, and is flat across the line.
  const int t[] = {-2, -1, 0, 1, 3};
  float zl[5];
  for (int i = 0; i < 5; ++i) zl[i] = static_cast<float>(1.0 + 0.4 * t[i]);
  p = fit_kernel_plane(t, t, zl, 5);
  EXPECT_NEAR(p.a, 1.0, 1e-6);
  EXPECT_NEAR(p.b, 0.2, 1e-6);
  EXPECT_NEAR(p.c, 0.2, 1e-6);
  // One cell, twice: the mean, no slope.
  const int o[] = {1, 1};
  const float zo[] = {0.5f, 0.7f};
  p = fit_kernel_plane(o, o, zo, 2);
  EXPECT_NEAR(p.a + p.b + p.c, 0.6, 1e-6);
  EXPECT_EQ(p.b, 0.0);
  EXPECT_EQ(p.c, 0.0);
}

/// Independent reference: Eigen's QR least squares over the kernel's observed cells,
/// then the residual range and the variances of the cells it comes from.
void detrended_reference(const DenseGrid& h, const DenseGrid& var, int kernel, int row, int col,
                         double* range, double* sigma, double* fill) {
  const std::vector<int> widths = kernel_half_widths(kernel);
  const int half = (kernel - 1) / 2;
  std::vector<Eigen::Vector3d> rows;
  std::vector<double> z, v;
  int cells = 0;
  for (int dy = -half; dy <= half; ++dy)
    for (int dx = -widths[dy + half]; dx <= widths[dy + half]; ++dx) {
      ++cells;
      const float hz = h.at(row + dy, col + dx);
      if (std::isnan(hz)) continue;
      rows.emplace_back(1.0, dx, dy);
      z.push_back(hz);
      v.push_back(var.at(row + dy, col + dx));
    }
  *fill = double(z.size()) / cells;
  Eigen::MatrixXd A(rows.size(), 3);
  Eigen::VectorXd b(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) A.row(i) = rows[i].transpose(), b(i) = z[i];
  const Eigen::VectorXd e = b - A * A.colPivHouseholderQr().solve(b);
  Eigen::Index hi = 0, lo = 0;
  e.maxCoeff(&hi);
  e.minCoeff(&lo);
  *range = e(hi) - e(lo);
  *sigma = std::sqrt(v[hi] + v[lo]);
}

TEST(DetrendedRoughness, IsZeroOnASteepPlaneAndMatchesAnEigenFitOnRandomTerrain) {
  const int kernel = 7;
  RoughnessFilter filter;
  filter.set_detrended(true);
  DenseGrid range, sigma, fill;
  // A 40 deg plane with holes: the range sees 6 cells x 0.84 = 5 cm, the residuals none.
  DenseGrid steep = plane(40, 0.01, std::tan(40 * M_PI / 180));
  const DenseGrid holes = random_map(40, 40, 0.3, 7);
  for (size_t i = 0; i < steep.values.size(); ++i)
    if (std::isnan(holes.values[i])) steep.values[i] = NAN;
  DenseGrid slope, slope_sigma;
  filter.compute(steep, constant_like(steep, 1e-6f), kernel, range, sigma, fill, &slope, &slope_sigma);
  int checked = 0;
  for (int row = 3; row < 37; ++row)
    for (int col = 3; col < 37; ++col)
      if (fill.at(row, col) > 0.3f) {
        EXPECT_LT(std::abs(range.at(row, col)), 2e-6) << row << "," << col;  // float heights
        EXPECT_NEAR(slope.at(row, col), std::tan(40 * M_PI / 180), 1e-4) << row << "," << col;
        // Independent: trace of sigma^2 (A^T A)^-1 over the slope terms, A = [1 dx dy].
        std::vector<Eigen::Vector3d> a;
        const std::vector<int> widths = kernel_half_widths(kernel);
        for (int dy = -3; dy <= 3; ++dy)
          for (int dx = -widths[dy + 3]; dx <= widths[dy + 3]; ++dx)
            if (!std::isnan(steep.at(row + dy, col + dx))) a.emplace_back(1.0, dx, dy);
        Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
        for (const auto& v : a) ata += v * v.transpose();
        const Eigen::Matrix3d inv = ata.inverse();
        EXPECT_NEAR(slope_sigma.at(row, col), std::sqrt(1e-6 * (inv(1, 1) + inv(2, 2))) / 0.01,
                    1e-5) << row << "," << col;
        ++checked;
      }
  EXPECT_GT(checked, 500);
  // Random heights (+-0.2 m) with 40 % holes: every cell against the reference.
  const DenseGrid h = random_map(30, 30, 0.4, 11);
  const DenseGrid var = random_variance(h, 11);
  filter.compute(h, var, kernel, range, sigma, fill);
  for (int row = 0; row < 30; ++row)
    for (int col = 0; col < 30; ++col) {
      if (row < 3 || col < 3 || row >= 27 || col >= 27) {  // kernel leaves the grid
        EXPECT_TRUE(std::isnan(range.at(row, col)));
        continue;
      }
      double r_ref, s_ref, f_ref;
      detrended_reference(h, var, kernel, row, col, &r_ref, &s_ref, &f_ref);
      EXPECT_NEAR(range.at(row, col), r_ref, 1e-5) << row << "," << col;
      EXPECT_NEAR(sigma.at(row, col), s_ref, 1e-7) << row << "," << col;
      EXPECT_NEAR(fill.at(row, col), f_ref, 1e-6) << row << "," << col;
    }
  // A region's cells equal the whole grid's (SPEC 8.6), the rest untouched.
  DenseGrid r2 = range, s2 = sigma, f2 = fill;
  for (auto& x : r2.values) x = -1.0f;
  filter.compute(h, var, kernel, GridRect{5, 17, 8, 21}, r2, s2, f2);
  for (int row = 0; row < 30; ++row)
    for (int col = 0; col < 30; ++col) {
      const bool inside = row >= 5 && row < 17 && col >= 8 && col < 21;
      const float want = inside ? range.at(row, col) : -1.0f;
      if (std::isnan(want)) EXPECT_TRUE(std::isnan(r2.at(row, col)));
      else EXPECT_EQ(r2.at(row, col), want) << row << "," << col;
    }
}

}  // namespace
}  // namespace hazmap
