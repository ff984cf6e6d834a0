#include "robot_test_support.h"

#include <fstream>
#include <random>
#include <sstream>

#include <opencv2/imgproc.hpp>

#include "core/robot/model/primitives.h"

namespace omniview::robot::test {
namespace fs = std::filesystem;

fs::path spot_urdf() { return fs::path(OMNIVIEW_SOURCE_DIR) / "config/robots/spot/spot_like.urdf"; }

cv::Mat alpha_mask(const cv::Mat& bgra) {
  cv::Mat alpha;
  cv::extractChannel(bgra, alpha, 3);
  return alpha > 0;
}

ViewSpec birdseye_view(int width, int height, double hfov_deg, double x, double y, double height_m, double yaw_deg,
                       double pitch_deg) {
  ViewSpec s = default_view_spec(ViewType::kBirdseye);
  s.width = width;
  s.height = height;
  s.hfov_deg = hfov_deg;
  s.position = Vec3(x, y, 0);
  s.ground_z = 0;
  s.height_m = height_m;
  s.yaw_deg = yaw_deg;
  s.pitch_deg = pitch_deg;
  return s;
}

std::vector<cv::Point2f> project(const PinholeCamera& camera, const Pose& T_robot_camera, const std::vector<Vec3>& points) {
  std::vector<cv::Point2f> out;
  const Pose T_camera_robot = T_robot_camera.inverse();
  for (const auto& p : points) {
    const Vec2 uv = camera.project(T_camera_robot * p);
    out.emplace_back(float(uv.x()), float(uv.y()));
  }
  return out;
}

std::vector<Vec3> link_vertices(const RobotModel& model, const std::string& link, const std::vector<double>& positions) {
  const int index = model.link_index(link);
  const Pose T = model.link_poses(positions).at(index);
  std::vector<Vec3> out;
  for (const auto& v : model.visuals()) {
    if (v.link != index) continue;
    for (const auto& p : v.mesh.positions) out.push_back(T * p.cast<double>());
  }
  return out;
}

void hull_mask(const std::vector<cv::Point2f>& pixels, cv::Size size, cv::Mat& mask, cv::Mat& distance) {
  std::vector<cv::Point2f> hull;
  cv::convexHull(pixels, hull);
  mask = cv::Mat::zeros(size, CV_8UC1);
  distance.create(size, CV_64FC1);
  for (int v = 0; v < size.height; ++v) {
    for (int u = 0; u < size.width; ++u) {
      const double d = cv::pointPolygonTest(hull, cv::Point2f(float(u), float(v)), true);
      distance.at<double>(v, u) = d;
      if (d > 0) mask.at<uint8_t>(v, u) = 255;
    }
  }
}

int hull_disagreements(const cv::Mat& mask, const std::vector<cv::Point2f>& pixels, double band_px) {
  cv::Mat expected, distance;
  hull_mask(pixels, mask.size(), expected, distance);
  int bad = 0;
  for (int v = 0; v < mask.rows; ++v) {
    for (int u = 0; u < mask.cols; ++u) {
      if ((mask.at<uint8_t>(v, u) != 0) != (expected.at<uint8_t>(v, u) != 0) && std::abs(distance.at<double>(v, u)) > band_px) ++bad;
    }
  }
  return bad;
}

TempDir::TempDir() {
  std::random_device rd;
  path_ = fs::temp_directory_path() / ("omniview_robot_test_" + std::to_string(rd()) + std::to_string(rd()));
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

void write_text(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

namespace {

TriangleMesh cube(double edge, const Vec3& centre) {
  TriangleMesh m = make_box(Eigen::Vector3f::Constant(float(edge)));
  for (auto& p : m.positions) p += centre.cast<float>();
  return m;
}

}  // namespace

void write_cube_stl_ascii(const fs::path& path, double edge, const Vec3& centre) {
  const TriangleMesh m = cube(edge, centre);
  std::ostringstream s;
  s << "solid cube\n";
  for (size_t i = 0; i < m.positions.size(); i += 3) {
    const auto& n = m.normals[i];
    s << "  facet normal " << n.x() << ' ' << n.y() << ' ' << n.z() << "\n    outer loop\n";
    for (size_t k = 0; k < 3; ++k) {
      const auto& p = m.positions[i + k];
      s << "      vertex " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    }
    s << "    endloop\n  endfacet\n";
  }
  s << "endsolid cube\n";
  write_text(path, s.str());
}

void write_cube_stl_binary(const fs::path& path, double edge, const Vec3& centre) {
  const TriangleMesh m = cube(edge, centre);
  std::string bytes(80, '\0');  // header: must not start with "solid"
  const auto put = [&](const void* data, size_t n) { bytes.append(static_cast<const char*>(data), n); };
  const uint32_t count = static_cast<uint32_t>(m.triangle_count());
  put(&count, 4);
  for (size_t i = 0; i < m.positions.size(); i += 3) {
    put(m.normals[i].data(), 12);
    for (size_t k = 0; k < 3; ++k) put(m.positions[i + k].data(), 12);
    const uint16_t attributes = 0;
    put(&attributes, 2);
  }
  write_text(path, bytes);
}

void write_cube_obj(const fs::path& path, double edge, const Vec3& centre, const cv::Vec3d& rgb) {
  const TriangleMesh m = cube(edge, centre);
  const std::string mtl = path.stem().string() + ".mtl";
  std::ostringstream s;
  s << "mtllib " << mtl << "\nusemtl paint\n";
  for (const auto& p : m.positions) s << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (size_t i = 1; i <= m.positions.size(); i += 3) s << "f " << i << ' ' << i + 1 << ' ' << i + 2 << '\n';
  write_text(path, s.str());
  std::ostringstream material;
  material << "newmtl paint\nKd " << rgb[0] << ' ' << rgb[1] << ' ' << rgb[2] << "\n";
  write_text(path.parent_path() / mtl, material.str());
}

void write_cube_dae(const fs::path& path, double edge_m, const Vec3& centre_m, double unit_m, const cv::Vec3d& rgb) {
  const TriangleMesh m = cube(edge_m / unit_m, centre_m / unit_m);
  std::ostringstream positions, indices;
  for (const auto& p : m.positions) positions << p.x() << ' ' << p.y() << ' ' << p.z() << ' ';
  for (size_t i = 0; i < m.positions.size(); ++i) indices << i << ' ';
  std::ostringstream s;
  s << R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="unit" meter=")" << unit_m << R"("/><up_axis>Z_UP</up_axis></asset>
  <library_effects><effect id="paint-fx"><profile_COMMON><technique sid="common"><lambert>
    <diffuse><color>)" << rgb[0] << ' ' << rgb[1] << ' ' << rgb[2] << R"( 1</color></diffuse>
  </lambert></technique></profile_COMMON></effect></library_effects>
  <library_materials><material id="paint" name="paint"><instance_effect url="#paint-fx"/></material></library_materials>
  <library_geometries><geometry id="cube" name="cube"><mesh>
    <source id="cube-pos">
      <float_array id="cube-pos-array" count=")" << 3 * m.positions.size() << "\">" << positions.str() << R"(</float_array>
      <technique_common><accessor source="#cube-pos-array" count=")" << m.positions.size() << R"(" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common>
    </source>
    <vertices id="cube-vtx"><input semantic="POSITION" source="#cube-pos"/></vertices>
    <triangles material="paint-sym" count=")" << m.triangle_count() << R"(">
      <input semantic="VERTEX" source="#cube-vtx" offset="0"/><p>)" << indices.str() << R"(</p>
    </triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene"><node id="cube-node">
    <instance_geometry url="#cube"><bind_material><technique_common>
      <instance_material symbol="paint-sym" target="#paint"/>
    </technique_common></bind_material></instance_geometry>
  </node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
  write_text(path, s.str());
}

}  // namespace omniview::robot::test
