// Mesh visuals from STL (ASCII and binary), OBJ and DAE files written by the test, found
// through package:// and relative URIs; clear errors for missing meshes and bad URDFs.
#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "core/robot/model/urdf_loader.h"
#include "core/robot/render/offscreen_renderer.h"
#include "robot_test_support.h"

namespace omniview::robot {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

// Four 0.2 m cubes in a row along x; URDF in PKG/urdf, meshes in PKG/meshes.
std::string cubes_urdf() {
  const auto link = [](const std::string& name, double x, const std::string& uri, const std::string& extra) {
    return "<link name='" + name + "'><visual><geometry><mesh filename='" + uri + "' " + extra +
           "/></geometry></visual></link>\n<joint name='to_" + name + "' type='fixed'><parent link='base'/><child link='" +
           name + "'/><origin xyz='" + std::to_string(x) + " 0 0'/></joint>\n";
  };
  return "<robot name='cubes'><link name='base'/>\n" +
         link("stl_ascii", -0.6, "package://cubes/meshes/ascii.stl", "") +
         link("stl_binary", -0.2, "package://other_name/meshes/binary.stl", "scale='0.5 0.5 0.5'") +
         link("obj", 0.2, "../meshes/red.obj", "") +
         link("dae", 0.6, "package://cubes/meshes/green.dae", "") + "</robot>";
}

class MeshFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    const fs::path meshes = dir_.path() / "cubes/meshes";
    test::write_cube_stl_ascii(meshes / "ascii.stl", 0.2, Vec3::Zero());
    test::write_cube_stl_binary(meshes / "binary.stl", 0.4, Vec3::Zero());  // scaled by 0.5 in the URDF
    test::write_cube_obj(meshes / "red.obj", 0.2, Vec3::Zero(), {1, 0, 0});
    // 0.2 m in centimetres, Z_UP: must come out as a 0.2 m cube at the link's origin.
    test::write_cube_dae(meshes / "green.dae", 0.2, Vec3::Zero(), 0.01, {0, 1, 0});
    test::write_text(dir_.path() / "cubes/urdf/cubes.urdf", cubes_urdf());
  }
  TempDir dir_;
};

TEST_F(MeshFiles, LoadThroughPackageAndRelativeUrisAndRenderInPlace) {
  // package://cubes/... -> FOLDER/cubes/...; package://other_name/meshes/... -> FOLDER/cubes/meshes/...
  const MeshSearchPath search({dir_.path() / "nowhere", dir_.path(), dir_.path() / "cubes"});
  const RobotModel model = load_urdf_file(dir_.path() / "cubes/urdf/cubes.urdf", search);
  ASSERT_EQ(model.visuals().size(), 4u);

  ViewSpec spec = test::birdseye_view(160, 120, 60, 0, 0, 2.0, 0, 90);
  const PinholeCamera camera = pinhole_camera_of(spec);
  const Pose T_robot_camera = T_frame_optical(spec);
  const auto poses = model.link_poses(model.zero_positions());
  std::vector<DrawItem> items;
  for (const auto& v : model.visuals()) items.push_back({&v.mesh, poses[v.link]});
  OffscreenRenderer renderer;
  const cv::Mat image = renderer.render(items, camera, T_robot_camera);
  const cv::Mat mask = test::alpha_mask(image);

  // Each cube's silhouette from above is the hull of its eight projected corners.
  cv::Mat expected = cv::Mat::zeros(mask.size(), CV_8UC1);
  for (const auto& v : model.visuals()) {
    const char* name = model.links()[v.link].name.c_str();
    std::vector<Vec3> corners;
    for (int i = 0; i < 8; ++i) corners.push_back(poses[v.link] * Vec3(i & 1 ? 0.1 : -0.1, i & 2 ? 0.1 : -0.1, i & 4 ? 0.1 : -0.1));
    const auto px = test::project(camera, T_robot_camera, corners);
    cv::Mat hull, distance;
    test::hull_mask(px, mask.size(), hull, distance);
    expected |= hull;
    cv::Mat inside = mask & hull;
    EXPECT_GE(cv::countNonZero(inside), cv::countNonZero(hull) - 2 * int(std::sqrt(cv::countNonZero(hull)))) << name;
  }
  cv::dilate(expected, expected, cv::Mat());
  EXPECT_EQ(cv::countNonZero(mask & ~expected), 0) << "robot pixels where no cube is";

  // Colours: the OBJ's material is red, the DAE's green, the STLs have none (grey).
  const auto colour_at = [&](double x) {
    const auto px = test::project(camera, T_robot_camera, {Vec3(x, 0, 0.1)})[0];
    return image.at<cv::Vec4b>(int(std::lround(px.y)), int(std::lround(px.x)));
  };
  const cv::Vec4b red = colour_at(0.2), green = colour_at(0.6), grey = colour_at(-0.6);
  EXPECT_GT(red[2], 150);
  EXPECT_LT(red[1], 30);
  EXPECT_GT(green[1], 150);
  EXPECT_LT(green[2], 30);
  EXPECT_NEAR(grey[0], grey[2], 2);
  EXPECT_GT(grey[0], 80);
}

TEST_F(MeshFiles, UrdfColourWinsOverTheMeshFile) {
  test::write_text(dir_.path() / "blue.urdf",
                   "<robot name='b'><link name='base'><visual><geometry><mesh filename='package://cubes/meshes/red.obj'/>"
                   "</geometry><material name='blue'><color rgba='0 0 1 1'/></material></visual></link></robot>");
  const RobotModel model = load_urdf_file(dir_.path() / "blue.urdf", MeshSearchPath({dir_.path()}));
  ASSERT_EQ(model.visuals().size(), 1u);
  for (const auto& c : model.visuals()[0].mesh.colours) ASSERT_EQ(c, (Rgba8{0, 0, 255, 255}));
}

TEST_F(MeshFiles, MissingMeshNamesTheUriAndTheSearchPath) {
  test::write_text(dir_.path() / "missing.urdf",
                   "<robot name='m'><link name='base'><visual><geometry><mesh filename='package://cubes/meshes/gone.stl'/>"
                   "</geometry></visual></link></robot>");
  const fs::path a = dir_.path() / "first", b = dir_.path() / "second";
  try {
    load_urdf_file(dir_.path() / "missing.urdf", MeshSearchPath({a, b}));
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("package://cubes/meshes/gone.stl"), std::string::npos) << what;
    EXPECT_NE(what.find(a.string()), std::string::npos) << what;
    EXPECT_NE(what.find(b.string()), std::string::npos) << what;
    EXPECT_NE(what.find("base"), std::string::npos) << "names the link: " << what;
  }
}

TEST_F(MeshFiles, MalformedUrdfNamesTheFile) {
  const fs::path broken = dir_.path() / "broken.urdf";
  test::write_text(broken, "<robot name='x'><link name='a'><visual>");
  try {
    load_urdf_file(broken);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(broken.string()), std::string::npos) << e.what();
  }
  // urdfdom's own reason comes along.
  const fs::path orphan = dir_.path() / "orphan.urdf";
  test::write_text(orphan, "<robot name='x'><link name='a'/><joint name='j' type='fixed'><parent link='a'/>"
                           "<child link='nobody'/></joint></robot>");
  try {
    load_urdf_file(orphan);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(orphan.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("nobody"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_urdf_file(dir_.path() / "does_not_exist.urdf"), std::runtime_error);
  // A URI scheme we do not read.
  test::write_text(dir_.path() / "web.urdf", "<robot name='w'><link name='base'><visual><geometry>"
                                             "<mesh filename='http://example.com/base.stl'/></geometry></visual></link></robot>");
  try {
    load_urdf_file(dir_.path() / "web.urdf");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("only package://, file:// and file paths"), std::string::npos) << e.what();
  }
  // A mesh file that is not a mesh.
  test::write_text(dir_.path() / "cubes/meshes/junk.stl", "this is not a mesh");
  test::write_text(dir_.path() / "junk.urdf", "<robot name='j'><link name='base'><visual><geometry>"
                                              "<mesh filename='cubes/meshes/junk.stl'/></geometry></visual></link></robot>");
  try {
    load_urdf_file(dir_.path() / "junk.urdf");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("junk.stl"), std::string::npos) << e.what();
  }
}

// urdfdom reads "1e300" as a number: anything no robot can have is refused where it is
// written; and what urdfdom itself cannot read (it would drop the element) is an error too.
TEST_F(MeshFiles, NumbersARobotCannotHaveAreRefusedWhereTheyAreWritten) {
  const struct {
    std::string body, expected;
  } cases[] = {
      {"<link name='a'><visual><origin xyz='1e300 0 0'/><geometry><box size='1 1 1'/></geometry></visual></link>",
       "link 'a' visual origin"},
      {"<link name='a'><visual><geometry><box size='1 -1 1'/></geometry></visual></link>", "box size"},
      {"<link name='a'><visual><geometry><box size='0.87 0.25'/></geometry></visual></link>", "2 elements but 3 expected"},
      {"<link name='a'><visual><geometry><cylinder radius='0.1'/></geometry></visual></link>", "both length and radius"},
      {"<link name='a'><visual><geometry><sphere radius='1e300'/></geometry></visual></link>", "sphere radius"},
      {"<link name='a'/><link name='b'/><joint name='j' type='revolute'><parent link='a'/><child link='b'/>"
       "<origin xyz='0 0 1e300'/><axis xyz='0 0 1'/><limit lower='0' upper='1' effort='1' velocity='1'/></joint>",
       "joint 'j' origin"},
      {"<link name='a'/><link name='b'/><joint name='j' type='continuous'><parent link='a'/><child link='b'/>"
       "<axis xyz='1e300 0 1'/></joint>",
       "joint 'j' axis"},
  };
  for (const auto& c : cases) {
    try {
      load_urdf_string("<robot name='x'>" + c.body + "</robot>", dir_.path(), {}, "bad.urdf");
      ADD_FAILURE() << "no error for " << c.body;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.urdf"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace omniview::robot
