#include "spot_adapter/convert/camera_model_from_source.h"

#include <stdexcept>

#include "spot_adapter/client/spot_error.h"

namespace omniview::spot {
namespace {

using Source = bosdyn::api::ImageSource;
using Intrinsics = Source::PinholeModel::CameraIntrinsics;

[[noreturn]] void fail(const Source& s, const std::string& message) {
  throw SpotError(SpotError::Kind::kProtocol, "image source '" + s.name() + "': " + message);
}

std::vector<double> pinhole(const Source& s, const Intrinsics& in) {
  if (in.skew().x() != 0 || in.skew().y() != 0) {
    fail(s, "skewed pixel axes are not supported");  // Spot's cameras report none
  }
  return {in.focal_length().x(), in.focal_length().y(), in.principal_point().x(), in.principal_point().y()};
}

ModelSpec model_spec(const Source& s) {
  switch (s.camera_models_case()) {
    case Source::kPinhole:
      return {"pinhole", "none", pinhole(s, s.pinhole().intrinsics()), {}};
    case Source::kPinholeBrownConrady: {
      const auto& in = s.pinhole_brown_conrady().intrinsics();
      return {"pinhole", "radtan", pinhole(s, in.pinhole_intrinsics()), {in.k1(), in.k2(), in.p1(), in.p2(), in.k3()}};
    }
    case Source::kKannalaBrandt: {
      const auto& in = s.kannala_brandt().intrinsics();
      return {"pinhole", "equidistant", pinhole(s, in.pinhole_intrinsics()), {in.k1(), in.k2(), in.k3(), in.k4()}};
    }
    default:
      fail(s, "reports no camera model (pinhole, pinhole_brown_conrady or kannala_brandt)");
  }
}

}  // namespace

Camera camera_from_image_source(const Source& s) {
  Camera c;
  c.name = s.name();
  c.width = s.cols();
  c.height = s.rows();
  if (c.width < 2 || c.height < 2 || c.width > 16384 || c.height > 16384) {
    fail(s, "reports an image size of " + std::to_string(c.width) + "x" + std::to_string(c.height));
  }
  try {
    // The same checks as a calibration file gets: finite, focal lengths > 0, ...
    c.model = make_camera_model(model_spec(s), "image source '" + s.name() + "'");
  } catch (const std::invalid_argument& e) {
    throw SpotError(SpotError::Kind::kProtocol, e.what());
  }
  return c;
}

}  // namespace omniview::spot
