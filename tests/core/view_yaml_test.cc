// View YAML: errors point at the key that is wrong (file:line: key:), for type-level
// checks and for the range checks of validate(), and view names are unique in a file.
#include <gtest/gtest.h>

#include "core/io/yaml_reader.h"
#include "core/view/view_yaml.h"
#include "test_support.h"

namespace omniview {
namespace {

using testing::expect_throw_containing;

void expect_error(const std::string& name, const std::string& text, std::initializer_list<std::string> needles) {
  expect_throw_containing<ConfigError>([&] { parse_views(YamlReader::from_string(text, name)); }, needles, name);
}

TEST(ViewYaml, RangeErrorsNameTheLineOfTheKey) {
  expect_error("fov.yaml", "name: v\ntype: fisheye\nwidth: 64\nfov_deg: 0\nheight: 32\n",
               {"fov.yaml:4: fov_deg: view 'v': fov_deg must be in [0.01, 360], got 0"});
  expect_error("hfov.yaml", "type: perspective\nhfov_deg: 180\n", {"hfov.yaml:2: hfov_deg:"});
  expect_error("width.yaml", "type: perspective\nheight: 8\nwidth: 0\n", {"width.yaml:3: width:", "between 1"});
  // A bird's-eye view's height_m, though validate() calls it "height".
  expect_error("birdseye.yaml", "type: birdseye\nheight: 100\nheight_m: -1\n", {"birdseye.yaml:3: height_m:"});
  expect_error("pixels.yaml", "type: birdseye\nheight: 0\nheight_m: 3\n", {"pixels.yaml:2: height:"});
  // A pair names the first of its keys that is given.
  expect_error("lat.yaml", "type: mercator\nlat_max_deg: 90\n", {"lat.yaml:2: lat_max_deg:"});
  expect_error("feather.yaml", "type: perspective\nfusion: blend\nfeather_px: 0\n", {"feather.yaml:3: feather_px:"});
  expect_error("list.yaml", "views:\n  - {name: a, type: perspective}\n  - name: b\n    type: cylindrical\n"
               "    vfov_deg: 200\n",
               {"list.yaml:5: views[1].vfov_deg: view 'b': vfov_deg"});
}

TEST(ViewYaml, KeysOfAnotherViewTypeAreErrors) {
  expect_error("fov.yaml", "name: pano\ntype: equirectangular\nfov_deg: 120\n",
               {"fov.yaml:3: fov_deg: fov_deg does not apply to equirectangular views",
                "their keys: radius, azimuth_span_deg, lat_min_deg, lat_max_deg"});
  expect_error("hfov.yaml", "type: fisheye\nhfov_deg: 90\n", {"hfov.yaml:2: hfov_deg:", "fisheye views"});
  expect_error("list.yaml", "views:\n  - {name: a, type: perspective, radius: 3}\n",
               {"list.yaml:2: views[0].radius: radius does not apply to perspective views"});
}

TEST(ViewYaml, NamesAreOneWordAndTiltStaysWithinStraightDownAndUp) {
  expect_error("name.yaml", "name: my view\ntype: perspective\n", {"name.yaml:", "no spaces"});
  expect_error("tilt.yaml", "type: perspective\npose: {ypr_deg: [0, 100, 0]}\n", {"tilt.yaml:", "[-90, 90]"});
}

TEST(ViewYaml, RepeatedNamesNameBothViews) {
  expect_error("dup.yaml",
               "views:\n  - {name: a, type: perspective}\n  - {name: b, type: perspective}\n"
               "  - {name: a, type: fisheye}\n",
               {"dup.yaml:4: views[2].name: view name 'a' is already used by views[0] on line 2"});
  expect_error("unnamed.yaml", "views:\n  - {type: perspective}\n  - {type: fisheye}\n",
               {"unnamed.yaml:3: views[1].name: view name 'view' is already used by views[0] on line 2",
                "a view without 'name' is called 'view'"});
}

TEST(ViewYaml, GainCompensationIsOnByDefaultAndCanBeTurnedOff) {
  const auto on = parse_views(YamlReader::from_string("type: perspective\n", "on.yaml"));
  ASSERT_EQ(on.size(), 1u);
  EXPECT_TRUE(on[0].gain_compensation);
  const auto off = parse_views(YamlReader::from_string("type: perspective\ngain_compensation: false\n", "off.yaml"));
  EXPECT_FALSE(off[0].gain_compensation);
  EXPECT_FALSE(view_to_yaml(off[0])["gain_compensation"].as<bool>());  // written back as read
  expect_error("gain.yaml", "type: perspective\ngain_compensation: sometimes\n", {"gain.yaml:2: gain_compensation:"});
}

TEST(ViewYaml, GroundCutsAnySurfaceButTheBirdseyesAndIsWrittenBack) {
  const auto views = parse_views(YamlReader::from_string(
      "views:\n  - {name: f, type: perspective, ground: true, ground_z: -0.5}\n"
      "  - {name: p, type: equirectangular, lat_min_deg: -40, lat_max_deg: 0, ground: true,"
      " pose: {xyz: [0, 0, 0.5]}}\n",
      "ground.yaml"));
  ASSERT_EQ(views.size(), 2u);
  EXPECT_TRUE(views[0].ground);
  EXPECT_DOUBLE_EQ(views[0].ground_z, -0.5);
  EXPECT_TRUE(views[1].ground);
  const YAML::Node written = view_to_yaml(views[0]);
  EXPECT_TRUE(written["ground"].as<bool>());
  EXPECT_DOUBLE_EQ(written["ground_z"].as<double>(), -0.5);
  EXPECT_FALSE(view_to_yaml(parse_views(YamlReader::from_string("type: perspective\n", "plain.yaml"))[0])["ground"]);
  expect_error("birdseye.yaml", "type: birdseye\nground: true\n", {"birdseye.yaml:2: ground:", "birdseye"});
  expect_error("below.yaml", "type: perspective\nground: true\nground_z: 2\n", {"below.yaml:", "above the ground plane"});
}

TEST(ViewYaml, DepthIsFixedByDefaultMeasuredOnRequestAndWrittenBackOnlyWhenMeasured) {
  const auto views = parse_views(YamlReader::from_string(
      "views:\n  - {name: f, type: perspective}\n  - {name: m, type: birdseye, depth: measured}\n"
      "  - {name: x, type: fisheye, depth: fixed}\n",
      "depth.yaml"));
  ASSERT_EQ(views.size(), 3u);
  EXPECT_EQ(views[0].depth, Depth::kFixed);
  EXPECT_EQ(views[1].depth, Depth::kMeasured);
  EXPECT_EQ(views[2].depth, Depth::kFixed);
  EXPECT_FALSE(view_to_yaml(views[0])["depth"]);  // fixed views' files stay as they were
  EXPECT_EQ(view_to_yaml(views[1])["depth"].as<std::string>(), "measured");
  expect_error("depth.yaml", "type: perspective\ndepth: lidar\n",
               {"depth.yaml:2: depth:", "unknown depth 'lidar'", "fixed", "measured"});
  expect_error("list.yaml", "views:\n  - {name: a, type: perspective, depth: [measured]}\n",
               {"list.yaml:2: views[0].depth:"});
}

}  // namespace
}  // namespace omniview
