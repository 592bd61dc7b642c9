#include "arrays.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "hazmap/io/sequence.hpp"

namespace hazmap::python {
namespace {

/// Largest |R^T R - I| entry accepted for a pose's rotation: a matrix written out with
/// 7 or more significant digits passes, a scaled or sheared one does not.
constexpr double kRotationTolerance = 1e-6;
/// Largest | |q| - 1 | accepted before normalising, as load_sequence accepts in poses.txt.
constexpr double kQuaternionTolerance = 1e-3;

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// `value` as a C-contiguous float64 array; TypeError naming `what` when numpy cannot
/// read it as numbers.
DoubleArray as_doubles(const py::handle& value, const std::string& what) {
  DoubleArray a = DoubleArray::ensure(value);
  if (!a) throw py::type_error(what + ": expected an array of numbers, got " +
                               std::string(py::str(py::type::of(value).attr("__name__"))));
  return a;
}

std::string shape_of(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

}  // namespace

py::object grid_view(const DenseGrid& grid, const py::object& owner) {
  if (grid.rows == 0 || grid.cols == 0) return py::none();
  const auto cols = static_cast<py::ssize_t>(grid.cols);
  py::array_t<float> view({static_cast<py::ssize_t>(grid.rows), cols},
                          {cols * static_cast<py::ssize_t>(sizeof(float)),
                           static_cast<py::ssize_t>(sizeof(float))},
                          grid.values.data(), owner);
  // The grid is the pipeline's state: a write through the view would corrupt the next
  // frame's incremental update (SPEC 8.6).
  py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return std::move(view);
}

cv::Mat image_from_numpy(const py::handle& image, const char* what, py::array& keep) {
  const std::string name = what;
  if (!py::isinstance<py::array>(image))
    throw py::type_error(name + " image: expected a numpy array, got " +
                         std::string(py::str(py::type::of(image).attr("__name__"))));
  const auto a = py::reinterpret_borrow<py::array>(image);
  int depth = -1;
  if (a.dtype().is(py::dtype::of<std::uint8_t>())) depth = CV_8U;
  if (a.dtype().is(py::dtype::of<std::uint16_t>())) depth = CV_16U;
  if (depth < 0)
    throw py::type_error(name + " image: dtype " + std::string(py::str(a.dtype())) +
                         " is not supported (expected uint8 or uint16)");
  const bool grey = a.ndim() == 2;
  const bool colour = a.ndim() == 3 && (a.shape(2) == 1 || a.shape(2) == 3 || a.shape(2) == 4);
  if (!grey && !colour)
    throw py::value_error(name + " image: shape " + shape_of(a) +
                          " is not H x W, H x W x 1, H x W x 3 or H x W x 4");
  if (a.shape(0) == 0 || a.shape(1) == 0)
    throw py::value_error(name + " image: shape " + shape_of(a) + " is empty");
  // Strided views (a crop, a channel slice) are copied once into a contiguous buffer:
  // cv::Mat needs contiguous pixels within a row.
  keep = py::array::ensure(a, py::array::c_style);
  const int channels = grey ? 1 : static_cast<int>(a.shape(2));
  return cv::Mat(static_cast<int>(keep.shape(0)), static_cast<int>(keep.shape(1)),
                 CV_MAKETYPE(depth, channels), keep.mutable_data());
}

py::array numpy_from_mat(const cv::Mat& image) {
  const cv::Mat m = image.isContinuous() ? image : image.clone();
  std::vector<py::ssize_t> shape{m.rows, m.cols};
  if (m.channels() > 1) shape.push_back(m.channels());
  py::array out;
  switch (m.depth()) {
    case CV_8U: out = py::array_t<std::uint8_t>(shape); break;
    case CV_16U: out = py::array_t<std::uint16_t>(shape); break;
    case CV_16S: out = py::array_t<std::int16_t>(shape); break;
    case CV_32F: out = py::array_t<float>(shape); break;
    default: throw py::type_error("image depth " + std::to_string(m.depth()) + " has no numpy type here");
  }
  std::memcpy(out.mutable_data(), m.data, m.total() * m.elemSize());
  return out;
}

Pose3d pose_from_python(const py::handle& pose) {
  const DoubleArray a = as_doubles(pose, "pose");
  const double* v = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i)
    if (!std::isfinite(v[i])) throw py::value_error("pose: values must be finite");
  Pose3d T = Pose3d::Identity();
  if (a.ndim() == 2 && a.shape(0) == 4 && a.shape(1) == 4) {
    if (v[12] != 0 || v[13] != 0 || v[14] != 0 || v[15] != 1)
      throw py::value_error("pose: the last row of a 4 x 4 T_W_B must be 0 0 0 1");
    Eigen::Matrix3d R;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) R(r, c) = v[4 * r + c];
    const double off = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (off > kRotationTolerance || R.determinant() < 0)
      throw py::value_error("pose: the upper-left 3 x 3 of T_W_B is not a rotation (|R^T R - I| = " +
                            std::to_string(off) + ", det " + std::to_string(R.determinant()) + ")");
    T.linear() = R;
    T.translation() = Eigen::Vector3d(v[3], v[7], v[11]);
  } else if (a.ndim() == 1 && a.shape(0) == 7) {
    const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);  // given as qx qy qz qw
    if (std::abs(q.norm() - 1.0) > kQuaternionTolerance)
      throw py::value_error("pose: quaternion (qx qy qz qw) is not a unit quaternion (norm " +
                            std::to_string(q.norm()) + ")");
    T.linear() = q.normalized().toRotationMatrix();
    T.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  } else {
    throw py::value_error("pose: shape " + shape_of(a) +
                          "; expected a 4 x 4 T_W_B or 7 numbers x y z qx qy qz qw");
  }
  const Eigen::Vector3d p = T.translation();
  const std::string bad = check_position(p.x(), p.y(), p.z());
  if (!bad.empty()) throw py::value_error("pose: " + bad);
  return T;
}

py::array numpy_from_pose(const Pose3d& T) {
  py::array_t<double> out({4, 4});
  auto m = out.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = T.matrix()(r, c);
  return std::move(out);
}

PoseNoise noise_from_python(const py::handle& noise) {
  if (noise.is_none()) return {};
  const DoubleArray a = as_doubles(noise, "noise");
  if (a.ndim() != 1 || a.shape(0) != 4)
    throw py::value_error("noise: shape " + shape_of(a) + "; expected 4 numbers sx sy sz syaw");
  const double* v = a.data();
  for (int i = 0; i < 4; ++i)
    if (!(v[i] >= 0) || !std::isfinite(v[i]))
      throw py::value_error("noise: sx sy sz syaw must be finite and >= 0");
  return PoseNoise{v[0], v[1], v[2], v[3]};
}

void cloud_from_numpy(const py::handle& points, const py::handle& covariances, PointCloud& out) {
  const DoubleArray p = as_doubles(points, "points");
  if (p.ndim() != 2 || p.shape(1) != 3)
    throw py::value_error("points: shape " + shape_of(p) + "; expected N x 3 positions");
  const py::ssize_t n = p.shape(0);
  const DoubleArray c = as_doubles(covariances, "covariances");
  enum class Form { isotropic, diagonal, upper, full };
  Form form;
  if (c.ndim() == 1 && c.shape(0) == n) form = Form::isotropic;
  else if (c.ndim() == 2 && c.shape(0) == n && c.shape(1) == 3) form = Form::diagonal;
  else if (c.ndim() == 2 && c.shape(0) == n && c.shape(1) == 6) form = Form::upper;
  else if (c.ndim() == 3 && c.shape(0) == n && c.shape(1) == 3 && c.shape(2) == 3) form = Form::full;
  else
    throw py::value_error("covariances: shape " + shape_of(c) + " for " + std::to_string(n) +
                          " points; expected (N,), (N, 3), (N, 6) or (N, 3, 3)");
  out.resize(static_cast<size_t>(n));
  const double* pv = p.data();
  const double* cv = c.data();
  for (py::ssize_t i = 0; i < n; ++i) {
    const double* x = pv + 3 * i;
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
      throw py::value_error("points: row " + std::to_string(i) + " is not finite");
    double xx, xy = 0, xz = 0, yy, yz = 0, zz;
    switch (form) {
      case Form::isotropic: xx = yy = zz = cv[i]; break;
      case Form::diagonal: xx = cv[3 * i]; yy = cv[3 * i + 1]; zz = cv[3 * i + 2]; break;
      case Form::upper: {
        const double* u = cv + 6 * i;
        xx = u[0], xy = u[1], xz = u[2], yy = u[3], yz = u[4], zz = u[5];
        break;
      }
      case Form::full: {
        const double* m = cv + 9 * i;
        xx = m[0], xy = m[1], xz = m[2], yy = m[4], yz = m[5], zz = m[8];
        break;
      }
    }
    const double all[] = {xx, xy, xz, yy, yz, zz};
    for (double e : all)
      if (!std::isfinite(e))
        throw py::value_error("covariances: row " + std::to_string(i) + " is not finite");
    if (!(xx > 0 && yy > 0 && zz > 0))
      throw py::value_error("covariances: row " + std::to_string(i) +
                            " has a variance <= 0 on its diagonal");
    Measurement& m = out[static_cast<size_t>(i)];
    m.p_W = Eigen::Vector3d(x[0], x[1], x[2]).cast<float>();
    m.cov_xx = static_cast<float>(xx);
    m.cov_xy = static_cast<float>(xy);
    m.cov_xz = static_cast<float>(xz);
    m.cov_yy = static_cast<float>(yy);
    m.cov_yz = static_cast<float>(yz);
    m.cov_zz = static_cast<float>(zz);
  }
}

std::pair<py::array, py::array> numpy_from_cloud(const PointCloud& cloud) {
  const auto n = static_cast<py::ssize_t>(cloud.size());
  py::array_t<float> p({n, py::ssize_t{3}}), c({n, py::ssize_t{6}});
  auto pm = p.mutable_unchecked<2>();
  auto cm = c.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const Measurement& m = cloud[static_cast<size_t>(i)];
    for (int k = 0; k < 3; ++k) pm(i, k) = m.p_W[k];
    const float u[] = {m.cov_xx, m.cov_xy, m.cov_xz, m.cov_yy, m.cov_yz, m.cov_zz};
    for (int k = 0; k < 6; ++k) cm(i, k) = u[k];
  }
  return {std::move(p), std::move(c)};
}

}  // namespace hazmap::python
