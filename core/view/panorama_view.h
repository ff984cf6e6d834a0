// Panoramas: cylindrical (the paper's "Mercator": a central cylinder), true Mercator and
// equirectangular (both on a sphere).
//
// Columns (all three): azimuth lambda = span * (0.5 - (u + 0.5) / W), so the centre column
// looks along the view's +x and u grows to the right; a 360 deg panorama's edges are
// straight behind.
// Rows: cylindrical  h   = r tan(vfov/2) (1 - 2 (v + 0.5) / H)
//       equirect.    phi = lat_max - (lat_max - lat_min) (v + 0.5) / H
//       mercator     y   = y(lat_max) - (y(lat_max) - y(lat_min)) (v + 0.5) / H,
//                    y(phi) = ln tan(pi/4 + phi/2), phi = atan(sinh y)
#pragma once

#include <vector>

#include "core/view/view.h"

namespace omniview {

class PanoramaView : public View {
 public:
  explicit PanoramaView(const ViewSpec& spec);

  bool pixel_to_direction(double u, double v, Vec3& dir) const override;
  bool point_to_pixel(const Vec3& point, Vec2& uv) const override;

 protected:
  void surface_row_points(int v, float* x, float* y, float* z, uint8_t* valid) const override;
  void surface_points_at(int v, const int* columns, int n, float* x, float* y, float* z,
                         uint8_t* valid) const override;
  double surface_range(const Vec3& unit_dir) const override;

 private:
  template <typename Column>
  void points(int v, Column column, int n, float* x, float* y, float* z, uint8_t* valid) const;
  double azimuth(double u) const;
  // Elevation coordinate of row v: height on the unit-radius cylinder, or latitude.
  double row_coordinate(double v) const;

  double span_;                  // azimuth span (rad)
  double top_, bottom_;          // row coordinate at the top and bottom image edges
  std::vector<float> cos_az_, sin_az_;  // per column, for surface_row_points
};

}  // namespace omniview
