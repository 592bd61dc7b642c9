// The wheel ring's tests on partial rings (issue 34): exact samples holding an opposite
// pair and a third sample prove as the full ring does, from their plane; fewer give
// hazard evidence only. The plane and its variance are checked against an independent
// least-squares fit (Eigen's QR) of the same samples, at the edge of each test's k-sigma
// margin, over every subset of the ring.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "hazmap/hazard/wheel_ring.hpp"

namespace hazmap {
namespace {

constexpr double kRadius = 0.15, kK = 3.0, kTanMax = 0.364, kHMin = 0.03;
constexpr int kN = WheelRing::kSamples;

/// Samples of the plane z = c + gx x + gy y on the ring, each with variance var; samples
/// whose bit is clear in `exact_mask` are left unknown.
void plane_ring(double c, double gx, double gy, double var, unsigned exact_mask,
                RingSample (&s)[kN]) {
  for (int k = 0; k < kN; ++k) {
    const double x = kRadius * std::cos(k * M_PI / 4), y = kRadius * std::sin(k * M_PI / 4);
    s[k] = RingSample{};
    if (!(exact_mask >> k & 1u)) continue;
    s[k] = {c + gx * x + gy * y, var, true, true};
  }
}

/// Whether a mask of exact samples may prove: an opposite pair and a third sample.
bool qualifies(unsigned mask) {
  bool pair = false;
  for (int i = 0; i < kN / 2; ++i) pair = pair || ((mask >> i & 1u) && (mask >> (i + kN / 2) & 1u));
  int n = 0;
  for (int k = 0; k < kN; ++k) n += mask >> k & 1u;
  return pair && n >= 3;
}

/// Independent fit: least squares of the plane (c, gx, gy) to the exact samples by QR,
/// and the variances of c and of the gradient (trace of its covariance) by propagating
/// each sample's variance through the solve, one sample at a time.
struct Fit {
  double var_c, var_g;
};
Fit batch_fit(unsigned mask, double var) {
  std::vector<int> used;
  for (int k = 0; k < kN; ++k)
    if (mask >> k & 1u) used.push_back(k);
  Eigen::MatrixXd A(used.size(), 3);
  for (size_t j = 0; j < used.size(); ++j)
    A.row(j) << 1.0, kRadius * std::cos(used[j] * M_PI / 4), kRadius * std::sin(used[j] * M_PI / 4);
  const auto qr = A.colPivHouseholderQr();
  Fit f{0, 0};
  for (size_t j = 0; j < used.size(); ++j) {  // d theta / d z_j, scaled by sigma_j
    const Eigen::Vector3d d = qr.solve(Eigen::VectorXd::Unit(used.size(), j));
    f.var_c += var * d(0) * d(0);
    f.var_g += var * (d(1) * d(1) + d(2) * d(2));
  }
  return f;
}

HazardClass slope_class(const RingSample (&s)[kN]) {
  WheelRing ring(kRadius, kK);
  Evidence ev(kK);
  ring.slope_test(s, kTanMax, ev);
  return ev.result();
}
HazardClass step_class(double h, double var_h, const RingSample (&s)[kN]) {
  WheelRing ring(kRadius, kK);
  Evidence ev(kK);
  ring.step_test(h, var_h, s, kHMin, kTanMax, ev);
  return ev.result();
}

TEST(WheelRing, PartialRingsWithAPairAndAThirdSampleProveTheSlopeAtTheEdgeOfItsMarginAsABatchFitDoes) {
  // Every mask of exact samples; the gradient's magnitude set 1 % of a sigma inside or
  // outside the proof margin tan_max - k sigma, sigma from the batch fit, in 8 directions.
  const double var = 1e-5;
  int proven_masks = 0;
  for (unsigned mask = 0; mask < (1u << kN); ++mask) {
    const bool proves = qualifies(mask);
    for (int dir = 0; dir < 8; ++dir) {
      const double phi = dir * M_PI / 8 + 0.1;
      if (!proves) {
        RingSample s[kN];
        plane_ring(0.0, 0.0, 0.0, var, mask, s);
        ASSERT_EQ(slope_class(s), HazardClass::unknown) << "mask " << mask;
        continue;
      }
      const double sigma = std::sqrt(batch_fit(mask, var).var_g);
      for (double side : {-0.01, 0.01}) {
        const double g = kTanMax - kK * sigma + side * sigma;
        RingSample s[kN];
        plane_ring(0.2, g * std::cos(phi), g * std::sin(phi), var, mask, s);
        const HazardClass want = side < 0 ? HazardClass::traversable : HazardClass::unknown;
        ASSERT_EQ(slope_class(s), want) << "mask " << mask << " dir " << dir << " side " << side;
      }
      // Beyond the threshold by k sigma: the full ring shows the hazard; a partial ring's
      // plane only proves (wheel_ring.cpp), so there the cell stays unknown.
      const double g = kTanMax + kK * sigma + 0.01 * sigma;
      RingSample s[kN];
      plane_ring(0.2, g * std::cos(phi), g * std::sin(phi), var, mask, s);
      ASSERT_EQ(slope_class(s), mask == 0xFFu ? HazardClass::hazard : HazardClass::unknown)
          << "mask " << mask << " dir " << dir;
    }
    proven_masks += proves;
  }
  EXPECT_EQ(proven_masks, 171);  // of 256 (counted by hand: a pair and a third sample)
}

TEST(WheelRing, PartialRingsWithAPairAndAThirdSampleProveTheStepAboveTheirPlaneAsABatchFitDoes) {
  // A cell height h on a tilted plane: the step h - c, set 1 % of a sigma inside or
  // outside the margin h_min - k sigma (sigma^2 = var_h + var(c) of the batch fit).
  const double var = 4e-6, var_h = 1e-6;
  for (unsigned mask = 0; mask < (1u << kN); ++mask) {
    if (!qualifies(mask)) continue;
    const double sigma = std::sqrt(var_h + batch_fit(mask, var).var_c);
    for (double side : {-0.01, 0.01}) {
      RingSample s[kN];
      plane_ring(0.5, 0.2, -0.1, var, mask, s);
      const double step = kHMin - kK * sigma + side * sigma;
      const HazardClass want = side < 0 ? HazardClass::traversable : HazardClass::unknown;
      ASSERT_EQ(step_class(0.5 + step, var_h, s), want) << "mask " << mask << " side " << side;
    }
    RingSample s[kN];
    plane_ring(0.5, 0.2, -0.1, var, mask, s);
    const HazardClass beyond = step_class(0.5 + kHMin + kK * sigma * 1.01, var_h, s);
    if (mask == 0xFFu)
      ASSERT_EQ(beyond, HazardClass::hazard);
    else  // hazard only from the evidence of the lowest sample or opposite pairs
      ASSERT_NE(beyond, HazardClass::traversable) << "mask " << mask;
  }
}

TEST(WheelRing, APairAloneAQuarterRingOrSamplesOnlyKnownProveNothingButStillShowAStep) {
  const double var = 1e-6;
  RingSample s[kN];
  plane_ring(0.0, 0.0, 0.0, var, 0x11u, s);  // samples 0 and 4: one pair, no third
  EXPECT_EQ(step_class(0.0, var, s), HazardClass::unknown);
  EXPECT_EQ(slope_class(s), HazardClass::unknown);
  EXPECT_EQ(step_class(0.10, var, s), HazardClass::hazard);
  plane_ring(0.0, 0.0, 0.0, var, 0x07u, s);  // samples 0, 1, 2: the centre extrapolated
  EXPECT_EQ(step_class(0.0, var, s), HazardClass::unknown);
  EXPECT_EQ(slope_class(s), HazardClass::unknown);
  EXPECT_EQ(step_class(0.10, var, s), HazardClass::hazard);
  // Every sample known but none exact (CCM cells without a plane): no proof either.
  plane_ring(0.0, 0.0, 0.0, var, 0xFFu, s);
  for (RingSample& x : s) x.exact = false;
  EXPECT_EQ(step_class(0.0, var, s), HazardClass::unknown);
  EXPECT_EQ(slope_class(s), HazardClass::unknown);
  EXPECT_EQ(step_class(0.10, var, s), HazardClass::hazard);
}

TEST(WheelRing, FullRingAndAHalfRingAgreeOnAPlane) {
  // On a plane, a half ring (samples 2..6, as at the edge of what was seen) gives the
  // full ring's plane: only the margin (the variance) differs.
  const double var = 1e-6;
  RingSample full[kN], partial[kN];
  plane_ring(0.3, 0.25, 0.1, var, 0xFFu, full);
  plane_ring(0.3, 0.25, 0.1, var, 0x7Cu, partial);
  for (double h : {0.3 + 0.02, 0.3 + 0.04})
    EXPECT_EQ(step_class(h, var, full), step_class(h, var, partial)) << h;
  EXPECT_EQ(slope_class(full), HazardClass::traversable);
  EXPECT_EQ(slope_class(partial), HazardClass::traversable);
}

}  // namespace
}  // namespace hazmap
