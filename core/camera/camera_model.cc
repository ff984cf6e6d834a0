#include "core/camera/camera_model.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace omniview {
namespace {

std::string join(const std::vector<double>& v) {
  std::ostringstream os;
  os << "[";
  for (size_t i = 0; i < v.size(); ++i) os << (i ? ", " : "") << v[i];
  os << "]";
  return os.str();
}

void expect_count(const std::vector<double>& v, size_t lo, size_t hi, const std::string& what,
                  const std::string& field, const std::string& names) {
  if (v.size() < lo || v.size() > hi) {
    std::ostringstream os;
    os << what << ": " << field << " needs " << (lo == hi ? std::to_string(lo)
                                                          : std::to_string(lo) + " or " + std::to_string(hi))
       << (hi == 1 ? " value " : " values ") << names << ", got " << v.size() << " " << join(v);
    throw std::invalid_argument(os.str());
  }
  for (double x : v) {
    if (!std::isfinite(x)) throw std::invalid_argument(what + ": " + field + " has a non-finite value " + join(v));
  }
}

void expect(bool ok, const std::string& what, const std::string& message) {
  if (!ok) throw std::invalid_argument(what + ": " + message);
}

void check_focal(double fu, double fv, const std::string& what) {
  expect(fu > 0 && fv > 0, what, "intrinsics: focal lengths fu, fv must be positive, got " +
                                     std::to_string(fu) + ", " + std::to_string(fv));
}

RadtanDistortion radtan_from(const ModelSpec& s, const std::string& what) {
  RadtanDistortion d;
  if (s.distortion_model == "none") {
    expect(s.distortion.empty() || std::all_of(s.distortion.begin(), s.distortion.end(),
                                               [](double x) { return x == 0; }),
           what, "distortion_model none takes no distortion_coeffs, got " + join(s.distortion));
    return d;
  }
  expect_count(s.distortion, 4, 5, what, "distortion_coeffs", "[k1, k2, p1, p2(, k3)]");
  d.k1 = s.distortion[0];
  d.k2 = s.distortion[1];
  d.p1 = s.distortion[2];
  d.p2 = s.distortion[3];
  d.k3 = s.distortion.size() == 5 ? s.distortion[4] : 0;
  return d;
}

}  // namespace

CameraModel make_camera_model(const ModelSpec& s, const std::string& what) {
  const std::string& cm = s.camera_model;
  const std::string& dm = s.distortion_model.empty() ? std::string("none") : s.distortion_model;
  ModelSpec spec = s;
  spec.distortion_model = dm;
  const auto& in = s.intrinsics;
  if (cm == "pinhole") {
    expect_count(in, 4, 4, what, "intrinsics", "[fu, fv, pu, pv]");
    check_focal(in[0], in[1], what);
    if (dm == "radtan" || dm == "none") {
      return PinholeRadtan(in[0], in[1], in[2], in[3], radtan_from(spec, what));
    }
    if (dm == "equidistant") {
      expect_count(s.distortion, 4, 4, what, "distortion_coeffs", "[k1, k2, k3, k4]");
      const auto& k = s.distortion;
      return Equidistant(in[0], in[1], in[2], in[3], k[0], k[1], k[2], k[3]);
    }
    if (dm == "fov") {
      expect_count(s.distortion, 1, 1, what, "distortion_coeffs", "[w]");
      expect(s.distortion[0] > 0 && s.distortion[0] < M_PI, what,
             "distortion_coeffs: fov w must be in (0, pi) radians, got " + std::to_string(s.distortion[0]));
      return Fov(in[0], in[1], in[2], in[3], s.distortion[0]);
    }
    throw std::invalid_argument(what + ": distortion_model '" + dm +
                                "' is not supported with camera_model pinhole (use radtan, "
                                "equidistant, fov or none)");
  }
  if (cm == "omni") {
    expect_count(in, 5, 5, what, "intrinsics", "[xi, fu, fv, pu, pv]");
    check_focal(in[1], in[2], what);
    expect(in[0] >= 0, what, "intrinsics: omni xi must be >= 0, got " + std::to_string(in[0]));
    if (dm == "radtan" || dm == "none") {
      return OmniRadtan(in[0], in[1], in[2], in[3], in[4], radtan_from(spec, what));
    }
    throw std::invalid_argument(what + ": distortion_model '" + dm +
                                "' is not supported with camera_model omni (use radtan or none)");
  }
  if (cm == "ds" || cm == "eucm") {
    expect(dm == "none", what, "camera_model " + cm + " takes distortion_model none, got '" + dm + "'");
    expect(s.distortion.empty(), what, "camera_model " + cm + " takes no distortion_coeffs");
    if (cm == "ds") {
      expect_count(in, 6, 6, what, "intrinsics", "[xi, alpha, fu, fv, pu, pv]");
      check_focal(in[2], in[3], what);
      expect(in[1] >= 0 && in[1] <= 1, what, "intrinsics: ds alpha must be in [0, 1], got " + std::to_string(in[1]));
      expect(in[0] > -1, what, "intrinsics: ds xi must be > -1, got " + std::to_string(in[0]));
      return DoubleSphere(in[0], in[1], in[2], in[3], in[4], in[5]);
    }
    expect_count(in, 6, 6, what, "intrinsics", "[alpha, beta, fu, fv, pu, pv]");
    check_focal(in[2], in[3], what);
    expect(in[0] >= 0 && in[0] <= 1, what, "intrinsics: eucm alpha must be in [0, 1], got " + std::to_string(in[0]));
    expect(in[1] > 0, what, "intrinsics: eucm beta must be > 0, got " + std::to_string(in[1]));
    return Eucm(in[0], in[1], in[2], in[3], in[4], in[5]);
  }
  std::string known;
  for (const auto& m : supported_models()) known += " " + m.camera_model + "+" + m.distortion_model;
  throw std::invalid_argument(what + ": unknown camera_model '" + cm + "' (supported:" + known + ")");
}

ModelSpec describe(const CameraModel& model) {
  struct Visitor {
    ModelSpec operator()(const PinholeRadtan& m) const {
      const auto& d = m.distortion();
      if (d.is_zero()) return {"pinhole", "none", {m.fu(), m.fv(), m.pu(), m.pv()}, {}};
      std::vector<double> k{d.k1, d.k2, d.p1, d.p2};
      if (d.k3 != 0) k.push_back(d.k3);
      return {"pinhole", "radtan", {m.fu(), m.fv(), m.pu(), m.pv()}, k};
    }
    ModelSpec operator()(const Equidistant& m) const {
      const auto k = m.k();
      return {"pinhole", "equidistant", {m.fu(), m.fv(), m.pu(), m.pv()}, {k[0], k[1], k[2], k[3]}};
    }
    ModelSpec operator()(const Fov& m) const {
      return {"pinhole", "fov", {m.fu(), m.fv(), m.pu(), m.pv()}, {m.w()}};
    }
    ModelSpec operator()(const OmniRadtan& m) const {
      const auto& d = m.distortion();
      std::vector<double> in{m.xi(), m.fu(), m.fv(), m.pu(), m.pv()};
      if (d.is_zero()) return {"omni", "none", in, {}};
      std::vector<double> k{d.k1, d.k2, d.p1, d.p2};
      if (d.k3 != 0) k.push_back(d.k3);
      return {"omni", "radtan", in, k};
    }
    ModelSpec operator()(const DoubleSphere& m) const {
      return {"ds", "none", {m.xi(), m.alpha(), m.fu(), m.fv(), m.pu(), m.pv()}, {}};
    }
    ModelSpec operator()(const Eucm& m) const {
      return {"eucm", "none", {m.alpha(), m.beta(), m.fu(), m.fv(), m.pu(), m.pv()}, {}};
    }
  };
  return std::visit(Visitor{}, model);
}

bool project(const CameraModel& model, const Eigen::Vector3d& p, Eigen::Vector2d& uv) {
  return std::visit([&](const auto& m) { return m.project(p.x(), p.y(), p.z(), uv.x(), uv.y()); },
                    model);
}

bool unproject(const CameraModel& model, const Eigen::Vector2d& uv, Eigen::Vector3d& ray) {
  return std::visit([&](const auto& m) { return m.unproject(uv.x(), uv.y(), ray); }, model);
}

const std::vector<ModelInfo>& supported_models() {
  static const std::vector<ModelInfo> models{
      {"pinhole", "none", "[fu, fv, pu, pv]", "[]", "ideal pinhole (Spot's PinholeModel)"},
      {"pinhole", "radtan", "[fu, fv, pu, pv]", "[k1, k2, p1, p2] or [k1, k2, p1, p2, k3]",
       "Brown-Conrady / OpenCV plumb_bob (Spot's PinholeBrownConrady)"},
      {"pinhole", "equidistant", "[fu, fv, pu, pv]", "[k1, k2, k3, k4]",
       "Kannala-Brandt fisheye, theta = atan2(r, z): works beyond 180 deg (Spot's KannalaBrandtModel)"},
      {"pinhole", "fov", "[fu, fv, pu, pv]", "[w]", "Devernay-Faugeras field-of-view model, w in radians"},
      {"omni", "none", "[xi, fu, fv, pu, pv]", "[]", "Mei unified omnidirectional model"},
      {"omni", "radtan", "[xi, fu, fv, pu, pv]", "[k1, k2, p1, p2] or [k1, k2, p1, p2, k3]",
       "Mei unified model with radial-tangential distortion (cv::omnidir)"},
      {"ds", "none", "[xi, alpha, fu, fv, pu, pv]", "[]", "double sphere (Usenko et al. 2018)"},
      {"eucm", "none", "[alpha, beta, fu, fv, pu, pv]", "[]",
       "enhanced unified camera model (Khomutenko et al. 2016)"},
  };
  return models;
}

}  // namespace omniview
