#include "insta360_adapter/source/capture_config.h"

#include <filesystem>
#include <set>

#include "insta360_adapter/device/device_locator.h"
#include "insta360_adapter/device/file_device.h"
#include "insta360_adapter/device/v4l2_device.h"
#include "server/sources/source_config_helpers.h"

namespace omniview::insta360 {

extern const char* const kAirCalibrationYaml;  // generated from config/insta360/air_calibration.yaml

namespace {

Pose pose_from_six(const YamlReader& r, const YAML::Node& node, const std::string& key) {
  if (node.IsSequence() && node.size() == 6) {
    const auto v = r.numbers(node, key, 6);
    return make_pose(Vec3(v[0], v[1], v[2]), v[3] * M_PI / 180, v[4] * M_PI / 180, v[5] * M_PI / 180);
  }
  return r.pose(node, key);
}

uint32_t pixel_format_named(const YamlReader& r, const YAML::Node& node, const std::string& key) {
  const std::string t = r.text(node, key);
  if (t == "MJPG" || t == "MJPEG" || t == "mjpeg") return kMjpeg;
  if (t == "YUYV" || t == "yuyv") return kYuyv;
  r.fail(node, key, "'" + t + "' is not a pixel format omniview decodes (MJPG or YUYV)");
}

}  // namespace

Rig default_air_calibration() {
  return parse_rig_yaml(YamlReader::from_string(kAirCalibrationYaml, "built-in Air calibration (config/insta360/air_calibration.yaml)"), "");
}

Rig place_rig(const Rig& calibration, const std::string& rig_frame, const Pose& mount) {
  Rig rig(rig_frame);
  const std::string& body = calibration.default_frame();
  if (body != rig_frame) rig.add_frame(body, rig_frame, mount);
  std::set<std::string> cameras;
  for (const Camera& c : calibration.cameras()) cameras.insert(c.name);
  const FrameGraph& graph = calibration.frames();
  for (const std::string& f : graph.frames()) {
    const auto parent = graph.parent_of(f);
    if (parent && !cameras.count(f)) rig.add_frame(f, *parent, graph.lookup(*parent, f));
  }
  for (const Camera& c : calibration.cameras()) rig.add_camera(c);
  return rig;
}

CaptureSettings read_capture_settings(const SourceConfig& config, const std::string& type, DeviceOpener open_override) {
  const YamlReader& r = *config.reader;
  const YAML::Node& n = config.node;
  const std::string& p = config.path;
  r.expect_keys(n, p, {"name", "type", "device", "file", "rate_hz", "speed", "loop", "calibration", "frame", "rig_frame",
                       "mount", "format", "lenses", "decode_scale", "lens_check"});
  const bool air = type == "insta360";
  CaptureSettings s;
  s.type = type;
  s.check_lens_circles = air;
  if (n["lens_check"]) s.check_lens_circles = r.boolean(n["lens_check"], p + ".lens_check");

  // The calibration, in lens-image pixels, placed on the robot.
  const std::string body = n["frame"] ? r.text(n["frame"], p + ".frame") : (air ? "insta360" : "camera");
  Rig calibration;
  if (n["calibration"]) {
    const std::string path = config_path(config, "calibration");
    try {
      const YamlReader file = YamlReader::from_file(path);
      if (is_kalibr_camchain(file)) {
        // cam0 sits where the nominal front lens sits (Air), or looks along the body's +x.
        Pose T_body_cam0 = Pose::Identity();
        if (air) {
          T_body_cam0 = default_air_calibration().camera_pose("insta360", 0);
        } else {
          T_body_cam0.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // optical z = body x, x = -y, y = -z
        }
        calibration = parse_kalibr_camchain(file, body, T_body_cam0);
      } else {
        calibration = parse_rig_yaml(file, std::filesystem::path(path).parent_path().string());
      }
    } catch (const ConfigError&) {
      throw;
    } catch (const std::exception& e) {
      r.fail(n["calibration"], p + ".calibration", "cannot load calibration '" + path + "': " + e.what());
    }
  } else if (air) {
    calibration = default_air_calibration();
  } else {
    r.fail(n, p, "a v4l2 source needs `calibration` (a kalibr camchain.yaml or our rig YAML)");
  }
  const std::string rig_frame = n["rig_frame"] ? r.text(n["rig_frame"], p + ".rig_frame") : "base_link";
  const Pose mount = n["mount"] ? pose_from_six(r, n["mount"], p + ".mount") : Pose::Identity();
  try {
    s.calibration = std::make_shared<const Rig>(place_rig(calibration, rig_frame, mount));
  } catch (const std::exception& e) {
    r.fail(n, p, std::string("cannot place the calibration on the robot: ") + e.what());
  }

  // Lens crops (default: side by side) and the frame they need.
  if (const YAML::Node lenses = n["lenses"]) {
    if (!lenses.IsMap()) r.fail(lenses, p + ".lenses", "expected {camera: [x, y, width, height]}");
    for (const auto& kv : lenses) {
      const std::string key = p + ".lenses." + kv.first.Scalar();
      const auto v = r.numbers(kv.second, key, 4);
      s.crops.push_back({kv.first.Scalar(), cv::Rect(int(v[0]), int(v[1]), int(v[2]), int(v[3]))});
    }
  } else {
    s.crops = side_by_side(*s.calibration);
  }
  cv::Rect bounds;
  for (const auto& c : s.crops) bounds |= c.rect;
  s.frame_size = cv::Size(bounds.x + bounds.width, bounds.y + bounds.height);

  // The format to ask for: the frame the lenses need, MJPEG (v4l2: or YUYV).
  s.format.pixel_formats = air ? std::vector<uint32_t>{kMjpeg} : std::vector<uint32_t>{kMjpeg, kYuyv};
  if (const YAML::Node f = n["format"]) {
    r.expect_keys(f, p + ".format", {"pixel_format", "width", "height", "fps"});
    if (f["pixel_format"]) s.format.pixel_formats = {pixel_format_named(r, f["pixel_format"], p + ".format.pixel_format")};
    if (f["width"]) s.frame_size.width = r.integer(f["width"], p + ".format.width");
    if (f["height"]) s.frame_size.height = r.integer(f["height"], p + ".format.height");
    if (f["fps"]) s.format.fps = r.number(f["fps"], p + ".format.fps");
  }
  s.format.width = s.frame_size.width;
  s.format.height = s.frame_size.height;
  try {
    check_crops(*s.calibration, s.crops, s.frame_size);
  } catch (const std::exception& e) {
    r.fail(n["lenses"] ? n["lenses"] : n, p + ".lenses", e.what());
  }

  if (const YAML::Node d = n["decode_scale"]) {
    const std::string t = r.text(d, p + ".decode_scale");
    if (t == "auto") {
      s.decode_scale = 0;
    } else if (t == "1" || t == "2" || t == "4") {
      s.decode_scale = std::stoi(t);
    } else {
      r.fail(d, p + ".decode_scale", "expected auto, 1, 2 or 4");
    }
  }

  // Where frames come from.
  if (n["file"] && n["device"]) r.fail(n["file"], p + ".file", "give `device` or `file`, not both");
  if (open_override) {
    s.device_text = "test device";
    s.open = std::move(open_override);
  } else if (n["file"]) {
    const std::string path = config_path(config, "file");
    FilePlayback playback;
    playback.rate_hz = positive_number(config, "rate_hz", 30);
    playback.speed = positive_number(config, "speed", 1);
    if (n["loop"]) playback.loop = r.boolean(n["loop"], p + ".loop");
    // Load it now, so that a bad recording is a config error, not a runtime one.
    std::shared_ptr<VideoDevice> loaded;
    try {
      loaded = open_file_device(path, playback);
    } catch (const std::exception& e) {
      r.fail(n["file"], p + ".file", e.what());
    }
    s.device_text = path;
    // Played from the start at every (re)open; the frames stay loaded.
    s.open = [path, playback] { return open_file_device(path, playback); };
  } else {
    const std::string spec = n["device"] ? r.text(n["device"], p + ".device") : (air ? "name:Insta360" : "");
    if (spec.empty()) r.fail(n, p, "a v4l2 source needs `device` (/dev/videoN, vendor:product, serial:X or name:X) or `file`");
    try {
      (void)find_video_node(spec);  // checks the form
    } catch (const std::invalid_argument& e) {
      r.fail(n["device"], p + ".device", e.what());
    }
    s.device_text = spec;
    s.open = [spec]() -> std::unique_ptr<VideoDevice> {
      const std::string path = find_video_node(spec);
      if (path.empty()) {
        throw DeviceError(DeviceFault::kNotFound, "no camera matching '" + spec + "' is plugged in (" +
                                                     describe_video_nodes() + ")");
      }
      return open_v4l2_device(path);
    };
  }
  return s;
}

std::unique_ptr<Source> make_insta360_source(const SourceConfig& config) {
  return std::make_unique<CaptureSource>(config.name, read_capture_settings(config, "insta360"));
}

std::unique_ptr<Source> make_v4l2_source(const SourceConfig& config) {
  return std::make_unique<CaptureSource>(config.name, read_capture_settings(config, "v4l2"));
}

}  // namespace omniview::insta360
