// The Foxglove cloud layout without a network: the packed layout's colours under the names
// Foxglove's 3D panel colours points by (red, green, blue, alpha), every other byte kept.
#include <gtest/gtest.h>

#include <map>

#include "server/pipeline/cloud/cloud_message.h"
#include "server/web/foxglove/foxglove_messages.h"

namespace omniview::web::foxglove_io {
namespace {

TEST(FoxgloveCloud, ColourFieldsByFoxglovesNamesAndAnOpaqueAlpha) {
  PointCloud cloud;
  cloud.frame = "body";
  cloud.points = {{1, 2, 3}, {4, 5, 6}};
  cloud.rgb = {{10, 20, 30}, {40, 50, 60}};
  cloud.flags = {1, 0};
  cloud.camera = {2, 255};
  const v1::PointCloud packed = pack_cloud(cloud);

  foxglove::PointCloud prefix;
  ASSERT_TRUE(prefix.ParseFromString(point_cloud_prefix(packed)));
  EXPECT_EQ(prefix.frame_id(), "body");
  EXPECT_EQ(prefix.point_stride(), packed.point_stride() + 1);
  std::map<std::string, std::pair<uint32_t, int>> fields;
  for (const auto& f : prefix.fields()) fields[f.name()] = {f.offset(), f.type()};
  using F = foxglove::PackedElementField;
  const std::map<std::string, std::pair<uint32_t, int>> want = {
      {"x", {0, F::FLOAT32}},    {"y", {4, F::FLOAT32}},      {"z", {8, F::FLOAT32}},
      {"red", {12, F::UINT8}},   {"green", {13, F::UINT8}},   {"blue", {14, F::UINT8}},
      {"flags", {15, F::UINT8}}, {"camera", {16, F::UINT8}},  {"alpha", {17, F::UINT8}}};
  EXPECT_EQ(fields, want);

  const std::string points = foxglove_points(packed);
  ASSERT_EQ(points.size(), 2u * 18);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(points.substr(i * 18, 17), packed.data().substr(i * 17, 17)) << "point " << i;
    EXPECT_EQ(static_cast<uint8_t>(points[i * 18 + 17]), 255) << "point " << i;
  }
}

TEST(FoxgloveFrames, ViewFramesUnderTheViewPrefix) {
  // Apart from the robot's frames; view names hold no '/', so no view's frames collide with another's.
  EXPECT_EQ(view_frame("back"), "view/back");
  EXPECT_EQ(view_optical_frame("back"), "view/back/optical");
}

}  // namespace
}  // namespace omniview::web::foxglove_io
