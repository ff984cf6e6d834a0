// What a measured-depth surface needs of a view and keeps between depth updates: each
// pixel's unit ray and the range to the view's fixed surface along it.
#pragma once

#include <memory>
#include <vector>

#include "core/view/view.h"

namespace omniview {

struct ViewRays {
  std::shared_ptr<const View> view;  // the view on its fixed surface
  int width = 0, height = 0;
  std::vector<float> x, y, z;        // unit ray per pixel, view frame, row-major
  std::vector<uint8_t> valid;        // the pixel has a ray (a fisheye's corners do not)
  // Range along the ray to the fixed surface (the ground cut included); 0 where it has none
  // (a bird's-eye ray above the horizon).
  std::vector<float> fixed_range;
  // The fixed surface point is on the ground plane (a bird's-eye view, `ground: true`): the
  // floor is real geometry, where a plane at `distance` is a guess.
  std::vector<uint8_t> fixed_on_ground;
  double pixel_rad = 0;              // angle between neighbouring rays at the image centre

  size_t size() const { return x.size(); }
};

// Rays of `view` (any type). O(pixels) once per view change.
std::shared_ptr<const ViewRays> make_view_rays(std::shared_ptr<const View> view);

}  // namespace omniview
