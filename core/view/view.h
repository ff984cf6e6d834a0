// A view: the projection surface behind every output pixel, and the way back.
//
// All surfaces are central: every pixel's ray starts at the view frame's origin (the
// virtual camera's centre) and meets the surface once. pixel_to_point gives that surface
// point; point_to_pixel takes any 3D point, surface or not, to the pixel whose ray passes
// through it, which is what clients need to click and to draw overlays.
//
// `ground: true` cuts any surface with the ground plane (z = ground_z of the view's frame):
// a ray that meets the ground before the plane, cylinder or sphere ends there, as in a
// car's surround view bowl. Whatever lies on the ground then has no parallax between
// cameras, so seams across the floor vanish and its texture stays sharp; the type's own
// surface still catches what stands up from it.
// Coordinates are in the view frame (x viewing direction, y left, z up) unless named.
#pragma once

#include <cstdint>
#include <memory>

#include "core/view/view_spec.h"

namespace omniview {

class View {
 public:
  virtual ~View() = default;

  // Validates the spec; throws std::invalid_argument naming the view and field.
  static std::unique_ptr<View> create(const ViewSpec& spec);

  const ViewSpec& spec() const { return spec_; }
  int width() const { return spec_.width; }
  int height() const { return spec_.height; }

  // Direction (not necessarily unit) of pixel (u, v)'s ray; false outside the surface
  // (a fisheye view's corners, a bird's-eye ray above the horizon).
  virtual bool pixel_to_direction(double u, double v, Vec3& dir) const = 0;
  // Surface point seen at pixel (u, v).
  bool pixel_to_point(double u, double v, Vec3& point) const;
  // Pixel at which `point` appears; false if it is outside the image or behind the view.
  virtual bool point_to_pixel(const Vec3& point, Vec2& uv) const = 0;

  // Surface points of one output row, in float, for the map builder. Invalid pixels get
  // valid[i] = 0 and unspecified coordinates.
  void row_points(int v, float* x, float* y, float* z, uint8_t* valid) const;
  // The same for chosen columns of row v: outputs i = 0..n-1 for pixel (columns[i], v),
  // bit for bit what row_points gives there. The adaptive builder samples sparse lattices
  // and isolated exact pixels with it, and never pays for the rest of the row.
  void points_at(int v, const int* columns, int n, float* x, float* y, float* z, uint8_t* valid) const;
  // Whether the surface over pixels [x0, x1] x [y0, y1] (inclusive) is smooth enough for the
  // adaptive map builder to interpolate across it from samples: every pixel's range within
  // `tolerance_rel` of the bilinear blend of the corners' (the builder sets it from how far
  // a camera sees the point move). Analytic surfaces always are (the builder's own midpoint
  // test catches strong curvature); measured depth has steps between the samples (a thin
  // post) that the samples alone would miss.
  virtual bool smooth_over(int x0, int y0, int x1, int y1, float tolerance_rel) const {
    (void)tolerance_rel;
    return x0 <= x1 && y0 <= y1;
  }
  // Whether smooth_over can ever say no (the builder then keeps the samples' points).
  virtual bool measured() const { return false; }

 protected:
  explicit View(const ViewSpec& spec);
  // Distance along the unit ray `dir` to the type's own surface; <= 0 where it misses.
  virtual double surface_range(const Vec3& unit_dir) const = 0;
  // row_points and points_at of the type's own surface, before the ground cut (default:
  // per pixel).
  virtual void surface_row_points(int v, float* x, float* y, float* z, uint8_t* valid) const;
  virtual void surface_points_at(int v, const int* columns, int n, float* x, float* y, float* z,
                                 uint8_t* valid) const;
  bool in_image(const Vec2& uv) const {
    return uv.x() >= -0.5 && uv.y() >= -0.5 && uv.x() <= width() - 0.5 && uv.y() <= height() - 0.5;
  }

  ViewSpec spec_;

 private:
  // `ground: true`: a surface point below the ground plane moves up its ray onto the ground.
  void cut_at_ground(float& x, float& y, float& z) const;
  Vec3 down_;            // the parent frame's -z in the view frame
  double height_ = 0;    // the view's origin above the ground plane (m)
};

}  // namespace omniview
