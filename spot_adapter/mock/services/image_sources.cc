#include "spot_adapter/mock/services/image_sources.h"

#include <stdexcept>

#include "spot_adapter/mock/sensors/camera_depth.h"

namespace omniview::spot_mock {

bosdyn::api::ImageSource describe_source(const MockCamera& mock_camera, const Camera& camera, bool colour_robot) {
  const auto* pinhole = std::get_if<PinholeRadtan>(&camera.model);
  if (!pinhole) throw std::logic_error("spot-mock's cameras are pinholes (" + camera.name + " is not)");
  using bosdyn::api::Image;
  bosdyn::api::ImageSource s;
  s.set_name(mock_camera.source);
  s.set_cols(camera.width);
  s.set_rows(camera.height);
  auto* intrinsics = s.mutable_pinhole()->mutable_intrinsics();
  intrinsics->mutable_focal_length()->set_x(pinhole->fu());
  intrinsics->mutable_focal_length()->set_y(pinhole->fv());
  intrinsics->mutable_principal_point()->set_x(pinhole->pu());
  intrinsics->mutable_principal_point()->set_y(pinhole->pv());
  intrinsics->mutable_skew();  // zero skew, sent explicitly as the robot does
  s.set_image_type(bosdyn::api::ImageSource::IMAGE_TYPE_VISUAL);
  s.add_pixel_formats(colour_robot ? Image::PIXEL_FORMAT_RGB_U8 : Image::PIXEL_FORMAT_GREYSCALE_U8);
  if (colour_robot) s.add_pixel_formats(Image::PIXEL_FORMAT_GREYSCALE_U8);
  s.add_image_formats(Image::FORMAT_JPEG);
  s.add_image_formats(Image::FORMAT_RAW);
  return s;
}

std::string depth_source_name(const MockCamera& mock_camera) { return mock_camera.mount_frame + "_depth_in_visual_frame"; }

bosdyn::api::ImageSource describe_depth_source(const MockCamera& mock_camera, const Camera& camera) {
  using bosdyn::api::Image;
  bosdyn::api::ImageSource s = describe_source(mock_camera, camera, false);
  s.set_name(depth_source_name(mock_camera));
  s.set_image_type(bosdyn::api::ImageSource::IMAGE_TYPE_DEPTH);
  s.set_depth_scale(kDepthScale);
  s.clear_pixel_formats();
  s.add_pixel_formats(Image::PIXEL_FORMAT_DEPTH_U16);
  s.clear_image_formats();
  s.add_image_formats(Image::FORMAT_RAW);
  return s;
}

}  // namespace omniview::spot_mock
