#pragma once
// numpy <-> library types for the Python bindings. Everything here checks its input and
// raises TypeError (wrong dtype or type) or ValueError (wrong shape or value) with a
// message naming the argument; the library's own checks raise hazmap.Error.

#include <utility>

#include <opencv2/core.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "hazmap/core/types.hpp"
#include "hazmap/map/dense_grid.hpp"
#include "hazmap/map/measurement.hpp"

namespace hazmap::python {

namespace py = pybind11;

/// A read-only rows x cols float32 numpy view of `grid`'s values, without a copy. The
/// array holds a reference to `owner` (the Python object that owns the grid), so its
/// memory stays valid however long the array lives; it shows the owner's current values
/// (the next frame overwrites them in place). None when the grid is empty.
py::object grid_view(const DenseGrid& grid, const py::object& owner);

/// A cv::Mat header over a numpy image: uint8 or uint16, H x W (grey), H x W x 1, H x W x 3
/// (BGR, OpenCV's order) or H x W x 4 (BGRA). `keep` receives the array the header points
/// into: `image` itself, or a C-contiguous copy when it was not contiguous; it must
/// outlive the Mat. `what` names the argument in messages ("left").
cv::Mat image_from_numpy(const py::handle& image, const char* what, py::array& keep);

/// A numpy copy of an 8/16-bit or float32 image (H x W or H x W x C).
py::array numpy_from_mat(const cv::Mat& image);

/// Body pose T_W_B from a 4 x 4 homogeneous matrix (rotation orthonormal within
/// kRotationTolerance, last row 0 0 0 1) or from 7 numbers x y z qx qy qz qw (the order of
/// poses.txt; the quaternion unit within kQuaternionTolerance, then normalised, as
/// load_sequence does). The position must pass check_position.
Pose3d pose_from_python(const py::handle& pose);

/// T as a 4 x 4 float64 array.
py::array numpy_from_pose(const Pose3d& T);

/// Pose noise (SPEC 2) from None (no noise) or 4 numbers sx sy sz [m] syaw [rad], >= 0.
PoseNoise noise_from_python(const py::handle& noise);

/// A frame's points from N x 3 positions p_W [m] and their covariances [m^2], one of
///   (N,)      isotropic variance: Sigma = v I
///   (N, 3)    diagonal: var_x, var_y, var_z
///   (N, 6)    upper triangle xx xy xz yy yz zz (Measurement's order)
///   (N, 3, 3) full matrices (the upper triangle is read)
/// Positions must be finite and variances finite with a positive diagonal. Reuses `out`.
void cloud_from_numpy(const py::handle& points, const py::handle& covariances, PointCloud& out);

/// (N x 3 positions, N x 6 upper-triangle covariances), float32 copies.
std::pair<py::array, py::array> numpy_from_cloud(const PointCloud& cloud);

}  // namespace hazmap::python
