// The paper's fusion criterion, one rule for views and clouds: among the cameras that see a
// point, the one whose pixel lies nearest its image centre wins (there its lens distorts
// and vignettes least). The distance is measured per axis in units of the image's size, so
// cameras of different resolution and aspect ratio compete fairly. The fusion map's kernels
// (core/map) and the cloud colourer (core/cloud) both score with this, so a surface point
// of a view and the same point of a cloud take the same camera.
#pragma once

#include "core/camera/camera.h"

namespace omniview {

struct CentreScore {
  float centre_u = 0, centre_v = 0;  // the image centre (pixel centres at integers)
  float inv_w = 0, inv_h = 0;

  static CentreScore of(const Camera& camera) {
    CentreScore s;
    s.centre_u = static_cast<float>(camera.width - 1) / 2;
    s.centre_v = static_cast<float>(camera.height - 1) / 2;
    s.inv_w = 1.0f / static_cast<float>(camera.width);
    s.inv_h = 1.0f / static_cast<float>(camera.height);
    return s;
  }

  // Lower is better; 0.5 at a corner of the image.
  [[gnu::always_inline]] float operator()(float u, float v) const {
    const float du = (u - centre_u) * inv_w, dv = (v - centre_v) * inv_h;
    return du * du + dv * dv;
  }
};

}  // namespace omniview
