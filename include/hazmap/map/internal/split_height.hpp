#pragma once
// Used by RollingLayer's insertion and by the built-in rules, whose public types hold it
// (rules/omg.hpp, ccm.hpp, kalman.hpp): visible through them; a custom rule need not use it.
// A height stored as a float reference plus a float offset: ~48 bits together, so a cell
// at |z| ~ 100 m keeps sub-micrometre resolution in 8 bytes, and merges do not accumulate
// float rounding (the value is re-split at every store). Used by the Kalman, OMG and CCM
// cells for their mean height.

namespace hazmap {

struct SplitHeight {
  float ref_m = 0.0f;  ///< value = ref_m + off_m
  float off_m = 0.0f;

  void set(double z_m) {
    ref_m = static_cast<float>(z_m);
    off_m = static_cast<float>(z_m - double(ref_m));
  }
  double value() const { return double(ref_m) + double(off_m); }
};

}  // namespace hazmap
