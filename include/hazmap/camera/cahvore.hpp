#pragma once
// JPL's CAHV, CAHVOR and CAHVORE camera models (Yakimovsky & Cunningham; Gennery), as
// PDS rover stereo products give them (MODEL_COMPONENT_1..9 = C A H V O R E T P).
// All vectors in one frame M of the calibration (for PDS rover data, usually a rover
// frame with x forward, y right, z down); pixels with (0, 0) at the centre of the first
// pixel, x right, y down, as in OpenCV.
//
//   CAHV:    u = (p . H) / (p . A), v = (p . V) / (p . A), p = P - C.
//   CAHVOR:  radial distortion about the axis O: zeta = p . O, lambda = p - zeta O,
//            tau = |lambda|^2 / zeta^2, mu = r0 + r1 tau + r2 tau^2, then CAHV of
//            p' = p + mu lambda.
//   CAHVORE: the entrance pupil moves along O with the incidence angle theta:
//            zeta sin(theta) - |lambda| cos(theta) = (theta - sin(theta)) (e0 + e1 theta^2
//            + e2 theta^4) (solved by Newton), chi = tan(L theta)/L (L > 0),
//            sin(L theta)/L (L < 0) or theta (L = 0), mu = r0 + r1 chi^2 + r2 chi^4,
//            p' = (|lambda| / chi) O + (1 + mu) lambda, then CAHV of p'. The linearity L is
//            1 for type 1 (perspective), 0 for type 2 (fish-eye), the parameter P for
//            type 3 (general). With E = 0 and type 1 this is CAHVOR.

#include <filesystem>
#include <string>

#include <Eigen/Core>

#include "hazmap/core/types.hpp"

namespace hazmap {

enum class CahvoreKind { cahv, cahvor, cahvore };

/// "cahv" | "cahvor" | "cahvore" (any case); throws Error naming `what` otherwise.
CahvoreKind parse_cahvore_kind(const std::string& name, const std::string& what);
const char* cahvore_kind_name(CahvoreKind kind);

struct CahvoreModel {
  CahvoreKind kind = CahvoreKind::cahv;
  Eigen::Vector3d C = Eigen::Vector3d::Zero();   ///< entrance pupil centre [m]
  Eigen::Vector3d A = Eigen::Vector3d::UnitZ();  ///< unit optical axis (out of the camera)
  Eigen::Vector3d H = Eigen::Vector3d::UnitX();  ///< horizontal vector [px]
  Eigen::Vector3d V = Eigen::Vector3d::UnitY();  ///< vertical vector [px]
  Eigen::Vector3d O = Eigen::Vector3d::UnitZ();  ///< unit axis of the radial distortion
  Eigen::Vector3d R = Eigen::Vector3d::Zero();   ///< r0 r1 r2
  Eigen::Vector3d E = Eigen::Vector3d::Zero();   ///< e0 e1 e2 [m] (pupil movement)
  int type = 1;            ///< CAHVORE T: 1 perspective, 2 fish-eye, 3 general
  double parameter = 0.0;  ///< CAHVORE P: the linearity of type 3

  /// L of the CAHVORE equations (1, 0 or `parameter`).
  double linearity() const;

  /// Pixel of the world point P_M (frame M). False when P lies behind the camera or the
  /// model cannot image it (CAHVORE: angle beyond the lens' range).
  bool project(const Eigen::Vector3d& P_M, Eigen::Vector2d& uv) const;

  /// Pixel of the direction d_M seen from C: the limit of project(C + s d) as s grows
  /// (for CAHVORE the pupil's movement, a few millimetres, is then negligible). Used
  /// to rectify: a rectified pixel is a direction.
  bool project_direction(const Eigen::Vector3d& d_M, Eigen::Vector2d& uv) const;

  /// The direction (unit, frame M) whose project_direction is `uv`, by Newton's method
  /// from the linear model's ray, to 1e-9 px. False if it does not converge.
  bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d& d_M) const;
};

/// The pinhole camera the CAHV part (C, A, H, V) defines, exactly (the linear model;
/// O, R, E are the distortion around it): intrinsics K (upper triangular, with the skew
/// of H' against V' if any) and the camera frame C in M (OpenCV axes: z = A, y = V', x =
/// y x z): p_M = T_M_C p_C, origin at C.
struct CahvPinhole {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  Pose3d T_M_C = Pose3d::Identity();
};

/// Throws Error prefixed by `source` if A or O is not a unit vector (within 1e-6, as JPL
/// writes them) or H, V are parallel to A or to each other.
CahvPinhole cahv_pinhole(const CahvoreModel& model, const std::string& source = "CAHV model");

/// The CAHV model of a pinhole camera with intrinsics K (upper triangular) whose frame
/// (OpenCV axes) sits at T_M_C in M.
CahvoreModel cahv_from_pinhole(const Eigen::Matrix3d& K, const Pose3d& T_M_C);

/// Reads the camera model group of a PDS3 label (a detached .LBL or the label at the
/// start of an .IMG): the first `GROUP = GEOMETRIC_CAMERA_MODEL...` up to its END_GROUP,
/// MODEL_TYPE and MODEL_COMPONENT_1..9 (C A H V O R E T P), values in parentheses
/// possibly over several lines. Throws Error naming the file and the line (or the
/// missing keyword).
CahvoreModel read_pds_camera_model(const std::filesystem::path& label);

/// Checks the model's numbers (finite, unit A and O, type in 1..3); throws Error
/// prefixed by `source`.
void validate(const CahvoreModel& model, const std::string& source);

}  // namespace hazmap
