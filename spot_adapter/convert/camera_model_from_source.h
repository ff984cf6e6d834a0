// A robot image source's calibration as one of omniview's camera models. Spot reports a
// plain pinhole (its body cameras deliver rectified images), pinhole with Brown-Conrady
// distortion, or Kannala-Brandt: these are kalibr's pinhole, pinhole-radtan (with k3, as
// OpenCV's five coefficients) and equidistant.
#pragma once

#include <string>

#include "bosdyn/api/image.pb.h"
#include "core/camera/camera.h"

namespace omniview::spot {

// Model, width and height of `source`. Throws SpotError(kProtocol) naming the source when
// it reports no model, an unknown one, or numbers that cannot be a camera (zero focal
// length, an absurd size, NaN).
Camera camera_from_image_source(const bosdyn::api::ImageSource& source);

}  // namespace omniview::spot
