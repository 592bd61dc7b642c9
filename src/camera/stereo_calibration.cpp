#include "hazmap/camera/stereo_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "hazmap/core/error.hpp"
#include "hazmap/core/number_text.hpp"

namespace hazmap {

void derive_from_models(StereoCalibration& c, const std::string& source) {
  check(c.models.size() == 2, source + ": expected a left and a right camera model");
  const CahvPinhole left = cahv_pinhole(c.models[0], source + ": left");
  const CahvPinhole right = cahv_pinhole(c.models[1], source + ": right");
  c.left = CameraIntrinsics{left.K, {}};
  c.right = CameraIntrinsics{right.K, {}};
  const Pose3d T_CR_CL = right.T_M_C.inverse() * left.T_M_C;  // x_right = R x_left + T
  c.R = T_CR_CL.linear();
  c.T = T_CR_CL.translation();
  c.T_B_C = c.T_B_M * left.T_M_C;
  c.rectified = false;
}

void validate(const StereoCalibration& c, const std::string& source) {
  auto fail = [&](const std::string& key, const std::string& what) {
    throw Error(source + ": key '" + key + "': " + what);
  };
  auto number = [](double v) { return printf_double(v, "%g"); };
  if (c.image_width <= 0) fail("image_width", "must be > 0");
  if (c.image_height <= 0) fail("image_height", "must be > 0");
  const double side = std::max(c.image_width, c.image_height);
  for (const auto* cam : {&c.left, &c.right}) {
    const std::string name = cam == &c.left ? "left" : "right";
    const std::string k = name + ".K";
    if (!cam->K.allFinite()) fail(k, "holds a value that is not a finite number");
    for (double d : cam->D)
      if (!std::isfinite(d)) fail(name + ".D", "holds a value that is not a finite number");
    if (!(cam->K(0, 0) > 0 && cam->K(1, 1) > 0)) fail(k, "focal lengths must be > 0");
    if (cam->K(2, 2) != 1.0 || cam->K(1, 0) != 0 || cam->K(2, 0) != 0 || cam->K(2, 1) != 0)
      fail(k, "must be an upper-triangular camera matrix with K[2][2] = 1");
    // Plausibility: beyond these no lens images the ground, and the numbers that follow
    // from them (f B / Z, pixel rays) lose all precision or overflow.
    for (int i = 0; i < 2; ++i)
      if (cam->K(i, i) > kMaxFocalPerImageSide * side)
        fail(k, std::string(i ? "fy" : "fx") + " = " + number(cam->K(i, i)) +
                    " px is implausible: at most " + number(kMaxFocalPerImageSide) +
                    " x the image's larger side (" + number(side) +
                    " px), a field of view under 0.06 deg");
    if (std::abs(cam->K(0, 1)) > kMaxSkewPerFocal * cam->K(0, 0))
      fail(k, "skew K[0][1] = " + number(cam->K(0, 1)) + " is implausible: at most " +
                  number(kMaxSkewPerFocal) + " x fx (pixel axes within 6 deg of square)");
    const double cx = cam->K(0, 2), cy = cam->K(1, 2);
    if (!(cx >= -c.image_width && cx <= 2.0 * c.image_width && cy >= -c.image_height &&
          cy <= 2.0 * c.image_height))
      fail(k, "principal point (" + number(cx) + ", " + number(cy) +
                  ") px is implausible: more than an image width or height outside the " +
                  std::to_string(c.image_width) + "x" + std::to_string(c.image_height) + " image");
  }
  if (!c.R.allFinite()) fail("R", "holds a value that is not a finite number");
  if (!c.T.allFinite()) fail("T", "holds a value that is not a finite number");
  if (!c.R.isUnitary(1e-4) || c.R.determinant() < 0) fail("R", "is not a rotation matrix");
  if (!(c.T.norm() > 0)) fail("T", "baseline must be non-zero");
  if (!(c.T.norm() <= kMaxBaselineM))
    fail("T", "baseline |T| = " + number(c.T.norm()) + " m is implausible: at most " +
                  number(kMaxBaselineM) + " m (wider than any stereo rig; check the units)");
  if (!c.T_B_C.matrix().allFinite())
    fail("T_body_left", "holds a value that is not a finite number");
  if (!(c.T_B_C.translation().cwiseAbs().maxCoeff() <= kMaxBaselineM))
    fail("T_body_left", "translation is implausible: each coordinate at most " +
                            number(kMaxBaselineM) + " m from the body origin");
  if (c.rectified) {
    for (double d : c.left.D)
      if (d != 0) fail("left.D", "must be zero for a rectified sequence");
    for (double d : c.right.D)
      if (d != 0) fail("right.D", "must be zero for a rectified sequence");
    if (!c.R.isIdentity(1e-9)) fail("R", "must be the identity for a rectified sequence");
    if (!(c.T.x() < 0) || c.T.y() != 0 || c.T.z() != 0)
      fail("T", "must be [-B, 0, 0] for a rectified sequence");
    // SPEC 2: a rectified pair shares one camera matrix; the pipeline uses the left's.
    if (!c.right.K.isApprox(c.left.K, 1e-9))
      fail("right.K", "must equal left.K for a rectified sequence (SPEC 2)");
  }
}

}  // namespace hazmap
