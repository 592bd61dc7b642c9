#include "hazmap/hazard/evidence.hpp"

#include <algorithm>
#include <cmath>

namespace hazmap {

double kernel_k_sigma(double k, int n) {
  if (n <= 1 || k <= 0) return k;
  // Upper tail of the standard normal: Q(x) = erfc(x / sqrt 2) / 2, decreasing.
  auto tail = [](double x) { return 0.5 * std::erfc(x / std::sqrt(2.0)); };
  const double target = tail(k) / n;
  double lo = k, hi = k + 10.0;
  for (int i = 0; i < 100; ++i) {  // bisection to ~1e-12
    const double mid = 0.5 * (lo + hi);
    (tail(mid) > target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace hazmap
