// Helpers shared by the robot overlay tests: masks, projections, temporary folders and
// writers of small mesh files.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/robot/model/robot_model.h"
#include "core/robot/render/pinhole_camera.h"

namespace omniview::robot::test {

std::filesystem::path spot_urdf();  // the Spot-like URDF shipped in config/robots/spot

// 255 where the BGRA image's alpha is non-zero, 0 elsewhere.
cv::Mat alpha_mask(const cv::Mat& bgra);

// A bird's-eye view `height` above the base frame's origin plane, at (x, y), looking down
// with `pitch_deg` (90: straight down) and `yaw_deg`.
ViewSpec birdseye_view(int width, int height, double hfov_deg, double x, double y, double height_m,
                       double yaw_deg, double pitch_deg);

// Pixels of points given in the robot's base frame.
std::vector<cv::Point2f> project(const PinholeCamera& camera, const Pose& T_robot_camera, const std::vector<Vec3>& points);

// Every vertex of the link's visuals, in the base frame, for the given joint positions.
std::vector<Vec3> link_vertices(const RobotModel& model, const std::string& link, const std::vector<double>& positions);

// The mask of pixels whose centres are inside the convex hull of `pixels`, and the signed
// distance (px, positive inside) of each pixel centre to that hull's boundary.
void hull_mask(const std::vector<cv::Point2f>& pixels, cv::Size size, cv::Mat& mask, cv::Mat& distance);

// Counts pixels where `mask` and the hull of `pixels` disagree by more than `band_px` from
// the hull's edge (rasterisation rounding right on the edge is allowed).
int hull_disagreements(const cv::Mat& mask, const std::vector<cv::Point2f>& pixels, double band_px);

// A folder under the system's temp folder, removed with everything in it on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

void write_text(const std::filesystem::path& path, const std::string& text);

// An axis-aligned cube of edge `edge` centred at `centre`, in several file formats.
void write_cube_stl_ascii(const std::filesystem::path& path, double edge, const Vec3& centre);
void write_cube_stl_binary(const std::filesystem::path& path, double edge, const Vec3& centre);
// With an .mtl next to it giving the diffuse colour (r, g, b in [0, 1]).
void write_cube_obj(const std::filesystem::path& path, double edge, const Vec3& centre, const cv::Vec3d& rgb);
// Z_UP Collada whose coordinates are in units of `unit_m` metres, with a diffuse colour.
void write_cube_dae(const std::filesystem::path& path, double edge_m, const Vec3& centre_m, double unit_m,
                    const cv::Vec3d& rgb);

}  // namespace omniview::robot::test
