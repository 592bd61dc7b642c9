#include "hazmap/hazard/roughness_filter.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

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
    DenseGrid fast_r, fast_f, ref_r, ref_f;
    filter.compute(h, kernel, fast_r, fast_f);
    roughness_brute_force(h, kernel, ref_r, ref_f);
    for (size_t i = 0; i < h.values.size(); ++i) {
      if (std::isnan(ref_r.values[i])) {
        ASSERT_TRUE(std::isnan(fast_r.values[i])) << i;
      } else {
        ASSERT_EQ(fast_r.values[i], ref_r.values[i]) << "seed " << seed << " cell " << i;
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
  RoughnessParams params{kernel, (kernel - 1) * r * std::tan(20 * M_PI / 180), 0.5};
  RoughnessFilter filter;
  for (const double deg : {19.0, 21.0}) {
    const DenseGrid h = plane(n, r, std::tan(deg * M_PI / 180));
    DenseGrid rough, fill, hazard;
    filter.compute(h, kernel, rough, fill);
    classify_roughness(h, rough, fill, params, hazard);
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
  RoughnessFilter filter;
  DenseGrid rough, fill, hazard;
  filter.compute(h, kernel, rough, fill);
  classify_roughness(h, rough, fill, RoughnessParams{kernel, 0.03, 0.5}, hazard);
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
  DenseGrid rough, fill, hazard;
  filter.compute(h, kernel, rough, fill);
  EXPECT_FLOAT_EQ(fill.at(10, 10), 1.0f / 21.0f);
  EXPECT_FLOAT_EQ(fill.at(15, 10), 5.0f / 21.0f);
  classify_roughness(h, rough, fill, RoughnessParams{kernel, 0.03, 0.2}, hazard);
  EXPECT_EQ(hazard.at(10, 10), float(HazardClass::unknown));   // kernel too empty
  EXPECT_EQ(hazard.at(15, 10), float(HazardClass::traversable));
  EXPECT_EQ(hazard.at(14, 10), float(HazardClass::unknown));   // unobserved cell
}

}  // namespace
}  // namespace hazmap
