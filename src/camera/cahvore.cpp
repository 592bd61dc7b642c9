#include "hazmap/camera/cahvore.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <Eigen/Geometry>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

/// The CAHV projection of a (distortion-corrected) vector p from C.
bool cahv(const CahvoreModel& m, const Eigen::Vector3d& p, Eigen::Vector2d& uv) {
  const double a = p.dot(m.A);
  if (!(a > 0.0)) return false;
  uv = Eigen::Vector2d(p.dot(m.H) / a, p.dot(m.V) / a);
  return uv.allFinite();
}

/// p' of the CAHVOR / CAHVORE equations for p = P - C; `pupil`: CAHVORE's moving
/// entrance pupil is solved for (a finite point) or ignored (a direction).
bool corrected(const CahvoreModel& m, const Eigen::Vector3d& p, bool pupil, Eigen::Vector3d& out) {
  if (m.kind == CahvoreKind::cahv) {
    out = p;
    return true;
  }
  const double zeta = p.dot(m.O);
  const Eigen::Vector3d lambda_v = p - zeta * m.O;
  const double lambda = lambda_v.norm();
  if (m.kind == CahvoreKind::cahvor) {
    if (!(zeta > 0.0)) return false;
    const double tau = lambda * lambda / (zeta * zeta);
    const double mu = m.R[0] + m.R[1] * tau + m.R[2] * tau * tau;
    out = p + mu * lambda_v;
    return true;
  }
  // CAHVORE. theta: angle of the incoming ray to O, from the moving pupil.
  double theta = std::atan2(lambda, zeta);
  if (pupil && m.E.squaredNorm() > 0.0) {
    for (int i = 0; i < 100; ++i) {
      const double t2 = theta * theta, s = std::sin(theta), c = std::cos(theta);
      const double e = m.E[0] + m.E[1] * t2 + m.E[2] * t2 * t2;
      const double de = 2.0 * m.E[1] * theta + 4.0 * m.E[2] * t2 * theta;
      const double f = zeta * s - lambda * c - (theta - s) * e;
      const double df = zeta * c + lambda * s - (1.0 - c) * e - (theta - s) * de;
      if (df == 0.0) return false;
      const double step = f / df;
      theta -= step;
      if (std::abs(step) < 1e-14) break;
    }
  }
  const double L = m.linearity();
  if (!(std::abs(L * theta) < 0.5 * M_PI) || !(theta >= 0.0)) return false;
  double chi = theta;
  if (L > 1e-15) chi = std::tan(L * theta) / L;
  else if (L < -1e-15) chi = std::sin(L * theta) / L;
  if (lambda < 1e-15 * std::max(1.0, std::abs(zeta)) || chi < 1e-15) {
    out = p;  // on the axis: no distortion
    return zeta > 0.0;
  }
  const double chi2 = chi * chi;
  const double mu = m.R[0] + m.R[1] * chi2 + m.R[2] * chi2 * chi2;
  out = (lambda / chi) * m.O + (1.0 + mu) * lambda_v;
  return true;
}

}  // namespace

CahvoreKind parse_cahvore_kind(const std::string& name, const std::string& what) {
  std::string lower = name;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower == "cahv") return CahvoreKind::cahv;
  if (lower == "cahvor") return CahvoreKind::cahvor;
  if (lower == "cahvore") return CahvoreKind::cahvore;
  throw Error(what + ": unknown camera model '" + name + "' (pinhole, cahv, cahvor or cahvore)");
}

const char* cahvore_kind_name(CahvoreKind kind) {
  switch (kind) {
    case CahvoreKind::cahv: return "cahv";
    case CahvoreKind::cahvor: return "cahvor";
    default: return "cahvore";
  }
}

double CahvoreModel::linearity() const {
  if (type == 1) return 1.0;
  if (type == 2) return 0.0;
  return parameter;
}

bool CahvoreModel::project(const Eigen::Vector3d& P_M, Eigen::Vector2d& uv) const {
  Eigen::Vector3d p;
  return corrected(*this, P_M - C, true, p) && cahv(*this, p, uv);
}

bool CahvoreModel::project_direction(const Eigen::Vector3d& d_M, Eigen::Vector2d& uv) const {
  Eigen::Vector3d p;
  return corrected(*this, d_M, false, p) && cahv(*this, p, uv);
}

bool CahvoreModel::unproject(const Eigen::Vector2d& uv, Eigen::Vector3d& d_M) const {
  const CahvPinhole pin = cahv_pinhole(*this);
  const Eigen::Matrix3d R_M_C = pin.T_M_C.linear();
  Eigen::Vector2d xy = (pin.K.inverse() * Eigen::Vector3d(uv.x(), uv.y(), 1.0)).head<2>();
  auto f = [&](const Eigen::Vector2d& q, Eigen::Vector2d& out) {
    return project_direction(R_M_C * Eigen::Vector3d(q.x(), q.y(), 1.0), out);
  };
  for (int i = 0; i < 50; ++i) {
    Eigen::Vector2d f0, fx, fy;
    const double h = 1e-7;
    if (!f(xy, f0) || !f(xy + Eigen::Vector2d(h, 0), fx) || !f(xy + Eigen::Vector2d(0, h), fy))
      return false;
    const Eigen::Vector2d r = f0 - uv;
    if (r.norm() < 1e-9) {
      d_M = (R_M_C * Eigen::Vector3d(xy.x(), xy.y(), 1.0)).normalized();
      return true;
    }
    Eigen::Matrix2d J;
    J.col(0) = (fx - f0) / h;
    J.col(1) = (fy - f0) / h;
    xy -= J.inverse() * r;
    if (!xy.allFinite()) return false;
  }
  return false;
}

CahvPinhole cahv_pinhole(const CahvoreModel& m, const std::string& source) {
  check(std::abs(m.A.norm() - 1.0) < 1e-6, source + ": A must be a unit vector");
  const double hc = m.A.dot(m.H), vc = m.A.dot(m.V);
  const Eigen::Vector3d h_perp = m.H - hc * m.A, v_perp = m.V - vc * m.A;
  const double hs = h_perp.norm(), vs = v_perp.norm();
  check(hs > 1e-9 && vs > 1e-9, source + ": H and V must not be parallel to A");
  const Eigen::Vector3d y = v_perp / vs, z = m.A;
  const Eigen::Vector3d x = y.cross(z);
  const Eigen::Vector3d hp = h_perp / hs;
  check(hp.dot(x) > 0.5, source + ": H' and V' must be roughly perpendicular, H' along y' x A");
  CahvPinhole pin;
  pin.K << hs * hp.dot(x), hs * hp.dot(y), hc,  //
      0.0, vs, vc,                              //
      0.0, 0.0, 1.0;
  Eigen::Matrix3d R;
  R.col(0) = x;
  R.col(1) = y;
  R.col(2) = z;
  pin.T_M_C.linear() = R;
  pin.T_M_C.translation() = m.C;
  return pin;
}

CahvoreModel cahv_from_pinhole(const Eigen::Matrix3d& K, const Pose3d& T_M_C) {
  const Eigen::Matrix3d R = T_M_C.linear();
  CahvoreModel m;
  m.kind = CahvoreKind::cahv;
  m.C = T_M_C.translation();
  m.A = R.col(2);
  m.O = m.A;
  // u = (fx X + s Y + cx Z) / Z with (X, Y, Z) = R^T p: H = R (fx, s, cx), V = R (0, fy, cy).
  m.H = R * Eigen::Vector3d(K(0, 0), K(0, 1), K(0, 2));
  m.V = R * Eigen::Vector3d(0.0, K(1, 1), K(1, 2));
  return m;
}

CahvoreModel read_pds_camera_model(const std::filesystem::path& label) {
  std::ifstream in(label, std::ios::binary);
  if (!in) throw Error(label.string() + ": cannot open PDS label");
  const std::string source = label.string();
  auto at = [&](int line, const std::string& what) {
    return Error(source + ":" + std::to_string(line) + ": " + what);
  };
  auto trim = [](std::string t) {
    const auto a = t.find_first_not_of(" \t\r\"");
    const auto b = t.find_last_not_of(" \t\r\"");
    return a == std::string::npos ? std::string() : t.substr(a, b - a + 1);
  };
  // keyword -> (value, line) inside the camera model group
  std::map<std::string, std::pair<std::string, int>> values;
  bool in_group = false, done = false;
  std::string line, pending_key;
  int line_no = 0, pending_line = 0;
  std::string pending;
  while (!done && std::getline(in, line)) {
    ++line_no;
    if (!pending_key.empty()) {  // a value in parentheses continued
      pending += " " + trim(line);
      if (pending.find(')') != std::string::npos) {
        values[pending_key] = {pending, pending_line};
        pending_key.clear();
      }
      continue;
    }
    const auto eq = line.find('=');
    const std::string key = trim(line.substr(0, eq));
    if (key == "END") break;  // end of the label: image data may follow
    if (eq == std::string::npos) continue;
    const std::string value = trim(line.substr(eq + 1));
    if (key == "GROUP" && value.rfind("GEOMETRIC_CAMERA_MODEL", 0) == 0) {
      in_group = true;
      continue;
    }
    if (!in_group) continue;
    if (key == "END_GROUP") {
      done = true;
      continue;
    }
    if (!value.empty() && value[0] == '(' && value.find(')') == std::string::npos) {
      pending_key = key;
      pending = value;
      pending_line = line_no;
      continue;
    }
    values[key] = {value, line_no};
  }
  if (!in_group) throw Error(source + ": no GROUP = GEOMETRIC_CAMERA_MODEL in the label");
  if (!pending_key.empty()) throw at(pending_line, pending_key + ": unclosed '('");
  auto get = [&](const std::string& key) -> const std::pair<std::string, int>& {
    const auto it = values.find(key);
    if (it == values.end()) throw Error(source + ": camera model group lacks " + key);
    return it->second;
  };
  auto numbers = [&](const std::string& key, std::size_t n) {
    const auto& [text, where] = get(key);
    std::string t = text;
    for (char& c : t)
      if (c == '(' || c == ')' || c == ',') c = ' ';
    std::istringstream fields(t);
    std::vector<double> out;
    for (std::string tok; fields >> tok;) {
      // PDS may attach units: "1.5 <m>" -> skip the unit token
      if (tok[0] == '<') continue;
      char* end = nullptr;
      const double v = std::strtod(tok.c_str(), &end);
      if (*end != '\0' || !std::isfinite(v)) throw at(where, key + ": not a number: '" + tok + "'");
      out.push_back(v);
    }
    if (out.size() != n)
      throw at(where, key + ": expected " + std::to_string(n) + " numbers, found " +
                          std::to_string(out.size()));
    return out;
  };
  auto vec3 = [&](const std::string& key) {
    const auto v = numbers(key, 3);
    return Eigen::Vector3d(v[0], v[1], v[2]);
  };
  CahvoreModel m;
  const auto& type = get("MODEL_TYPE");
  std::string kind = trim(type.first);
  try {
    m.kind = parse_cahvore_kind(kind, "MODEL_TYPE");
  } catch (const Error& e) {
    throw at(type.second, e.what());
  }
  m.C = vec3("MODEL_COMPONENT_1");
  m.A = vec3("MODEL_COMPONENT_2");
  m.H = vec3("MODEL_COMPONENT_3");
  m.V = vec3("MODEL_COMPONENT_4");
  m.O = m.A;
  if (m.kind != CahvoreKind::cahv) {
    m.O = vec3("MODEL_COMPONENT_5");
    m.R = vec3("MODEL_COMPONENT_6");
  }
  if (m.kind == CahvoreKind::cahvore) {
    m.E = vec3("MODEL_COMPONENT_7");
    const double t = numbers("MODEL_COMPONENT_8", 1)[0];
    if (t != 1.0 && t != 2.0 && t != 3.0)
      throw at(get("MODEL_COMPONENT_8").second, "MODEL_COMPONENT_8 (T) must be 1, 2 or 3");
    m.type = static_cast<int>(t);
    if (m.type == 3) m.parameter = numbers("MODEL_COMPONENT_9", 1)[0];
  }
  validate(m, source);
  return m;
}

void validate(const CahvoreModel& m, const std::string& source) {
  for (const auto* v : {&m.C, &m.A, &m.H, &m.V, &m.O, &m.R, &m.E})
    check(v->allFinite(), source + ": every component must be a finite number");
  check(std::abs(m.O.norm() - 1.0) < 1e-6, source + ": O must be a unit vector");
  check(m.O.dot(m.A) > 0.5, source + ": O must lie within 60 deg of A");
  check(m.type >= 1 && m.type <= 3, source + ": type must be 1, 2 or 3");
  check(std::isfinite(m.parameter), source + ": parameter must be finite");
  cahv_pinhole(m, source);
}

}  // namespace hazmap
