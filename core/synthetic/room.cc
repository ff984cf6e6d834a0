// The bundled example's room: what config/examples/dual_fisheye/{front,back}.jpg show.
#include "core/synthetic/scene.h"

namespace omniview::synthetic {
namespace {

// Muted versions of the test texture over a base colour (BGR), so each surface is
// recognisable while misalignments in a stitched view still show.
Material wall(const Vec3& bgr) { return {.texture_contrast = 0.3, .base = bgr, .grid_m = 1.0, .lit = true}; }

}  // namespace

Scene Scene::room() {
  Scene s;
  // The shell: an 8 x 5.5 x 3 m box around the rig (which stands at the origin). Walls are
  // planes so each can wear its own colour; beyond the box nothing is visible anyway.
  const double x_front = 4.5, x_back = -3.5, y_left = 3.0, y_right = -2.5, ceiling = 3.0;
  s.add(Plane{Vec3::UnitZ(), 0.0}, {.texture_contrast = 0.2, .base = Vec3(80, 120, 165), .tiles_m = 0.5, .lit = true});
  s.add(Plane{Vec3::UnitZ(), ceiling}, {.texture_contrast = 0.15, .base = Vec3(225, 228, 230), .grid_m = 0.6, .lit = true});
  s.add(Plane{Vec3::UnitX(), x_front}, wall(Vec3(190, 150, 110)));   // blue-grey
  s.add(Plane{Vec3::UnitX(), x_back}, wall(Vec3(120, 170, 130)));    // sage green
  s.add(Plane{Vec3::UnitY(), y_left}, wall(Vec3(100, 130, 200)));    // terracotta
  s.add(Plane{Vec3::UnitY(), y_right}, wall(Vec3(170, 200, 215)));   // cream
  // Two columns and two cabinets standing at different distances: parallax between the
  // lenses shows at their edges in any stitched view.
  const Material concrete{.texture_contrast = 0.25, .base = Vec3(165, 165, 165), .grid_m = 0.5, .lit = true};
  s.add(Cylinder{Vec3(2.0, 1.2, 0), 0.25, 0.0, ceiling}, concrete);
  s.add(Cylinder{Vec3(-1.5, -1.4, 0), 0.3, 0.0, ceiling}, concrete);
  const Material wood{.texture_contrast = 0.3, .base = Vec3(50, 90, 140), .grid_m = 0.4, .lit = true};
  s.add(Box{Vec3(3.6, -2.5, 0), Vec3(4.5, -1.0, 1.4)}, wood);   // a cabinet against the front wall
  s.add(Box{Vec3(-0.8, 1.6, 0), Vec3(0.6, 2.4, 0.75)}, wood);   // a low sideboard on the left
  return s;
}

}  // namespace omniview::synthetic
