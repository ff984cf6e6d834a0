#include "cli/rig_args.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "core/io/image_codec.h"
#include "core/io/yaml_reader.h"

namespace omniview::cli {

namespace fs = std::filesystem;

const char* const kRigOptionsHelp =
    "  --rig FILE          our rig YAML, or a kalibr camchain.yaml (cam0, cam1, ...)\n"
    "  --rig-frame NAME    camchain only: the robot frame cam0 is posed in (default base_link)\n"
    "  --rig-pose \"x y z yaw pitch roll\" | \"x y z qx qy qz qw\"\n"
    "                      camchain only: the pose of cam0's optical frame in --rig-frame\n"
    "                      (see 'omniview render --help')\n"
    "  --image CAM=PATH    the image of camera CAM (repeat for each camera)\n";

std::string joined(const std::vector<std::string>& words, const std::string& separator) {
  std::string out;
  for (const auto& w : words) out += (out.empty() ? "" : separator) + w;
  return out;
}

// Whitespace- or comma-separated numbers, each one whole and finite.
std::vector<double> parse_numbers(std::string text, const std::string& option) {
  std::replace(text.begin(), text.end(), ',', ' ');
  std::istringstream in(text);
  std::vector<double> numbers;
  for (std::string word; in >> word;) {
    char* end = nullptr;
    const double x = std::strtod(word.c_str(), &end);
    if (end != word.c_str() + word.size() || !std::isfinite(x)) {
      throw UsageError(option + ": '" + word + "' is not a number");
    }
    numbers.push_back(x);
  }
  return numbers;
}

// The forms of T_parent_cam in our rig YAML: xyz with ypr_deg, or with quat_xyzw.
Pose parse_rig_pose(const std::string& text) {
  const std::vector<double> v = parse_numbers(text, "--rig-pose");
  const Vec3 xyz = v.size() >= 3 ? Vec3(v[0], v[1], v[2]) : Vec3::Zero();
  if (v.size() == 6) {
    constexpr double kDeg = M_PI / 180;
    return make_pose(xyz, v[3] * kDeg, v[4] * kDeg, v[5] * kDeg);
  }
  if (v.size() == 7) {
    const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
    if (std::abs(q.norm() - 1) > 1e-3) {
      throw UsageError("--rig-pose: the quaternion qx qy qz qw must have unit length, has " + std::to_string(q.norm()));
    }
    Pose T = Pose::Identity();
    T.linear() = q.normalized().toRotationMatrix();
    T.translation() = xyz;
    return T;
  }
  throw UsageError("--rig-pose needs 6 numbers \"x y z yaw pitch roll\" (metres, degrees) or 7 numbers "
                   "\"x y z qx qy qz qw\", got " + count_of(v.size(), "number", "numbers") + ": \"" + text + "\"");
}

LoadedRig load_rig_from_args(const Args& args) {
  const std::string path = args.required("rig");
  const YamlReader reader = YamlReader::from_file(path);
  if (is_kalibr_camchain(reader)) {
    const Pose T_frame_cam0 = args.has("rig-pose") ? parse_rig_pose(args.get("rig-pose")) : Pose::Identity();
    return {parse_kalibr_camchain(reader, args.get("rig-frame", "base_link"), T_frame_cam0), true};
  }
  // Our rig YAML poses every camera itself; silently ignoring these would mislead.
  for (const std::string option : {"rig-frame", "rig-pose"}) {
    if (args.has(option)) {
      throw UsageError("--" + option + " applies only to kalibr camchains, but '" + path +
                       "' is our rig YAML, which gives the rig's 'frame' and each camera's pose itself "
                       "(T_parent_cam or mount)");
    }
  }
  return {parse_rig_yaml(reader, fs::path(path).parent_path().string()), false};
}

namespace {

// A missing file, a folder and a file that is no image each get their own message.
cv::Mat read_camera_image(const Camera& camera, const std::string& path) {
  const std::string who = "camera '" + camera.name + "': ";
  std::error_code ec;
  if (!fs::exists(path, ec)) throw std::runtime_error(who + "image file '" + path + "' does not exist");
  if (fs::is_directory(path, ec)) throw std::runtime_error(who + "'" + path + "' is a folder, not an image");
  std::string why;
  cv::Mat img = read_image(path, ImageColour::kAsStored, &why);
  if (img.empty()) throw std::runtime_error(who + "'" + path + "' is " + why);
  if (!why.empty()) std::cerr << "warning: " << who << "'" << path << "': " << why << "\n";  // damaged, used as is
  if (img.cols != camera.width || img.rows != camera.height) {
    throw std::runtime_error(who + "image '" + path + "' is " + std::to_string(img.cols) + "x" +
                             std::to_string(img.rows) + ", but the camera is calibrated for " +
                             std::to_string(camera.width) + "x" + std::to_string(camera.height));
  }
  return img;
}

size_t camera_index(const Rig& rig, const std::string& name, const std::string& item) {
  for (size_t i = 0; i < rig.cameras().size(); ++i) {
    if (rig.cameras()[i].name == name) return i;
  }
  std::vector<std::string> names;
  for (const auto& c : rig.cameras()) names.push_back(c.name);
  throw UsageError("--image " + item + ": the rig has no camera '" + name + "' (cameras: " + joined(names, " ") + ")");
}

// One image per camera index; empty where no --image names the camera.
}  // namespace

std::vector<cv::Mat> read_images(const Args& args, const Rig& rig) {
  std::vector<cv::Mat> images(rig.cameras().size());
  std::vector<std::string> paths(rig.cameras().size());
  for (const auto& item : args.all("image")) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) throw UsageError("--image needs CAM=PATH, got '" + item + "'");
    const std::string name = item.substr(0, eq), path = item.substr(eq + 1);
    const size_t index = camera_index(rig, name, item);
    if (!paths[index].empty()) {
      throw UsageError("--image " + name + " given twice ('" + paths[index] + "' and '" + path + "')");
    }
    paths[index] = path;
    images[index] = read_camera_image(rig.cameras()[index], path);
  }
  return images;
}

}  // namespace omniview::cli
