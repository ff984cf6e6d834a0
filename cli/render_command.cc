#include "cli/render_command.h"

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cli/args.h"
#include "core/map/apply.h"
#include "core/map/fusion_map.h"
#include "core/rig/rig.h"
#include "core/view/view.h"
#include "core/view/view_yaml.h"

namespace omniview::cli {
namespace {

constexpr const char* kHelp = R"(usage: omniview render --rig RIG.yaml --image CAM=PATH ... --view VIEW.yaml ... --out OUT
       omniview render --list-models | --list-view-types

Computes views offline from a calibrated rig and one image per camera.

  --rig FILE          our rig YAML, or a kalibr camchain.yaml (cam0, cam1, ...)
  --rig-frame NAME    camchain only: the robot frame cam0 is posed in (default base_link)
  --rig-pose "x y z yaw pitch roll"
                      camchain only: pose of cam0's optical frame in --rig-frame
                      (metres, degrees; default all zero)
  --image CAM=PATH    the image of camera CAM (repeat for each camera a view needs)
  --view FILE         a view YAML (one view, or 'views: [...]'); repeatable
  --out PATH          output image (.png, .jpg); with several views, a folder that
                      receives NAME.png per view
  --grey | --colour   output greyscale or colour (default: colour if any input is)
  --list-models       camera models and their parameters
  --list-view-types   view types and their parameters
)";

void list_models() {
  std::cout << "camera models (kalibr names: camera_model + distortion_model):\n";
  for (const auto& m : supported_models()) {
    std::cout << "  " << std::left << std::setw(8) << m.camera_model << " + " << std::setw(12) << m.distortion_model
              << "intrinsics " << m.intrinsics << ", distortion_coeffs " << m.distortion << "\n"
              << "      " << m.note << "\n";
  }
}

void list_view_types() {
  std::cout << "view types (YAML key 'type') and their parameters:\n"
               "  perspective      hfov_deg (< 180), distance (m)\n"
               "  birdseye         hfov_deg, height_m (above the ground), ground_z (m in frame); looks straight down\n"
               "  cylindrical      radius, vfov_deg, azimuth_span_deg   (the paper's \"Mercator\")\n"
               "  mercator         radius, lat_min_deg, lat_max_deg, azimuth_span_deg\n"
               "  equirectangular  radius, lat_min_deg, lat_max_deg, azimuth_span_deg\n"
               "  fisheye          radius, fov_deg (ideal equidistant fisheye)\n"
               "all: name, width, height, frame, pose: {xyz: [x, y, z], ypr_deg: [yaw, pitch, roll]},\n"
               "     fusion (nearest | blend), feather_px\n";
}

Pose parse_rig_pose(const std::string& text) {
  std::istringstream in(text);
  double v[6];
  for (double& x : v) {
    if (!(in >> x)) throw UsageError("--rig-pose needs six numbers \"x y z yaw pitch roll\", got \"" + text + "\"");
  }
  const double d = M_PI / 180;
  return make_pose(Vec3(v[0], v[1], v[2]), v[3] * d, v[4] * d, v[5] * d);
}

cv::Mat read_image(const std::string& camera, const std::string& path) {
  cv::Mat img = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (img.empty()) throw std::runtime_error("camera '" + camera + "': cannot read image '" + path + "'");
  if (img.depth() != CV_8U) {
    throw std::runtime_error("camera '" + camera + "': image '" + path + "' is not 8-bit");
  }
  if (img.channels() == 4) cv::cvtColor(img, img, cv::COLOR_BGRA2BGR);
  if (img.channels() == 2) throw std::runtime_error("camera '" + camera + "': image '" + path + "' has 2 channels");
  return img;
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int render_command(const std::vector<std::string>& argv) {
  const Args args(argv, {"help", "grey", "colour", "color", "list-models", "list-view-types"});
  args.allow_only({"help", "grey", "colour", "color", "list-models", "list-view-types", "rig", "rig-frame",
                   "rig-pose", "image", "view", "out"});
  if (args.has("help")) {
    std::cout << kHelp;
    return 0;
  }
  if (args.has("list-models")) {
    list_models();
    return 0;
  }
  if (args.has("list-view-types")) {
    list_view_types();
    return 0;
  }
  if (!args.positional().empty()) throw UsageError("unexpected argument '" + args.positional()[0] + "'");

  const Rig rig = load_rig(args.required("rig"), args.get("rig-frame", "base_link"),
                           parse_rig_pose(args.get("rig-pose", "0 0 0 0 0 0")));
  std::vector<ViewSpec> views;
  if (args.all("view").empty()) throw UsageError("missing --view");
  for (const auto& file : args.all("view")) {
    for (auto& v : load_views(file)) views.push_back(std::move(v));
  }
  const std::string out = args.required("out");
  const bool to_folder = views.size() > 1 || std::filesystem::is_directory(out) || out.back() == '/';

  std::vector<cv::Mat> images(rig.cameras().size());
  for (const auto& item : args.all("image")) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) throw UsageError("--image needs CAM=PATH, got '" + item + "'");
    const std::string name = item.substr(0, eq);
    size_t index = 0;
    while (index < rig.cameras().size() && rig.cameras()[index].name != name) ++index;
    if (index == rig.cameras().size()) {
      std::string known;
      for (const auto& c : rig.cameras()) known += " " + c.name;
      throw UsageError("--image " + item + ": the rig has no camera '" + name + "' (cameras:" + known + ")");
    }
    images[index] = read_image(name, item.substr(eq + 1));
  }
  bool any_colour = false;
  for (const auto& img : images) any_colour = any_colour || img.channels() == 3;
  const int channels = args.has("grey") ? 1 : (args.has("colour") || args.has("color") || any_colour) ? 3 : 1;

  if (to_folder) std::filesystem::create_directories(out);
  for (const auto& spec : views) {
    const auto view = View::create(spec);
    auto t0 = std::chrono::steady_clock::now();
    const FusionMap map = build_map(rig, *view);
    const double build_ms = ms_since(t0);
    for (size_t i = 0; i < images.size(); ++i) {
      if (map.camera_used[i] && images[i].empty()) {
        throw UsageError("view '" + spec.name + "' needs camera '" + rig.cameras()[i].name + "': add --image " +
                         rig.cameras()[i].name + "=PATH");
      }
    }
    cv::Mat result;
    t0 = std::chrono::steady_clock::now();
    apply_map(map, images, result, channels);
    const double apply_ms = ms_since(t0);
    const std::string path = to_folder ? (std::filesystem::path(out) / (spec.name + ".png")).string() : out;
    if (!cv::imwrite(path, result)) throw std::runtime_error("cannot write '" + path + "'");
    std::cout << std::fixed << std::setprecision(1) << path << ": " << spec.name << " (" << to_string(spec.type) << " "
              << spec.width << "x" << spec.height << "), coverage " << 100 * map.coverage() << " %, map "
              << build_ms << " ms, apply " << apply_ms << " ms\n";
  }
  return 0;
}

}  // namespace omniview::cli
