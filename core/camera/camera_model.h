// One calibrated camera model, whichever of the supported kinds it is.
//
// A std::variant rather than a virtual base: the map builder visits the variant once per
// camera and then runs a loop specialised to that model, so the projection inlines and
// vectorises. Names and parameter orders are kalibr's (README, "Rendering views offline").
#pragma once

#include <string>
#include <variant>
#include <vector>

#include <Eigen/Core>

#include "core/camera/double_sphere.h"
#include "core/camera/equidistant.h"
#include "core/camera/eucm.h"
#include "core/camera/fov.h"
#include "core/camera/omni_radtan.h"
#include "core/camera/pinhole_radtan.h"

namespace omniview {

using CameraModel = std::variant<PinholeRadtan, Equidistant, Fov, OmniRadtan, DoubleSphere, Eucm>;

// A model as calibration files write it.
struct ModelSpec {
  std::string camera_model;       // pinhole | omni | ds | eucm
  std::string distortion_model;   // radtan | equidistant | fov | none
  std::vector<double> intrinsics;
  std::vector<double> distortion;
};

// Builds a model; throws std::invalid_argument naming `what` (e.g. "rig.yaml: cam1")
// for an unknown model or combination, a wrong parameter count, or non-finite or
// impossible values (focal lengths <= 0, xi < 0, alpha outside [0, 1], ...).
CameraModel make_camera_model(const ModelSpec& spec, const std::string& what);

// The spec that make_camera_model() would turn back into `model`.
ModelSpec describe(const CameraModel& model);

// Projects a point in the camera's optical frame; false if the model cannot image it.
bool project(const CameraModel& model, const Eigen::Vector3d& p, Eigen::Vector2d& uv);
// Unit ray through pixel `uv`; false where no ray maps there.
bool unproject(const CameraModel& model, const Eigen::Vector2d& uv, Eigen::Vector3d& ray);

// For --list-models: every accepted combination, its parameters, and a note.
struct ModelInfo {
  std::string camera_model;
  std::string distortion_model;
  std::string intrinsics;
  std::string distortion;
  std::string note;
};
const std::vector<ModelInfo>& supported_models();

}  // namespace omniview
