#include "hazmap/hazard/wheel_ring.hpp"

#include <cmath>
#include <limits>

namespace hazmap {

WheelRing::WheelRing(double radius_m, double k_sigma) : radius_(radius_m), k_sigma_(k_sigma) {
  for (int k = 0; k < kSamples; ++k) {
    dx_[k] = radius_m * std::cos(k * M_PI / 4.0);
    dy_[k] = radius_m * std::sin(k * M_PI / 4.0);
  }
  for (int n = 0; n <= kSamples; ++n) lowest_k_[n] = kernel_k_sigma(k_sigma, n);
}

void WheelRing::slope_test(const RingSample (&s)[kSamples], double tan_max_slope,
                           Evidence& ev) const {
  ev.why(kReasonRingIncomplete, kReasonSlopeMargin);
  const double norm = 4.0 * radius_ * radius_;
  double a = 0, b = 0, var_a = 0, var_b = 0;
  for (int k = 0; k < kSamples; ++k) {
    if (!s[k].exact) {
      ev.missing();
      return;
    }
    a += s[k].z_m * dx_[k];
    b += s[k].z_m * dy_[k];
    var_a += s[k].var_m2 * dx_[k] * dx_[k];
    var_b += s[k].var_m2 * dy_[k] * dy_[k];
  }
  a /= norm;
  b /= norm;
  // |(a, b)| has a standard deviation of at most sqrt(var_a + var_b).
  ev.test(std::hypot(a, b), std::sqrt(var_a + var_b) / norm, tan_max_slope, true);
}

void WheelRing::step_test(double h_m, double var_h_m2, const RingSample (&s)[kSamples],
                          double h_min_m, double tan_max_slope, Evidence& ev) const {
  ev.why(kReasonRingIncomplete, kReasonStepMargin);
  int known = 0, exact = 0;
  double sum = 0, sum_var = 0;
  double lowest = std::numeric_limits<double>::infinity(), lowest_var = 0;
  for (int k = 0; k < kSamples; ++k) {
    if (!s[k].known) continue;
    ++known;
    exact += s[k].exact;
    sum += s[k].z_m;
    sum_var += s[k].var_m2;
    if (s[k].z_m < lowest) {
      lowest = s[k].z_m;
      lowest_var = s[k].var_m2;
    }
  }
  if (exact == kSamples) {
    const double ground = sum / kSamples;
    ev.test(h_m - ground, std::sqrt(var_h_m2 + sum_var / (kSamples * kSamples)), h_min_m, true);
    return;
  }
  ev.missing();
  if (known == 0) return;
  // The lowest of `known` noisy samples: its k counts them (kernel_k_sigma).
  ev.evidence(h_m - (lowest + radius_ * tan_max_slope), std::sqrt(var_h_m2 + lowest_var),
              h_min_m, ev.k() == k_sigma_ ? lowest_k_[known] : kernel_k_sigma(ev.k(), known));
  // Opposite samples: across planar ground their mean is the height under the centre
  // with no slope allowance, as the full ring's mean is; the mean over the available
  // pairs uses every direction that was seen (one pair alone would read the curvature
  // of a crest along it as a step).
  int pairs = 0;
  double pair_sum = 0, pair_var = 0;
  for (int k = 0; k < kSamples / 2; ++k) {
    const RingSample &a = s[k], &b = s[k + kSamples / 2];
    if (!a.known || !b.known) continue;
    ++pairs;
    pair_sum += 0.5 * (a.z_m + b.z_m);
    pair_var += 0.25 * (a.var_m2 + b.var_m2);
  }
  if (pairs > 0)
    ev.evidence(h_m - pair_sum / pairs, std::sqrt(var_h_m2 + pair_var / (pairs * pairs)), h_min_m);
}

}  // namespace hazmap
