// A coloured cloud made into one client's message (server/pipeline/cloud/cloud_message.h):
// frame change, crop, voxel means, and the packed layout read back by its field list.
#include <gtest/gtest.h>

#include <cstring>

#include "server/pipeline/cloud/cloud_message.h"

namespace omniview {
namespace {

PointCloud coloured_cloud() {
  PointCloud c;
  c.frame = "lidar";
  c.stamp = std::chrono::system_clock::time_point(std::chrono::seconds(1700000000));
  const auto add = [&](float x, float y, float z, PointCloud::Rgb rgb, uint8_t flags, uint8_t camera) {
    c.points.emplace_back(x, y, z);
    c.rgb.push_back(rgb);
    c.flags.push_back(flags);
    c.camera.push_back(camera);
  };
  add(1.01f, 0.01f, 0.01f, {100, 0, 0}, cloud_flags::kColoured, 0);  // voxel (1, 0, 0)
  add(1.09f, 0.09f, 0.09f, {200, 50, 0}, cloud_flags::kColoured, 1);
  add(1.05f, 0.05f, 0.05f, {0, 0, 0}, 0, kNoCamera);                  // unseen, same voxel
  add(3.05f, 0.05f, 0.05f, {0, 0, 0}, cloud_flags::kOccluded, kNoCamera);
  add(5.05f, 0.05f, 0.05f, {0, 0, 0}, cloud_flags::kSelf, kNoCamera);
  add(NAN, 0, 0, {0, 0, 0}, 0, kNoCamera);  // no return: never sent
  return c;
}

TEST(CloudMessage, MovesCropsAndKeepsEveryFinitePoint) {
  CloudShape shape;
  shape.frame = "body";
  shape.T_out_cloud = Pose::Identity();
  shape.T_out_cloud.translation() = Vec3(0, 0, 1);
  PointCloud out = shape_cloud(coloured_cloud(), shape);
  EXPECT_EQ(out.frame, "body");
  ASSERT_EQ(out.size(), 5u);
  EXPECT_NEAR(out.points[0].z(), 1.01f, 1e-6);
  shape.crop = Eigen::AlignedBox3d(Vec3(0, -1, 0), Vec3(2, 1, 2));
  out = shape_cloud(coloured_cloud(), shape);
  EXPECT_EQ(out.size(), 3u);
}

TEST(CloudMessage, VoxelsAverageTheirPointsAndColouredColours) {
  CloudShape shape;
  shape.frame = "lidar";
  shape.voxel_m = 0.1;
  const PointCloud out = shape_cloud(coloured_cloud(), shape);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_NEAR(out.points[0].x(), (1.01f + 1.09f + 1.05f) / 3, 1e-5);
  EXPECT_EQ(out.rgb[0], (PointCloud::Rgb{150, 25, 0}));  // the uncoloured point adds no black
  EXPECT_EQ(out.flags[0], cloud_flags::kColoured);
  EXPECT_EQ(out.camera[0], 0);
  EXPECT_EQ(out.flags[1], cloud_flags::kOccluded);
  EXPECT_EQ(out.flags[2], cloud_flags::kSelf);
}

TEST(CloudMessage, PackedLayoutIsDescribedByItsFields) {
  CloudShape shape;
  shape.frame = "lidar";
  const v1::PointCloud m = pack_cloud(shape_cloud(coloured_cloud(), shape));
  EXPECT_EQ(m.frame(), "lidar");
  EXPECT_EQ(m.stamp().seconds(), 1700000000);
  ASSERT_EQ(m.point_count(), 5u);
  ASSERT_EQ(m.data().size(), m.point_count() * m.point_stride());
  std::map<std::string, v1::PointField> fields;
  for (const auto& f : m.fields()) fields[f.name()] = f;
  ASSERT_EQ(fields.size(), 8u);
  for (const auto& [name, f] : fields) EXPECT_LE(f.offset() + (f.datatype() == v1::PointField::FLOAT32 ? 4 : 1), m.point_stride()) << name;
  const char* second = m.data().data() + m.point_stride();
  float y;
  std::memcpy(&y, second + fields["y"].offset(), 4);
  EXPECT_FLOAT_EQ(y, 0.09f);
  EXPECT_EQ(static_cast<uint8_t>(second[fields["r"].offset()]), 200);
  EXPECT_EQ(static_cast<uint8_t>(second[fields["g"].offset()]), 50);
  EXPECT_EQ(static_cast<uint8_t>(second[fields["camera"].offset()]), 1);
  EXPECT_EQ(m.counts().points(), 5u);
  EXPECT_EQ(m.counts().coloured(), 2u);
  EXPECT_EQ(m.counts().unseen(), 1u);
  EXPECT_EQ(m.counts().occluded(), 1u);
  EXPECT_EQ(m.counts().self_filtered(), 1u);
}

}  // namespace
}  // namespace omniview
