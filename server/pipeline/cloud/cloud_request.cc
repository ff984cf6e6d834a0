#include "server/pipeline/cloud/cloud_request.h"

#include "server/convert/convert.h"

namespace omniview {

ColourOptions CloudRequest::colour_options() const {
  ColourOptions o;
  o.fusion = fusion;
  o.occlusion = occlusion;
  return o;
}

CloudRequest cloud_request_from_proto(const v1::CloudOptions& options) {
  CloudRequest r;
  r.frame = options.frame();
  r.voxel_m = options.voxel_size_m();
  if (options.has_crop()) {
    const auto& c = options.crop();
    r.crop = Eigen::AlignedBox3d(Eigen::Vector3d(c.min().x(), c.min().y(), c.min().z()),
                                 Eigen::Vector3d(c.max().x(), c.max().y(), c.max().z()));
  }
  if (options.fusion() != v1::FUSION_UNSPECIFIED) r.fusion = from_proto(options.fusion(), "options.fusion");
  r.occlusion = !options.has_occlusion() || options.occlusion();
  return r;
}

}  // namespace omniview
