// View definitions from --set flags and view YAML files into the API's ViewSpec, and zoom.
#include "cli/client/view_spec_proto.h"

#include <gtest/gtest.h>

#include "cli/args.h"

namespace omniview::cli {
namespace {

TEST(Zoom, OneIsNinetyDegrees) {
  EXPECT_NEAR(hfov_from_zoom(1), 90, 1e-12);
  EXPECT_NEAR(hfov_from_zoom(2), 2 * std::atan(0.5) * 180 / M_PI, 1e-12);  // 53.13 deg
  EXPECT_NEAR(zoom_from_hfov(90), 1, 1e-12);
  for (double zoom : {0.25, 0.5, 1.0, 1.7, 4.0, 30.0}) EXPECT_NEAR(zoom_from_hfov(hfov_from_zoom(zoom)), zoom, 1e-9);
  EXPECT_GT(hfov_from_zoom(0.5), 90);  // zooming out widens
}

TEST(SetFlags, ScalarsEnumsAndAliases) {
  v1::ViewSpec spec;
  for (const char* s : {"name=front", "type=birdseye", "width=640", "height= 480", "pan=12.5", "tilt=-3", "hfov=70",
                        "fusion=blend", "feather_px=10", "source=robot", "frame=base_link", "gain_compensation=off"}) {
    apply_setting(s, spec);
  }
  EXPECT_EQ(spec.name(), "front");
  EXPECT_EQ(spec.type(), v1::BIRDSEYE);
  EXPECT_EQ(spec.width(), 640);
  EXPECT_EQ(spec.height(), 480);
  EXPECT_DOUBLE_EQ(spec.yaw_deg(), 12.5);
  EXPECT_DOUBLE_EQ(spec.pitch_deg(), -3);
  EXPECT_DOUBLE_EQ(spec.hfov_deg(), 70);
  EXPECT_EQ(spec.fusion(), v1::BLEND);
  EXPECT_DOUBLE_EQ(spec.feather_px(), 10);
  EXPECT_TRUE(spec.has_gain_compensation());
  EXPECT_FALSE(spec.gain_compensation());
  EXPECT_EQ(spec.source(), "robot");
  EXPECT_EQ(spec.frame(), "base_link");
  // Only what was set is set.
  EXPECT_FALSE(spec.has_roll_deg());
  EXPECT_FALSE(spec.has_radius());
  EXPECT_FALSE(spec.has_position());
}

TEST(SetFlags, Vectors) {
  v1::ViewSpec spec;
  apply_setting("position=1,2.5,-3", spec);
  apply_setting("ypr_deg=10,20,30", spec);
  EXPECT_DOUBLE_EQ(spec.position().y(), 2.5);
  EXPECT_DOUBLE_EQ(spec.position().z(), -3);
  EXPECT_DOUBLE_EQ(spec.yaw_deg(), 10);
  EXPECT_DOUBLE_EQ(spec.roll_deg(), 30);
  apply_setting("pose.xyz=0,0,1", spec);
  EXPECT_DOUBLE_EQ(spec.position().z(), 1);
}

TEST(SetFlags, ErrorsNameTheKey) {
  v1::ViewSpec spec;
  const auto error = [&](const std::string& s) {
    try {
      apply_setting(s, spec);
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("hfov_deg").find("KEY=VALUE"), std::string::npos);
  EXPECT_NE(error("=3").find("KEY=VALUE"), std::string::npos);
  EXPECT_NE(error("hfvo=3").find("unknown key 'hfvo'"), std::string::npos);
  EXPECT_NE(error("position=1,2").find("3 comma-separated"), std::string::npos);
  EXPECT_NE(error("width=12.5").find("integer"), std::string::npos);
  EXPECT_NE(error("width=99999999999").find("integer"), std::string::npos);
  EXPECT_NE(error("hfov_deg=wide").find("--set hfov_deg: expected a number"), std::string::npos);
  EXPECT_NE(error("type=globe").find("globe"), std::string::npos);
  EXPECT_NE(error("fusion=average").find("average"), std::string::npos);
  EXPECT_NE(error("position=x").find("position"), std::string::npos);
}

TEST(ViewYaml, OnlyTheGivenKeysAreSet) {
  const auto reader = YamlReader::from_string(
      "name: front\ntype: perspective\nwidth: 800\nhfov_deg: 75\npose: {ypr_deg: [10, 5, 0]}\nfusion: blend\n",
      "front.yaml");
  const auto specs = views_from_yaml(reader);
  ASSERT_EQ(specs.size(), 1u);
  const auto& s = specs[0];
  EXPECT_EQ(s.name(), "front");
  EXPECT_EQ(s.type(), v1::PERSPECTIVE);
  EXPECT_EQ(s.width(), 800);
  EXPECT_DOUBLE_EQ(s.hfov_deg(), 75);
  EXPECT_DOUBLE_EQ(s.yaw_deg(), 10);
  EXPECT_DOUBLE_EQ(s.pitch_deg(), 5);
  EXPECT_TRUE(s.has_roll_deg());
  EXPECT_EQ(s.fusion(), v1::BLEND);
  EXPECT_FALSE(s.has_height());
  EXPECT_FALSE(s.has_position());
  EXPECT_FALSE(s.has_source());
  EXPECT_FALSE(s.has_radius());
}

TEST(ViewYaml, SeveralViewsAndNoName) {
  const auto reader = YamlReader::from_string(
      "views:\n  - {name: a, type: fisheye, fov_deg: 200, pose: {xyz: [0, 0, 1.5]}}\n"
      "  - {name: b, type: mercator, source: rear}\n",
      "views.yaml");
  const auto specs = views_from_yaml(reader);
  ASSERT_EQ(specs.size(), 2u);
  EXPECT_EQ(specs[0].type(), v1::FISHEYE);
  EXPECT_DOUBLE_EQ(specs[0].fov_deg(), 200);
  EXPECT_DOUBLE_EQ(specs[0].position().z(), 1.5);
  EXPECT_FALSE(specs[0].has_yaw_deg());
  EXPECT_EQ(specs[1].type(), v1::MERCATOR);
  EXPECT_EQ(specs[1].source(), "rear");
  EXPECT_FALSE(specs[1].has_lat_min_deg());  // the server applies mercator's defaults

  const auto unnamed = views_from_yaml(YamlReader::from_string("type: cylindrical\n", "v.yaml"));
  EXPECT_FALSE(unnamed[0].has_name());
}

TEST(ViewYaml, ErrorsComeFromCoresParser) {
  const auto error = [](const std::string& text) {
    try {
      views_from_yaml(YamlReader::from_string(text, "bad.yaml"));
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("name: a\ntype: perspective\nhfvo_deg: 3\n").find("hfvo_deg"), std::string::npos);
  EXPECT_NE(error("name: a\n").find("type"), std::string::npos);
  EXPECT_NE(error("name: a\ntype: perspective\nwidth: -5\n").find("width"), std::string::npos);
  EXPECT_NE(error("type: perspective\nwidth: 0\n").find("bad.yaml"), std::string::npos);
}

TEST(ViewSpecConversion, RoundTripsThroughTheProto) {
  ViewSpec s = default_view_spec(ViewType::kEquirectangular);
  s.name = "pano";
  s.width = 2048;
  s.position = Vec3(1, 2, 3);
  s.lat_min_deg = -30;
  s.fusion = Fusion::kBlend;
  const ViewSpec back = spec_from_proto(to_proto(s));
  EXPECT_EQ(back.name, "pano");
  EXPECT_EQ(back.type, ViewType::kEquirectangular);
  EXPECT_EQ(back.width, 2048);
  EXPECT_DOUBLE_EQ(back.position.y(), 2);
  EXPECT_DOUBLE_EQ(back.lat_min_deg, -30);
  EXPECT_EQ(back.fusion, Fusion::kBlend);
  for (int t = 0; t < 6; ++t) EXPECT_EQ(from_proto(to_proto(static_cast<ViewType>(t)), "t"), static_cast<ViewType>(t));
  EXPECT_EQ(to_proto(ViewType::kPerspective), v1::PERSPECTIVE);
  EXPECT_EQ(to_proto(ViewType::kFisheye), v1::FISHEYE);
  EXPECT_THROW(from_proto(v1::VIEW_TYPE_UNSPECIFIED, "t"), std::invalid_argument);
  // Unset fields take the type's defaults.
  v1::ViewSpec birdseye;
  birdseye.set_type(v1::BIRDSEYE);
  EXPECT_DOUBLE_EQ(spec_from_proto(birdseye).pitch_deg, 90);
}

}  // namespace
}  // namespace omniview::cli
