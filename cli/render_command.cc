#include "cli/render_command.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include <opencv2/imgproc.hpp>

#include "cli/args.h"
#include "cli/render_cloud.h"
#include "cli/rig_args.h"
#include "core/depth/camera_occluders.h"
#include "core/depth/measured_depth_view.h"
#include "core/io/image_codec.h"
#include "core/io/yaml_reader.h"
#include "core/gain/gain_compensator.h"
#include "core/map/apply.h"
#include "core/map/fusion_map.h"
#include "core/rig/rig.h"
#include "core/view/view.h"
#include "core/view/view_yaml.h"

namespace omniview::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kRenderHelp = R"(usage: omniview render --rig RIG.yaml --image CAM=PATH ... --view VIEW.yaml ... --out OUT
       omniview render --list-models | --list-view-types

Computes views offline from a calibrated rig and one image per camera.

  --rig FILE          our rig YAML, or a kalibr camchain.yaml (cam0, cam1, ...)
  --rig-frame NAME    camchain only: the robot frame cam0 is posed in (default base_link);
                      views are posed in it unless they name another 'frame'
  --rig-pose "x y z yaw pitch roll" | "x y z qx qy qz qw"
                      camchain only: the pose of cam0's optical frame (z along the optical
                      axis, x right, y down) in --rig-frame (x forward, y left, z up), as
                      T_parent_cam in our rig YAML: metres, then yaw, pitch, roll in degrees
                      (R = Rz(yaw)*Ry(pitch)*Rx(roll)) or a unit quaternion. Default all
                      zero: cam0 looks along the frame's +z. Example: cam0 1 m up, looking
                      along +x (forward) with the image's top up:
                        --rig-pose "0 0 1 -90 0 -90"   (or "0 0 1 -0.5 0.5 -0.5 0.5")
  --image CAM=PATH    the image of camera CAM (repeat for each camera a view needs)
  --view FILE         a view YAML (one view, or 'views: [...]'); repeatable; view names
                      must be unique
  --out PATH          one view: the output image (.png, .jpg or .jpeg), or a folder (existing,
                      or written with a trailing '/') that receives NAME.png;
                      several views: a folder, which receives NAME.png per view
  --cloud FILE        measured points (PLY or PCD) for the views with 'depth: measured': their
                      surface follows the points (gaps between a lidar's rings filled, the
                      view's fixed surface where nothing was measured, blended), and a point
                      every camera sees hidden behind a nearer surface is black. At most
                      20 000 000 points; NaN/inf points (no return) are skipped and counted
  --cloud-frame NAME  the rig frame the cloud's points are in (default: the frame the file
                      records, else the rig's frame, e.g. --rig-frame's)
  --grey | --colour   output greyscale or colour (default: colour if any input is)
  --list-models       camera models and their parameters
  --list-view-types   view types and their parameters
  -h, --help          this help
)";

const OptionSpec kRenderOptions{.switches = {"grey", "colour", "color", "list-models", "list-view-types"},
                          .single = {"rig", "rig-frame", "rig-pose", "out", "cloud", "cloud-frame"},
                          .repeatable = {"image", "view"}};

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
               "     fusion (nearest | blend), feather_px,\n"
               "     ground: true (all but birdseye: the surface ends at the ground plane z = ground_z),\n"
               "     depth: fixed | measured (the surface follows --cloud's points; default fixed)\n";
}

// ---- options ----

void check_option_combinations(const Args& args) {
  if (args.has("grey") && (args.has("colour") || args.has("color"))) {
    throw UsageError("--grey and --colour contradict each other; give one of them");
  }
  if (!args.positional().empty()) throw UsageError("unexpected argument '" + args.positional()[0] + "'");
  for (const char* needed : {"rig", "view", "out"}) args.required(needed);
  if (args.has("cloud-frame") && !args.has("cloud")) throw UsageError("--cloud-frame needs --cloud FILE");
}

// ---- the views ----

struct NamedView {
  ViewSpec spec;
  std::string source;  // where it was defined, for messages: "views.yaml views[1]"
};

// Each view is written as, and addressed by, its name: two of one name would overwrite.
void reject_taken_name(const std::vector<NamedView>& views, const NamedView& view) {
  for (const auto& other : views) {
    if (other.spec.name == view.spec.name) {
      throw UsageError("view name '" + view.spec.name + "' is used twice: in " + other.source + " and in " +
                       view.source + "; view names must be unique");
    }
  }
}

std::vector<NamedView> load_views_from_args(const Args& args) {
  std::vector<NamedView> views;
  for (const auto& file : args.all("view")) {
    const std::vector<ViewSpec> specs = load_views(file);
    for (size_t i = 0; i < specs.size(); ++i) {
      NamedView view{specs[i], specs.size() == 1 ? file : file + " views[" + std::to_string(i) + "]"};
      reject_taken_name(views, view);
      views.push_back(std::move(view));
    }
  }
  return views;
}

// A view posed in a frame the rig does not know would only fail once earlier views are
// written; checked for all views up front.
void check_view_frame(const NamedView& view, const LoadedRig& loaded) {
  const Rig& rig = loaded.rig;
  const std::string frame = view.spec.frame.empty() ? rig.default_frame() : view.spec.frame;
  const std::vector<std::string> known = rig.known_frames();
  if (std::find(known.begin(), known.end(), frame) != known.end()) return;
  std::string message = "view '" + view.spec.name + "' (" + view.source + "): frame '" + frame +
                        "' is not a frame of the rig (known frames: " + joined(known) + ")";
  message += loaded.camchain ? "; a camchain's cameras are posed in --rig-frame (now '" + rig.default_frame() +
                                   "'): give --rig-frame " + frame + " to pose cam0 in '" + frame + "'"
                             : "; add it under the rig's 'frames:', or pose the view in a known frame";
  throw std::runtime_error(message);
}

// ---- output paths ----

// The image formats we offer for --out (core/io/image_codec.h).
const std::vector<std::string>& writable_extensions() { return writable_image_extensions(); }

std::string lowercase_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

void check_image_file_name(const std::string& out) {
  const std::string ext = lowercase_extension(out);
  const auto& writable = writable_extensions();
  if (ext.empty()) {
    throw UsageError("--out " + out + ": give the output image a file extension (" + joined(writable, " ") +
                     "), or end it with '/' to write NAME.png into that folder");
  }
  if (std::find(writable.begin(), writable.end(), ext) == writable.end()) {
    throw UsageError("--out " + out + ": cannot write " + ext + " images; supported: " + joined(writable, " "));
  }
}

// Several views need a folder; an image-like name there would become a folder called x.png.
void check_folder_name(const std::string& out, size_t view_count) {
  const std::string views = count_of(view_count, "view", "views");
  if (fs::exists(out)) {
    throw UsageError("--out " + out + " is a file, but with " + views +
                     " --out must be a folder (it receives NAME.png per view)");
  }
  if (fs::path(out).has_extension()) {
    throw UsageError("--out " + out + ": with " + views + " --out must be a folder (it receives NAME.png per view), " +
                     "not an image file; render one view to write one file (to name a folder with a dot, " +
                     "end it with '/')");
  }
}

// Where each view goes: the single file --out, or FOLDER/NAME.png.
std::vector<std::string> output_paths(const std::string& out, const std::vector<NamedView>& views) {
  if (out.empty()) throw UsageError("--out needs a value");
  const bool names_folder = fs::is_directory(out) || out.back() == '/';
  if (!names_folder && views.size() == 1) {
    check_image_file_name(out);
    return {out};
  }
  if (!names_folder) check_folder_name(out, views.size());
  std::vector<std::string> paths;
  for (const auto& view : views) paths.push_back((fs::path(out) / (view.spec.name + ".png")).string());
  return paths;
}

// ---- input images ----

int output_channels(const Args& args, const std::vector<cv::Mat>& images) {
  if (args.has("grey")) return 1;
  if (args.has("colour") || args.has("color")) return 3;
  const bool any_colour = std::any_of(images.begin(), images.end(), [](const cv::Mat& m) { return m.channels() == 3; });
  return any_colour ? 3 : 1;
}

// ---- rendering ----

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

struct PreparedView {
  const NamedView* view;
  FusionMap map;
  double build_ms;
  std::string note;  // measured depth: how much of the view stands on it
};

void check_needed_images(const NamedView& view, const FusionMap& map, const Rig& rig,
                         const std::vector<cv::Mat>& images) {
  std::vector<std::string> missing, flags;
  for (size_t i = 0; i < images.size(); ++i) {
    if (!map.camera_used[i] || !images[i].empty()) continue;
    missing.push_back("'" + rig.cameras()[i].name + "'");
    flags.push_back("--image " + rig.cameras()[i].name + "=PATH");
  }
  if (missing.empty()) return;
  const bool one = missing.size() == 1;
  throw UsageError("view '" + view.spec.name + "' needs " + (one ? "camera " : "cameras ") + joined(missing) +
                   (one ? ", which has" : ", which have") + " no image: add " + joined(flags, " "));
}

// Everything that can fail is checked for every view before the first is written. All maps
// are held at once for that: an offline render has a few views, not hundreds.
// A measured-depth view's map: its surface from the cloud, its occlusion from the cloud and
// that surface (core/depth).
FusionMap measured_depth_map(const NamedView& view, const Rig& rig, const RenderCloud& cloud, std::string& note) {
  const ViewSpec& spec = view.spec;
  const std::string frame = spec.frame.empty() ? rig.default_frame() : spec.frame;
  const Pose T_view_robot = spec.T_frame_view().inverse() * rig.frames().lookup(frame, rig.default_frame());
  DepthStats stats;
  const auto depth_view = DepthSurface(spec).update(cloud.points, T_view_robot, &stats, &cloud.completion.points);
  const Occlusion occlusion = view_occlusion(CameraRangeImages(rig, ViewOcclusionOptions{}.cell_deg), *depth_view,
                                             cloud.points, T_view_robot, {}, &cloud.completion.points);
  std::ostringstream os;
  os << std::fixed << std::setprecision(1) << ", " << 100 * depth_view->measured_fraction()
     << " % on measured depth (" << stats.points - stats.non_finite - stats.outside_view << " of "
     << stats.points << " points in view";
  if (stats.non_finite) os << ", " << stats.non_finite << " NaN/inf skipped";
  if (!cloud.completion.points.empty()) os << "; " << cloud.completion.stats.columns << " columns complete them";
  os << ")";
  note = os.str();
  return build_map(rig, *depth_view, MapPrecision::kAdaptive, Sampling::kFootprint, &occlusion);
}

std::vector<PreparedView> prepare_views(const std::vector<NamedView>& views, const LoadedRig& loaded,
                                        const std::vector<cv::Mat>& images, const RenderCloud* cloud) {
  for (const auto& view : views) check_view_frame(view, loaded);
  for (const auto& view : views) {
    if (view.spec.depth == Depth::kMeasured && !cloud) {
      throw UsageError("view '" + view.spec.name + "' (" + view.source +
                       ") has depth: measured: give the points it stands on with --cloud FILE");
    }
  }
  if (cloud && std::none_of(views.begin(), views.end(), [](const NamedView& v) { return v.spec.depth == Depth::kMeasured; })) {
    throw UsageError("--cloud " + cloud->file + " is for views with 'depth: measured', and none of the views has it");
  }
  std::vector<PreparedView> prepared;
  for (const auto& view : views) {
    const auto t0 = std::chrono::steady_clock::now();
    std::string note;
    FusionMap map = view.spec.depth == Depth::kMeasured ? measured_depth_map(view, loaded.rig, *cloud, note)
                                                        : build_map(loaded.rig, *View::create(view.spec));
    const double build_ms = ms_since(t0);
    check_needed_images(view, map, loaded.rig, images);
    prepared.push_back({&view, std::move(map), build_ms, note});
  }
  return prepared;
}

void render_and_write(const PreparedView& p, const std::vector<cv::Mat>& images, int channels,
                      const std::string& path) {
  cv::Mat result;
  const auto t0 = std::chrono::steady_clock::now();
  GainCompensator gains;  // one image set: its own estimate, nothing to smooth
  apply_map(p.map, images, result, channels, gains.update(p.map, images, channels));
  const double apply_ms = ms_since(t0);
  if (const fs::path folder = fs::path(path).parent_path(); !folder.empty()) {
    std::error_code ec;
    if (fs::create_directories(folder, ec); ec) {
      throw std::runtime_error("cannot create the folder '" + folder.string() + "' for '" + path + "': " + ec.message());
    }
  }
  write_image(path, result);
  const ViewSpec& spec = p.view->spec;
  std::cout << std::fixed << std::setprecision(1) << path << ": " << spec.name << " (" << to_string(spec.type) << " "
            << spec.width << "x" << spec.height << "), coverage " << 100 * p.map.coverage() << " %, map "
            << p.build_ms << " ms, apply " << apply_ms << " ms" << p.note << "\n";
}

}  // namespace

int render_command(const std::vector<std::string>& argv) {
  const Args args = Args::parse(argv, kRenderOptions);
  if (args.help_requested()) {
    std::cout << kRenderHelp;
    return 0;
  }
  if (args.has("list-models")) list_models();
  if (args.has("list-view-types")) list_view_types();
  if (args.has("list-models") || args.has("list-view-types")) return 0;
  check_option_combinations(args);

  const LoadedRig loaded = load_rig_from_args(args);
  const std::vector<NamedView> views = load_views_from_args(args);
  const std::vector<std::string> paths = output_paths(args.get("out"), views);
  const std::vector<cv::Mat> images = read_images(args, loaded.rig);
  std::optional<RenderCloud> cloud;
  if (args.has("cloud")) cloud = load_render_cloud(args, loaded.rig);
  const std::vector<PreparedView> prepared = prepare_views(views, loaded, images, cloud ? &*cloud : nullptr);
  const int channels = output_channels(args, images);
  for (size_t i = 0; i < prepared.size(); ++i) render_and_write(prepared[i], images, channels, paths[i]);
  return 0;
}

}  // namespace omniview::cli
