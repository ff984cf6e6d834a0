// Fuzz target: a robot's GetImageResponse (protobuf bytes off the wire) turned into what
// the Spot source delivers: each image decoded for the size its source reports, its frame
// tree and its calibration, and each read as a depth image (points). SpotError is the
// expected answer to bad input; a crash, a hang or any other exception is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "bosdyn/api/image_service.pb.h"
#include "spot_adapter/client/spot_error.h"
#include "spot_adapter/convert/camera_model_from_source.h"
#include "spot_adapter/convert/depth_from_response.h"
#include "spot_adapter/convert/frame_tree.h"
#include "spot_adapter/convert/image_from_response.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  bosdyn::api::GetImageResponse response;
  if (!response.ParseFromArray(data, static_cast<int>(size))) return 0;
  for (const auto& r : response.image_responses()) {
    using omniview::spot::SpotError;
    int width = 640, height = 480;
    try {
      auto camera = omniview::spot::camera_from_image_source(r.source());
      width = camera.width, height = camera.height;
      camera.name = "fuzz";
      // The same response as a depth image (Spot's *_depth_in_visual_frame): points or SpotError.
      for (const auto& p : omniview::spot::points_from_depth_response(r, camera, 1)) {
        if (!p.allFinite() || !(p.z() > 0)) std::abort();
      }
    } catch (const SpotError&) {
    }
    try {
      const auto d = omniview::spot::decode_image_response(r, "fuzz", width, height);
      if (d.image.cols != width || d.image.rows != height || d.image.depth() != CV_8U) std::abort();
      if (d.image.channels() != 1 && d.image.channels() != 3) std::abort();
    } catch (const SpotError&) {
    }
    try {
      omniview::spot::frame_edges(r.shot().transforms_snapshot(), "fuzz");
    } catch (const SpotError&) {
    }
  }
  return 0;
}
