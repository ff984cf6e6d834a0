// Time sync in the daemon's cloud path (server/pipeline/cloud), driven as the pipeline
// drives it: a robot walking at 1 m/s, its lidar sweep paired with the image set taken
// nearest the sweep's middle (not the later set the cloud arrived with), and the source's
// motion (FrameSet::motion) taken out between the two.
#include <gtest/gtest.h>

#include <cstring>
#include <map>

#include "cloud_scene.h"
#include "core/map/worker_threads.h"
#include "core/synthetic/lidar_scan.h"
#include "core/synthetic/spot_like_rig.h"
#include "server/pipeline/cloud/cloud_delivery.h"

namespace omniview {
namespace {

using Clock = std::chrono::system_clock;
const Clock::time_point kStamp = Clock::time_point(std::chrono::seconds(1700000000));

struct Walk {
  synthetic::Scene scene = test::textured_room();
  Pose start = make_pose(Vec3(-0.5, 0.2, 0.55), 0.2, 0, 0);
  std::shared_ptr<Rig> rig;
  PointCloud cloud;
  std::vector<PointCloud::Rgb> truth;
  std::shared_ptr<Trajectory> odometry = std::make_shared<Trajectory>();

  Pose T_world_body(double t) const {
    Pose T = start;
    T.translation() += start.linear() * Vec3(1.0 * t, 0, 0);
    return T;
  }

  Walk() {
    rig = std::make_shared<Rig>(synthetic::spot_like_rig());
    rig->add_frame("lidar", "body", test::T_body_lidar());
    for (int k = -10; k <= 40; ++k) odometry->add(kStamp + std::chrono::milliseconds(10 * k), T_world_body(0.01 * k));
    synthetic::LidarScanOptions options;
    options.keep_colour = true;
    cloud = synthetic::scan_vlp16(
        scene, [&](double t) { return T_world_body(t) * test::T_body_lidar(); }, "lidar", kStamp, options);
    truth = cloud.rgb;
    cloud.rgb.clear();
  }

  // The image set the cameras took `t` seconds after the cloud's stamp.
  FrameSet images_at(double t) const {
    FrameSet f;
    f.capture_time = kStamp + std::chrono::microseconds(static_cast<int64_t>(t * 1e6));
    f.rig = rig;
    f.rig_version = 1;
    auto world_rig = std::make_shared<Rig>(*rig);
    world_rig->add_frame("world", "body", T_world_body(t).inverse());
    f.images = test::render_images(scene, *world_rig);
    return f;
  }
};

// Coloured points within 8 grey levels of the scene's colour, and coloured points.
std::pair<size_t, size_t> score(const v1::PointCloud& c, const std::vector<PointCloud::Rgb>& truth) {
  std::map<std::string, uint32_t> at;
  for (const auto& f : c.fields()) at[f.name()] = f.offset();
  EXPECT_EQ(c.point_count(), truth.size()) << "every point, in order (no voxel, no crop)";
  size_t right = 0, coloured = 0;
  for (size_t i = 0; i < c.point_count() && i < truth.size(); ++i) {
    const char* p = c.data().data() + i * c.point_stride();
    if (!(static_cast<uint8_t>(p[at["flags"]]) & cloud_flags::kColoured)) continue;
    ++coloured;
    const PointCloud::Rgb rgb{static_cast<uint8_t>(p[at["r"]]), static_cast<uint8_t>(p[at["g"]]),
                              static_cast<uint8_t>(p[at["b"]])};
    right += std::abs(test::luma(rgb) - test::luma(truth[i])) <= 8;
  }
  return {right, coloured};
}

// What a client streaming the cloud in the lidar's frame gets after the pipeline handed
// `earlier` (no cloud) and then `with_cloud` to the source's CloudDelivery.
std::pair<size_t, size_t> deliver(const Walk& w, const FrameSet* earlier, FrameSet with_cloud,
                                  std::shared_ptr<const Trajectory> motion) {
  CloudDelivery delivery("walker");
  CloudRequest request;
  request.frame = "lidar";
  auto client = std::make_shared<CloudSubscriber>("test", request, 0);
  delivery.add(client);
  if (earlier) delivery.remember(*earlier);  // as Pipeline::deliver_cloud does for sets without a cloud
  with_cloud.cloud = std::make_shared<const PointCloud>(w.cloud);
  with_cloud.motion = std::move(motion);
  delivery.deliver(with_cloud, nullptr);
  const auto taken = client->take(std::chrono::milliseconds(0));
  if (!taken || !*taken) {
    ADD_FAILURE() << "no cloud offered: " << client->close_reason();
    return {0, 0};
  }
  return score(**taken, w.truth);
}

TEST(CloudTimeSync, NearestImagesAndTheSourcesMotion) {
  apply_worker_threads_from_env();  // OMNIVIEW_THREADS=1 (the TSan stage): no TBB hand-offs to miss
  const Walk w;
  // Images mid-sweep (+0.05 s), and the next set (+0.15 s) which the cloud arrives with.
  const FrameSet mid = w.images_at(0.05), next = w.images_at(0.15);

  const auto [synced_right, synced] = deliver(w, &mid, next, w.odometry);
  const auto [nearest_right, nearest] = deliver(w, &mid, next, nullptr);
  const auto [next_right, next_only] = deliver(w, nullptr, next, nullptr);
  std::cout << "walking at 1 m/s, right of coloured: nearest set + motion " << synced_right << "/" << synced
            << ", nearest set, no motion " << nearest_right << "/" << nearest << ", the next set, no motion "
            << next_right << "/" << next_only << "\n";
  EXPECT_GE(synced_right, 0.99 * synced);
  EXPECT_LT(next_right, 0.9 * next_only) << "without time sync a walking robot's colours slide";
  EXPECT_GT(double(nearest_right) / nearest, double(next_right) / next_only + 0.05)
      << "the set nearest the sweep's middle is the better one";
}

TEST(CloudTimeSync, MotionAlsoFixesTheLaterSet) {
  apply_worker_threads_from_env();
  const Walk w;
  const auto [right, coloured] = deliver(w, nullptr, w.images_at(0.15), w.odometry);
  EXPECT_GE(right, 0.99 * coloured) << right << " of " << coloured;
}

}  // namespace
}  // namespace omniview
