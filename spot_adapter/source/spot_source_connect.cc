// SpotSource's connection to the robot: its cameras and frame tree (the rig), the clock
// sync, and the rig kept current from the frame-tree snapshots of later images.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>

#include "bosdyn/api/image_service.grpc.pb.h"
#include "spot_adapter/convert/camera_model_from_source.h"
#include "spot_adapter/convert/depth_from_response.h"
#include "spot_adapter/source/joint_states.h"
#include "spot_adapter/source/spot_rig.h"
#include "spot_adapter/source/spot_source.h"

namespace omniview::spot {
namespace {

namespace api = bosdyn::api;
using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

// A moving robot changes `vision` and `odom` in every image set; rebuilding every view's
// map that often would cost more than the views, so the rig follows at most this often.
constexpr auto kMinRigInterval = milliseconds(500);

// ListImageSources does not name a source's sensor frame (only images do). Spot names the
// body cameras' frames after their sources (frontleft_fisheye_image -> frontleft_fisheye),
// other image services append "_sensor": take the first candidate the tree has.
std::string sensor_frame_in(const std::map<std::string, FrameEdge>& tree, const std::string& source) {
  const std::string suffix = "_image";
  std::string stem = source;
  if (stem.size() > suffix.size() && stem.compare(stem.size() - suffix.size(), suffix.size(), suffix) == 0) {
    stem.resize(stem.size() - suffix.size());
  }
  for (const std::string& candidate : {stem, source, source + "_sensor", stem + "_sensor"}) {
    if (tree.count(candidate)) return candidate;
  }
  return stem;  // build_spot_rig reports it missing from the tree
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}


// Same sources, sensor frames, sizes and calibrations, in the same order.
bool same_cameras(const std::vector<CameraSlot>& a, const std::vector<CameraSlot>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    const Camera &x = a[i].camera, &y = b[i].camera;
    const ModelSpec mx = describe(x.model), my = describe(y.model);
    if (a[i].source != b[i].source || x.name != y.name || x.width != y.width || x.height != y.height ||
        mx.camera_model != my.camera_model || mx.distortion_model != my.distortion_model ||
        mx.intrinsics != my.intrinsics || mx.distortion != my.distortion) {
      return false;
    }
  }
  return true;
}

// Whether any edge was added, removed or moved beyond noise.
bool tree_moved(const std::map<std::string, FrameEdge>& a, const std::map<std::string, FrameEdge>& b) {
  if (a.size() != b.size()) return true;
  for (const auto& [child, edge] : a) {
    const auto it = b.find(child);
    if (it == b.end() || edge_moved(edge, it->second)) return true;
  }
  return false;
}

}  // namespace

void SpotSource::set_rig(std::shared_ptr<const Rig> rig) {
  std::lock_guard lock(mutex_);
  rig_ = std::move(rig);
  ++rig_version_;
}

void SpotSource::announce_rig() {
  // A frame set without images: the pipeline rebuilds every view for the new rig, and the
  // views somebody watches then ask for their cameras.
  auto frames = std::make_shared<FrameSet>();
  frames->sequence = ++sequence_;
  frames->capture_time = std::chrono::system_clock::now();
  frames->arrival = Clock::now();
  {
    std::lock_guard lock(mutex_);
    frames->rig = rig_;
    frames->rig_version = rig_version_;
  }
  frames->images.resize(slots_.size());
  on_frame_(std::move(frames));
}

void SpotSource::connect() {
  session_.connect();
  const api::ListImageSourcesResponse response = session_.call(
      "image", &api::ImageService::Stub::ListImageSources, api::ListImageSourcesRequest(), "ListImageSources");

  std::map<std::string, FrameEdge> tree;
  for (auto& e : frame_edges(response.transforms_snapshot(), "ListImageSources")) tree[e.child] = e;
  std::vector<CameraSlot> slots;
  std::vector<std::string> missing, available;
  for (const auto& s : response.image_sources()) available.push_back(s.name());
  for (const std::string& name : settings_.cameras) {
    const auto it = std::find_if(response.image_sources().begin(), response.image_sources().end(),
                                 [&](const api::ImageSource& s) { return s.name() == name; });
    if (it == response.image_sources().end()) {
      missing.push_back(name);
      continue;
    }
    CameraSlot slot;
    slot.source = name;
    slot.camera = camera_from_image_source(*it);
    slot.camera.name = sensor_frame_in(tree, name);
    slot.pixel_format = settings_.prefer_rgb ? api::Image::PIXEL_FORMAT_RGB_U8 : api::Image::PIXEL_FORMAT_GREYSCALE_U8;
    // Its registered depth, where the robot has it (depth-aware views ask for it).
    const std::string depth = depth_source_for(name);
    if (std::find(available.begin(), available.end(), depth) != available.end()) slot.depth_source = depth;
    slots.push_back(std::move(slot));
  }
  if (slots.empty()) {
    throw SpotError(SpotError::Kind::kProtocol, "the robot has none of the configured cameras (it has: " +
                                                    join(available) + ")");
  }
  // The same robot back after an outage: keep the rig, so no view rebuilds its map and
  // the cameras watched before are pulled again at once.
  const bool unchanged = same_cameras(slots, slots_) && !tree_moved(tree_, tree);
  if (!unchanged) {
    std::vector<Camera> cameras;
    for (const auto& s : slots) cameras.push_back(s.camera);
    set_rig(build_spot_rig(cameras, tree));
    {
      std::lock_guard lock(mutex_);
      slots_ = std::move(slots);
      last_good_.clear();
      wanted_.assign(slots_.size(), false);  // the pipeline says again once it has the rig
    }
    tree_ = std::move(tree);
    last_rig_change_ = Clock::now();
  }

  std::vector<std::string> names;
  for (const auto& s : slots_) names.push_back(s.camera.name);
  const std::string note = missing.empty() ? "" : "not on this robot: " + join(missing) + " (it has: " + join(available) + ")";
  log(std::string(unchanged ? "reconnected to " : "connected to ") + session_.robot() + " at " + to_string(settings_.address) + "; cameras: " + join(names) +
      (note.empty() ? "" : "; " + note));
  sync_clock();
  std::string cloud_note;
  cloud_source_ = find_point_cloud_source(session_, settings_.point_cloud_source, cloud_note);
  {
    std::lock_guard lock(mutex_);
    clouds_missing_ = cloud_source_.empty();
  }
  if (!cloud_source_.empty()) {
    log("coloured clouds from point-cloud source '" + cloud_source_ + "' while someone watches one");
  } else if (settings_.point_cloud_source != "none") {
    log(cloud_note);
  }
  connect_note_ = note;
  // The robot's pose now, so that the first frames do not show it in the URDF's zero pose.
  if (robot_state_available_) {
    try {
      joints_ = read_joint_states(session_);
      joints_read_ = Clock::now();
      publish_joints();
    } catch (const SpotError& e) {
      if (e.kind() != SpotError::Kind::kProtocol) throw;  // away again: the usual handling
      robot_state_available_ = false;  // a robot (or image service) without robot state: no overlay joints
      log("no joint angles for the robot overlay: " + std::string(e.what()));
    }
  }
  report(true, note);
  if (!unchanged) announce_rig();
}

void SpotSource::sync_clock() {
  if (!time_sync_available_) return;
  clock_.reset();  // a robot back after a restart may have forgotten our clock identifier
  try {
    clock_.sync(session_);
  } catch (const SpotError& e) {
    if (e.kind() != SpotError::Kind::kProtocol) throw;  // away again: the usual handling
    time_sync_available_ = false;
    log("no time sync with the robot, capture times are its clock's: " + std::string(e.what()));
    return;
  }
  clock_updated_ = Clock::now();
  if (!clock_.synced()) {
    log("the robot's clock is not synchronised yet; capture times are its clock's until it is");
    return;
  }
  const double skew_s = std::chrono::duration<double>(clock_.skew()).count();
  char text[160];
  std::snprintf(text, sizeof text, "robot clock %.3f s %s ours (round trip %.1f ms); capture times are ours",
                std::abs(skew_s), skew_s >= 0 ? "ahead of" : "behind",
                std::chrono::duration<double, std::milli>(clock_.round_trip()).count());
  log(text);
}

void SpotSource::refresh_tree(const std::vector<FrameEdge>& edges) {
  std::map<std::string, FrameEdge> tree = tree_;
  bool moved = false;
  for (const auto& e : edges) {
    const auto it = tree.find(e.child);
    if (it == tree.end() || edge_moved(it->second, e)) {
      tree[e.child] = e;
      moved = true;
    }
  }
  if (!moved || Clock::now() - last_rig_change_ < kMinRigInterval) return;
  std::vector<Camera> cameras;
  for (const auto& s : slots_) cameras.push_back(s.camera);
  set_rig(build_spot_rig(cameras, tree));
  tree_ = std::move(tree);
  last_rig_change_ = Clock::now();
}

}  // namespace omniview::spot
