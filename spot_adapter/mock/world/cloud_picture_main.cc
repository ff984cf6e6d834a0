// Draws the coloured cloud of spot-mock's robot for the README: the mock's room, its five
// body cameras and its lidar (mock_scene.h), the cloud coloured by core/cloud with
// occlusion, then the points splatted (z-buffered) into a virtual camera above and behind
// the robot. Uncoloured points are drawn dark blue. Usage: spot_mock_cloud_picture OUT.jpg
#include <iostream>
#include <limits>

#include "core/cloud/colourer.h"
#include "core/io/image_codec.h"
#include "core/synthetic/lidar_scan.h"
#include "core/synthetic/render.h"
#include "spot_adapter/mock/world/mock_scene.h"

using namespace omniview;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: spot_mock_cloud_picture OUT.jpg\n";
    return 2;
  }
  const auto scene = spot_mock::make_scene(spot_mock::SceneKind::kRoom);
  auto rig = std::make_shared<Rig>(spot_mock::mock_rig());
  rig->add_frame(spot_mock::kLidarFrame, spot_mock::kBodyFrame, spot_mock::T_body_lidar());
  CameraImages images;
  for (size_t i = 0; i < rig->cameras().size(); ++i) {
    images.images.push_back(synthetic::render_camera(scene, *rig, i, spot_mock::kWorldFrame));
  }
  const Pose T_world_lidar = rig->frames().lookup(spot_mock::kWorldFrame, spot_mock::kLidarFrame);
  synthetic::LidarScanOptions dense;
  dense.columns = 3600;
  PointCloud cloud = synthetic::scan_vlp16(scene, T_world_lidar, spot_mock::kLidarFrame, {}, dense);
  CloudColourer colourer(rig);
  const auto stats = colourer.colour(cloud, images, ColourOptions{});

  // A virtual pinhole 3.5 m behind and 2.5 m above the robot, looking at it.
  const int W = 960, H = 600;
  const double f = 520;
  const Vec3 eye(-3.2, -1.4, 2.6), target(0.8, 0, 0.3);
  const Vec3 z = (target - eye).normalized(), x = z.cross(Vec3::UnitZ()).normalized(), y = z.cross(x);
  cv::Mat picture(H, W, CV_8UC3, cv::Scalar(40, 40, 40));
  cv::Mat depth(H, W, CV_32F, cv::Scalar(std::numeric_limits<float>::max()));
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Vec3 p = T_world_lidar * cloud.points[i].cast<double>() - eye;
    const double zc = p.dot(z);
    if (zc < 0.1) continue;
    const int u = static_cast<int>(f * p.dot(x) / zc + W / 2.0), v = static_cast<int>(f * p.dot(y) / zc + H / 2.0);
    const bool coloured = cloud.flags[i] & cloud_flags::kColoured;
    const cv::Vec3b bgr = coloured ? cv::Vec3b(cloud.rgb[i][2], cloud.rgb[i][1], cloud.rgb[i][0]) : cv::Vec3b(90, 30, 20);
    const int r = zc < 4 ? 2 : 1;  // nearer points a little larger
    for (int dv = -r; dv <= r; ++dv) {
      for (int du = -r; du <= r; ++du) {
        const int uu = u + du, vv = v + dv;
        if (uu < 0 || vv < 0 || uu >= W || vv >= H || depth.at<float>(vv, uu) <= zc) continue;
        depth.at<float>(vv, uu) = static_cast<float>(zc);
        picture.at<cv::Vec3b>(vv, uu) = bgr;
      }
    }
  }
  try {
    write_image(argv[1], picture, 88);
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }
  std::cout << argv[1] << ": " << stats.points << " points, " << stats.coloured << " coloured, " << stats.occluded
            << " occluded, " << stats.unseen << " unseen\n";
  return 0;
}
