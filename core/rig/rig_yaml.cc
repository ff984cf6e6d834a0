// Loaders for our rig YAML and kalibr camchains.
#include <filesystem>
#include <fstream>
#include <set>

#include "core/io/image_codec.h"
#include "core/io/yaml_reader.h"
#include "core/rig/rig.h"

namespace omniview {
namespace {

// Reads the kalibr-style model fields shared by both formats.
void read_model(const YamlReader& r, const YAML::Node& n, const std::string& path, Camera& cam) {
  ModelSpec spec;
  spec.camera_model = r.text(r.required(n, "camera_model", path), path + ".camera_model");
  spec.intrinsics = r.numbers(r.required(n, "intrinsics", path), path + ".intrinsics");
  spec.distortion_model = n["distortion_model"] ? r.text(n["distortion_model"], path + ".distortion_model") : "none";
  if (n["distortion_coeffs"]) spec.distortion = r.numbers(n["distortion_coeffs"], path + ".distortion_coeffs");
  const auto res = r.numbers(r.required(n, "resolution", path), path + ".resolution", 2);
  if (res[0] != std::floor(res[0]) || res[1] != std::floor(res[1]) || res[0] < 2 || res[1] < 2 ||
      res[0] > 65535 || res[1] > 65535) {
    r.fail(n["resolution"], path + ".resolution", "expected [width, height] in pixels (2..65535)");
  }
  cam.width = static_cast<int>(res[0]);
  cam.height = static_cast<int>(res[1]);
  try {
    cam.model = make_camera_model(spec, path);
  } catch (const std::invalid_argument& e) {
    // The message reads "<path>: <field> ..."; point at the line of the field it names
    // first (e.g. the intrinsics list with a wrong count), else at the camera.
    // (No YAML::Node reassignment here: for yaml-cpp that rebinds the node it referred to.)
    const std::string message = e.what();
    const char* named = nullptr;
    size_t first = std::string::npos;
    for (const char* field : {"camera_model", "intrinsics", "distortion_model", "distortion_coeffs"}) {
      const size_t pos = message.find(field, path.size());
      if (pos < first && n[field]) {
        first = pos;
        named = field;
      }
    }
    r.fail(named ? n[named] : n, "", message);
  }
}

void add_or_fail(const YamlReader& r, const YAML::Node& n, const std::string& path, Rig& rig, Camera cam) {
  try {
    rig.add_camera(std::move(cam));
  } catch (const std::exception& e) {
    r.fail(n, path, e.what());
  }
}

// Missing and undecodable masks get different messages.
cv::Mat read_mask(const YamlReader& r, const YAML::Node& n, const std::string& path, const std::string& file) {
  std::string why;
  cv::Mat mask = read_image(file, ImageColour::kGrey, &why);
  if (mask.empty()) r.fail(n, path, "cannot read mask image '" + file + "': " + why);
  return mask;
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

// The top of `frame`'s chain of parents.
std::string root_of(const FrameGraph& frames, std::string frame) {
  while (const auto parent = frames.parent_of(frame)) frame = *parent;
  return frame;
}

// An entry (camera or frame) whose chain of parents never reaches the rig's frame would
// only fail once a view is rendered; reported here, at its `parent` line, instead.
void check_reaches_rig_frame(const YamlReader& r, const YAML::Node& entry, const std::string& path, const Rig& rig,
                             const std::string& name) {
  if (rig.frames().try_lookup(rig.default_frame(), name)) return;
  const std::string parent = rig.frames().parent_of(name).value_or(rig.default_frame());
  const std::string root = root_of(rig.frames(), name);
  const std::string unknown = root == parent ? "'" + parent + "' is not a known frame"
                                             : "'" + parent + "' hangs from '" + root + "', which is not a known frame";
  r.fail(entry["parent"] ? entry["parent"] : entry, path + ".parent",
         unknown + " (known frames: " + joined(rig.known_frames()) +
             "); define it under 'frames:' with its pose in one of those, or fix the name");
}

// Camchain camera entries are read leniently (kalibr versions add keys we do not use), but a
// key given twice is still an error: yaml-cpp would silently use the first copy.
void expect_map_without_repeated_keys(const YamlReader& r, const YAML::Node& n, const std::string& path) {
  if (!n.IsMap()) r.fail(n, path, "expected a map");
  std::set<std::string> seen;
  for (const auto& kv : n) {
    const std::string key = kv.first.Scalar();
    if (!seen.insert(key).second) r.fail(kv.first, path + "." + key, "key given twice");
  }
}

}  // namespace

Rig load_rig_yaml(const std::string& path) {
  return parse_rig_yaml(YamlReader::from_file(path), std::filesystem::path(path).parent_path().string());
}

Rig parse_rig_yaml(const YamlReader& r, const std::string& folder_name) {
  const YAML::Node& root = r.root();
  if (!root.IsMap()) r.fail(root, "", "expected a rig: a map with 'cameras'");
  r.expect_keys(root, "", {"frame", "frames", "cameras"});
  Rig rig(root["frame"] ? r.text(root["frame"], "frame") : "base_link");
  const YAML::Node frames = root["frames"];
  if (frames) {
    if (!frames.IsSequence()) r.fail(frames, "frames", "expected a list of {name, parent, T_parent_frame}");
    for (size_t i = 0; i < frames.size(); ++i) {
      const std::string p = "frames[" + std::to_string(i) + "]";
      r.expect_keys(frames[i], p, {"name", "parent", "T_parent_frame"});
      try {
        rig.add_frame(r.text(r.required(frames[i], "name", p), p + ".name"),
                      r.text(r.required(frames[i], "parent", p), p + ".parent"),
                      r.pose(r.required(frames[i], "T_parent_frame", p), p + ".T_parent_frame"));
      } catch (const std::invalid_argument& e) {
        r.fail(frames[i], p, e.what());
      }
    }
  }
  const YAML::Node cams = r.required(root, "cameras", "");
  if (!cams.IsSequence() || cams.size() == 0) r.fail(cams, "cameras", "expected a non-empty list of cameras");
  const std::filesystem::path folder(folder_name);
  for (size_t i = 0; i < cams.size(); ++i) {
    const YAML::Node n = cams[i];
    std::string p = "cameras[" + std::to_string(i) + "]";
    r.expect_keys(n, p, {"name", "camera_model", "intrinsics", "distortion_model", "distortion_coeffs",
                         "resolution", "parent", "T_parent_cam", "mount", "mask", "fov_deg"});
    Camera cam;
    cam.name = r.text(r.required(n, "name", p), p + ".name");
    p += " (" + cam.name + ")";
    read_model(r, n, p, cam);
    if (n["parent"]) cam.parent_frame = r.text(n["parent"], p + ".parent");
    if (n["T_parent_cam"] && n["mount"]) r.fail(n, p, "give either T_parent_cam or mount, not both");
    if (n["T_parent_cam"]) {
      cam.T_parent_cam = r.pose(n["T_parent_cam"], p + ".T_parent_cam");
    } else if (n["mount"]) {
      // `mount` is posed like a view (x = optical axis, y left, z up): friendlier to write.
      cam.T_parent_cam = r.pose(n["mount"], p + ".mount");
      cam.T_parent_cam.linear() = cam.T_parent_cam.linear() * R_view_optical();
    } else {
      r.fail(n, p, "missing the camera's pose: give T_parent_cam (optical frame) or mount (view-like)");
    }
    if (n["fov_deg"]) cam.fov_deg = r.number(n["fov_deg"], p + ".fov_deg");
    if (n["mask"]) {
      const auto mask_path = (folder / r.text(n["mask"], p + ".mask")).string();
      cam.mask = read_mask(r, n["mask"], p + ".mask", mask_path);
      // Checked here too (Rig::add_camera would) so the message points at the mask's line.
      if (cam.mask.cols != cam.width || cam.mask.rows != cam.height) {
        r.fail(n["mask"], p + ".mask",
               "mask '" + mask_path + "' is " + std::to_string(cam.mask.cols) + "x" + std::to_string(cam.mask.rows) +
                   ", must be the camera's resolution " + std::to_string(cam.width) + "x" + std::to_string(cam.height));
      }
    }
    add_or_fail(r, n, p, rig, std::move(cam));
  }
  // Frames first: a camera under an unconnected frame is reported at that frame.
  for (size_t i = 0; frames && i < frames.size(); ++i) {
    check_reaches_rig_frame(r, frames[i], "frames[" + std::to_string(i) + "]", rig, frames[i]["name"].Scalar());
  }
  for (size_t i = 0; i < cams.size(); ++i) {
    const std::string& name = rig.cameras()[i].name;
    check_reaches_rig_frame(r, cams[i], "cameras[" + std::to_string(i) + "] (" + name + ")", rig, name);
  }
  return rig;
}

Rig load_kalibr_camchain(const std::string& path, const std::string& frame, const Pose& T_frame_cam0) {
  return parse_kalibr_camchain(YamlReader::from_file(path), frame, T_frame_cam0);
}

Rig parse_kalibr_camchain(const YamlReader& r, const std::string& frame, const Pose& T_frame_cam0) {
  const YAML::Node& root = r.root();
  if (!root.IsMap() || !root["cam0"]) r.fail(root, "", "not a kalibr camchain: expected keys cam0, cam1, ...");
  Rig rig(frame);
  Pose T_frame_prev = T_frame_cam0;
  size_t count = 0;
  // Every top-level key must be camN (N without leading zeros), each once, with no gaps.
  const auto cam_index = [](const std::string& key) -> long {
    if (key.size() < 4 || key.size() > 9 || key.rfind("cam", 0) != 0 || (key[3] == '0' && key.size() > 4)) return -1;
    for (size_t i = 3; i < key.size(); ++i) {
      if (key[i] < '0' || key[i] > '9') return -1;
    }
    return std::stol(key.substr(3));
  };
  std::set<long> indices;
  for (const auto& kv : root) {
    const std::string key = kv.first.Scalar();
    const long index = cam_index(key);
    if (index < 0) r.fail(kv.first, key, "unexpected top-level key in a camchain (expected cam0, cam1, ...)");
    if (!indices.insert(index).second) r.fail(kv.first, key, "key given twice");
  }
  long missing = 0;
  while (indices.count(missing)) ++missing;
  if (const auto after = indices.upper_bound(missing); after != indices.end()) {
    // Reported at the first camera past the gap.
    const std::string key = "cam" + std::to_string(*after);
    for (const auto& kv : root) {
      if (kv.first.Scalar() == key) {
        r.fail(kv.first, key, "camchain cameras must be numbered cam0, cam1, ... without gaps: cam" +
                                  std::to_string(missing) + " is missing");
      }
    }
  }
  for (;; ++count) {
    const std::string key = "cam" + std::to_string(count);
    const YAML::Node n = root[key];
    if (!n) break;
    expect_map_without_repeated_keys(r, n, key);
    Camera cam;
    cam.name = key;
    read_model(r, n, key, cam);
    cam.parent_frame = frame;
    if (count == 0) {
      cam.T_parent_cam = T_frame_cam0;
    } else {
      // T_cn_cnm1 maps points of cam(n-1) into cam(n): T_frame_cn = T_frame_cnm1 * T_cn_cnm1^-1.
      const Pose T_cn_cnm1 = r.pose(r.required(n, "T_cn_cnm1", key), key + ".T_cn_cnm1");
      cam.T_parent_cam = T_frame_prev * T_cn_cnm1.inverse();
    }
    T_frame_prev = cam.T_parent_cam;
    add_or_fail(r, n, key, rig, std::move(cam));
  }
  return rig;
}

bool is_kalibr_camchain(const YamlReader& reader) { return reader.root().IsMap() && reader.root()["cam0"]; }

Rig load_rig(const std::string& path, const std::string& camchain_frame, const Pose& camchain_T_frame_cam0) {
  const YamlReader r = YamlReader::from_file(path);
  if (is_kalibr_camchain(r)) return parse_kalibr_camchain(r, camchain_frame, camchain_T_frame_cam0);
  return parse_rig_yaml(r, std::filesystem::path(path).parent_path().string());
}

namespace {

void emit_numbers(YAML::Emitter& out, const std::vector<double>& values) {
  out << YAML::Flow << YAML::BeginSeq;
  for (double v : values) out << v;
  out << YAML::EndSeq;
}

// As a 4x4 matrix: exact at full precision, where ypr or a quaternion would round.
void emit_pose(YAML::Emitter& out, const Pose& T) {
  const Mat4 m = T.matrix();
  out << YAML::BeginSeq;
  for (int r = 0; r < 4; ++r) emit_numbers(out, {m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  out << YAML::EndSeq;
}

// `mask_files`: per camera, the file name to reference, or empty for none.
std::string rig_yaml_text(const Rig& rig, const std::vector<std::string>& mask_files) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap << YAML::Key << "frame" << YAML::Value << rig.default_frame();
  std::vector<std::string> extra;
  for (const auto& frame : rig.frames().frames()) {
    if (!rig.find(frame) && rig.frames().parent_of(frame)) extra.push_back(frame);
  }
  if (!extra.empty()) {
    out << YAML::Key << "frames" << YAML::Value << YAML::BeginSeq;
    for (const auto& frame : extra) {
      out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << frame;
      out << YAML::Key << "parent" << YAML::Value << *rig.frames().parent_of(frame);
      out << YAML::Key << "T_parent_frame" << YAML::Value;
      emit_pose(out, rig.frames().lookup(*rig.frames().parent_of(frame), frame));
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }
  out << YAML::Key << "cameras" << YAML::Value << YAML::BeginSeq;
  for (size_t i = 0; i < rig.cameras().size(); ++i) {
    const Camera& cam = rig.cameras()[i];
    const ModelSpec spec = describe(cam.model);
    out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << cam.name;
    out << YAML::Key << "camera_model" << YAML::Value << spec.camera_model;
    out << YAML::Key << "intrinsics" << YAML::Value;
    emit_numbers(out, spec.intrinsics);
    out << YAML::Key << "distortion_model" << YAML::Value << spec.distortion_model;
    if (!spec.distortion.empty()) {
      out << YAML::Key << "distortion_coeffs" << YAML::Value;
      emit_numbers(out, spec.distortion);
    }
    out << YAML::Key << "resolution" << YAML::Value;
    emit_numbers(out, {double(cam.width), double(cam.height)});
    if (cam.fov_deg != 0) out << YAML::Key << "fov_deg" << YAML::Value << cam.fov_deg;
    // From the frame graph, not cam.T_parent_cam: adapters update extrinsics live there.
    const std::string parent = rig.frames().parent_of(cam.name).value_or(cam.parent_frame);
    out << YAML::Key << "parent" << YAML::Value << parent;
    out << YAML::Key << "T_parent_cam" << YAML::Value;
    emit_pose(out, rig.frames().try_lookup(parent, cam.name).value_or(cam.T_parent_cam));
    if (i < mask_files.size() && !mask_files[i].empty()) out << YAML::Key << "mask" << YAML::Value << mask_files[i];
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace

std::string rig_to_yaml(const Rig& rig) { return rig_yaml_text(rig, {}); }

void save_rig_yaml(const Rig& rig, const std::string& path) {
  const std::filesystem::path file(path);
  std::vector<std::string> mask_files;
  for (const Camera& cam : rig.cameras()) {
    if (cam.mask.empty()) {
      mask_files.emplace_back();
      continue;
    }
    mask_files.push_back(cam.name + "_mask.png");
    const auto mask_path = (file.parent_path() / mask_files.back()).string();
    write_image(mask_path, cam.mask);
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << rig_yaml_text(rig, mask_files);
  out.flush();
  if (!out) throw std::runtime_error("cannot write rig file '" + path + "'");
}

}  // namespace omniview
