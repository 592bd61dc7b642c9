#pragma once
// The wheel ring (SPEC 8.2, 8.3): 8 samples of the terrain on a circle of radius
// wheelbase / 2 around a cell centre. A full ring gives the plane the rover would stand
// on (its tilt: the vehicle-slope test) and that plane's height under the cell (the cell's
// height above it: the step test, which sees rock tops too flat and wide for the roughness
// kernel). For 8 symmetric samples the least-squares plane has slope
// sum(z dx) / sum(dx^2) along x (likewise y), sum(dx^2) = 4 R^2, and its value at the
// centre is the samples' mean.
//
// A partial ring (issue 34), as at the edge of what the cameras saw or of the layer's
// window: its exact samples' least-squares plane, with the variance propagated from
// theirs, proves as the full ring's does when the centre is not extrapolated: at least
// one opposite pair (the centre lies on the samples' hull, on that diameter) and a third
// sample off it. A half ring qualifies. With less, the ring gives hazard evidence only.
// A partial ring's plane only proves; its hazards come from that evidence (wheel_ring.cpp).
// Which partial rings may prove (hazard.partial_ring_proof): with `view_edge` only those
// whose every inexact sample lies where the stereo pair never looked at the whole cell
// (RingSample::unseen, from SensorView). A hole inside the view (a shadow, ground a rock
// hid, a face without texture) is where a rock may be, and keeps the ring from proving.

#include "hazmap/core/core_config.hpp"
#include "hazmap/hazard/evidence.hpp"

namespace hazmap {

struct RingSample {
  double z_m = 0.0;
  double var_m2 = 0.0;
  bool known = false;  ///< a height with an honest variance: evidence for a hazard
  bool exact = false;  ///< known well enough to prove (a CCM sample on an evaluable plane)
  /// Not exact, in a cell no frame's view covered whole (SensorView): the ring is cut by
  /// the edge of what was looked at, not by a hole in it.
  bool unseen = false;
};

class WheelRing {
 public:
  static constexpr int kSamples = 8;
  /// `k_sigma`: the classifier's k (Evidence), for which step_test's Bonferroni k of the
  /// lowest of n samples is tabulated once: computing it (a bisection over erfc) per
  /// partly observed cell cost most of a 1 cm layer's classification.
  /// `partial_proof`: which partial rings that qualify prove (hazard.partial_ring_proof);
  /// the others give hazard evidence only, and the cell cannot be proven.
  WheelRing(double radius_m, double k_sigma, PartialRingProof partial_proof = PartialRingProof::any);

  double radius() const { return radius_; }
  double dx(int k) const { return dx_[k]; }
  double dy(int k) const { return dy_[k]; }

  /// Exact samples a partial ring needs to prove anything (one opposite pair among them):
  /// three fix a plane.
  static constexpr int kMinProofSamples = 3;

  /// Vehicle slope: tan of the ring plane's inclination against tan(max_slope), from every
  /// sample when all are exact, else from a partial ring's plane when it qualifies (else
  /// the test is missing: the cell cannot be proven traversable).
  void slope_test(const RingSample (&s)[kSamples], double tan_max_slope, Evidence& ev) const;

  /// Step above the ring: the cell height h (variance var_h) above the ring plane
  /// against h_min. With a full ring of exact samples the plane is fitted; with a partial
  /// ring that qualifies, its exact samples' plane. Beyond that (and otherwise alone)
  /// hazard evidence from the known samples: ground that is a plane no
  /// steeper than max_slope lies at most min_k(z_k) + R tan(max_slope) under the centre,
  /// and across planar ground its height is the mean of two opposite samples (averaged
  /// over the pairs that are known), so h above either bound is a step.
  void step_test(double h_m, double var_h_m2, const RingSample (&s)[kSamples], double h_min_m,
                 double tan_max_slope, Evidence& ev) const;

 private:
  /// The least-squares plane of a partial ring's exact samples: its height under the
  /// centre and gradient, with their variances (the gradient's: the trace of its
  /// covariance).
  struct PartialPlane {
    double ground = 0, var_ground = 0;
    double gx = 0, gy = 0, var_gradient = 0;
  };
  /// False when the exact samples do not qualify (no exact opposite pair, or fewer than
  /// kMinProofSamples).
  bool fit_partial(const RingSample (&s)[kSamples], PartialPlane* plane) const;
  /// The partial ring may prove: the mode allows it for these samples' missing ones.
  bool may_prove_partial(const RingSample (&s)[kSamples]) const;

  double radius_;
  double dx_[kSamples], dy_[kSamples];
  double k_sigma_;
  PartialRingProof partial_proof_;
  double lowest_k_[kSamples + 1];  ///< kernel_k_sigma(k_sigma_, n)
};

}  // namespace hazmap
