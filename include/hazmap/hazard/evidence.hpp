#pragma once
// The rule every hazard test follows (SPEC 8): hazard needs evidence, traversable needs
// proof. A test compares a statistic s, with standard deviation sigma propagated from the
// cells' variances, with a threshold T:
//   - hazard when s - k sigma > T, whether or not the data are complete;
//   - traversable only if every test had complete data and s + k sigma <= T;
//   - unknown otherwise.
// One Evidence collects a cell's tests; k = 0 gives the thesis' plain comparisons.

#include <cmath>

#include "hazmap/hazard/unknown_reason.hpp"
#include "hazmap/map/dense_grid.hpp"

namespace hazmap {

/// The k for the largest of n noisy values (a kernel's max or min): each of the n values
/// may exceed its truth by k_n sigma with probability P(Z > k) / n, so together no more
/// often than one value exceeds k sigma (Bonferroni). k_n >= k; k_1 = k.
double kernel_k_sigma(double k, int n);

class Evidence {
 public:
  explicit Evidence(double k_sigma) : k_(k_sigma) {}

  /// Names what blocks proof in the tests that follow (unknown_reason.hpp): incomplete or
  /// missing data, and a statistic within k sigma of its threshold. Only recorded: a
  /// classifier asked to explain itself (HazardClassifier::explain) reads reasons().
  void why(std::uint16_t incomplete, std::uint16_t margin) {
    why_incomplete_ = incomplete;
    why_margin_ = margin;
  }

  /// Adds one test. `complete`: the data behind s cover what the test needs (kernel fill,
  /// coverage, every ring sample). A NaN s or sigma is no evidence either way.
  /// `k_hazard` (>= k) replaces k on the hazard side where s is the most extreme of many
  /// noisy values (see kernel_k_sigma).
  void test(double s, double sigma, double threshold, bool complete) {
    test(s, sigma, threshold, complete, k_);
  }
  void test(double s, double sigma, double threshold, bool complete, double k_hazard) {
    if (!(std::isfinite(s) && sigma >= 0 && std::isfinite(sigma))) {
      proven_ = false;
      reasons_ |= why_incomplete_;
      return;
    }
    if (s - k_hazard * sigma > threshold) hazard_ = true;
    if (!complete) {
      proven_ = false;
      reasons_ |= why_incomplete_;
    }
    if (s + k_ * sigma > threshold) {
      proven_ = false;
      reasons_ |= why_margin_;
    }
  }
  /// Evidence only: a statistic that can show a hazard but, being partial (one axis of a
  /// plane, part of a ring), can never prove the cell traversable nor block the proof of
  /// the complete tests.
  void evidence(double s, double sigma, double threshold) { evidence(s, sigma, threshold, k_); }
  void evidence(double s, double sigma, double threshold, double k_hazard) {
    if (std::isfinite(s) && std::isfinite(sigma) && s - k_hazard * sigma > threshold) hazard_ = true;
  }
  /// A test that could not be run (missing data): the cell cannot be proven traversable.
  void missing() {
    proven_ = false;
    reasons_ |= why_incomplete_;
  }
  void missing(std::uint16_t reason) {
    proven_ = false;
    reasons_ |= reason;
  }

  bool hazard() const { return hazard_; }
  double k() const { return k_; }
  /// What blocked proof (UnknownReason bits); meaningful when result() is unknown.
  std::uint16_t reasons() const { return reasons_; }
  HazardClass result() const {
    return hazard_ ? HazardClass::hazard : proven_ ? HazardClass::traversable : HazardClass::unknown;
  }

 private:
  double k_;
  bool hazard_ = false;
  bool proven_ = true;
  std::uint16_t why_incomplete_ = 0, why_margin_ = 0, reasons_ = 0;
};

}  // namespace hazmap
