#include "spot_adapter/source/spot_source.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <mutex>
#include <utility>

#include "bosdyn/api/image_service.grpc.pb.h"
#include "spot_adapter/convert/camera_model_from_source.h"
#include "spot_adapter/convert/cloud_from_response.h"
#include "spot_adapter/source/body_motion.h"
#include "spot_adapter/source/joint_states.h"
#include "spot_adapter/source/spot_rig.h"

namespace omniview::spot {
namespace {

namespace api = bosdyn::api;
using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

constexpr auto kErrorLogInterval = std::chrono::seconds(30);
// Depth images (while a depth view is watched) with at most one image call this often.
constexpr auto kDepthInterval = std::chrono::milliseconds(500);
constexpr auto kChannelResetInterval = std::chrono::seconds(10);
// Legs move slower than cameras need frames: joint angles at 5 Hz are enough for the overlay.
constexpr auto kJointInterval = milliseconds(200);
// Joint angles older than this (the source was idle) are read again before a frame uses them.
constexpr auto kJointsStale = milliseconds(1000);
// Clocks drift by microseconds a second: one time-sync round trip now and then is enough.
constexpr auto kClockUpdateInterval = std::chrono::seconds(30);
// How long a camera's last good image stands in for bad ones before it goes black.
constexpr auto kHoldLastImage = milliseconds(1000);
// A frame set, or a failed call the robot answered (not one lost on the way), within this
// long: the robot is connected, whatever fails in between (GetStatus then says degraded,
// with the failure rate). Only silence makes it "not connected".
constexpr auto kConnectedWindow = milliseconds(1000);
// The failure rate's memory: each call's outcome weighs 1/20 (about the last 20 calls).
constexpr double kFailureRateWeight = 1.0 / 20;
// ... and how long it stands without new calls.
constexpr auto kFailureRateMemory = std::chrono::seconds(3);

}  // namespace

SpotSource::SpotSource(const SourceConfig& config)
    : Source(config.name),
      settings_(parse_spot_settings(config)),
      channels_(settings_.address, settings_.ca_pem),
      session_(channels_, SessionOptions{settings_.credentials_file, settings_.timeout, "omniviewd"}),
      rig_(placeholder_rig()) {
  health_.message = "connecting to " + to_string(settings_.address);
}

SpotSource::~SpotSource() { stop(); }

std::shared_ptr<const Rig> SpotSource::rig() const {
  std::lock_guard lock(mutex_);
  return rig_;
}

void SpotSource::start(FrameCallback on_frame) {
  on_frame_ = std::move(on_frame);
  thread_ = std::thread([this] { run(); });
}

void SpotSource::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  session_.cancel();  // a call in flight to an unreachable robot ends now, not at its deadline
  calls_.interrupt();  // the source's thread cancels its image calls on the way out
  if (thread_.joinable()) thread_.join();
}

void SpotSource::set_wanted_cameras(const std::vector<bool>& wanted) {
  {
    std::lock_guard lock(mutex_);
    wanted_ = wanted;
  }
  wake_.notify_all();
}

bool SpotSource::provides_clouds() const {
  std::lock_guard lock(mutex_);
  return settings_.point_cloud_source != "none" && !clouds_missing_;
}

void SpotSource::set_cloud_wanted(bool wanted) {
  std::lock_guard lock(mutex_);
  if (wanted && !cloud_wanted_) cloud_rewanted_ = true;
  cloud_wanted_ = wanted;
}

void SpotSource::set_depth_wanted(bool wanted) {
  std::lock_guard lock(mutex_);
  depth_wanted_ = wanted;
}

std::shared_ptr<const PointCloud> SpotSource::next_cloud() {
  bool wanted, rewanted;
  {
    std::lock_guard lock(mutex_);
    wanted = cloud_wanted_;
    rewanted = std::exchange(cloud_rewanted_, false);
  }
  auto answer = cloud_reader_.take();  // taken even when unwanted: a stale cloud is dropped
  // The first cycle after nobody watched: what the reader holds answered a request of the
  // last watcher's time, maybe minutes ago, and would be served as "the next cloud".
  if (rewanted) answer = {};
  if (!wanted || cloud_source_.empty()) return nullptr;
  cloud_reader_.request(session_, cloud_source_);  // the next one, answered by a later image set
  std::string problem = answer.problem;
  std::shared_ptr<const PointCloud> cloud;
  if (answer.cloud) {
    auto stamp = cloud_acquisition_time(*answer.cloud);
    if (stamp.time_since_epoch().count() == 0) {
      stamp = std::chrono::system_clock::now();  // a robot that sends no time
    } else if (clock_.synced()) {
      stamp = clock_.to_local(stamp);
    }
    try {
      cloud = std::make_shared<const PointCloud>(
          cloud_from_spot(*answer.cloud, stamp, "GetPointCloud of '" + cloud_source_ + "'"));
    } catch (const SpotError& e) {
      problem = e.what();
    }
  }
  if (!problem.empty()) {
    {
      std::lock_guard lock(mutex_);
      ++health_.errors;
      health_.message = problem;
    }
    if (Clock::now() - last_error_log_ > kErrorLogInterval) {
      log("cloud skipped: " + problem);
      last_error_log_ = Clock::now();
    }
  }
  return cloud;
}

void SpotSource::count_outcome(bool failed) {
  // After a pause in pulling (nobody watched) the rate starts afresh: it says how the
  // robot answers now, not before the pause.
  if (Clock::now() - last_outcome_ > kFailureRateMemory) failure_rate_ = 0;
  last_outcome_ = Clock::now();
  failure_rate_ += kFailureRateWeight * ((failed ? 1.0 : 0.0) - failure_rate_);
  health_.failure_rate = failure_rate_;
}

SourceHealth SpotSource::health() const {
  std::lock_guard lock(mutex_);
  SourceHealth h = health_;
  // Nothing pulled lately: no recent call failed (a stale rate would read "degraded" while
  // nobody watches).
  if (Clock::now() - last_outcome_ > kFailureRateMemory) h.failure_rate = 0;
  return h;
}

std::vector<size_t> SpotSource::wanted_slots() const {
  std::lock_guard lock(mutex_);
  std::vector<size_t> out;
  for (size_t i = 0; i < slots_.size() && i < wanted_.size(); ++i) {
    if (wanted_[i]) out.push_back(i);
  }
  return out;
}

bool SpotSource::sleep_until(Clock::time_point deadline) {
  std::unique_lock lock(mutex_);
  const auto none_wanted = std::none_of(wanted_.begin(), wanted_.end(), [](bool w) { return w; });
  // Idle, a change of wanted cameras ends the wait (a viewer arrived); pulling, it waits
  // for the next cycle so the rate never exceeds rate_hz.
  const auto snapshot = wanted_;
  wake_.wait_until(lock, deadline, [&] { return stopping_ || (none_wanted && wanted_ != snapshot); });
  return !stopping_;
}

std::shared_ptr<const std::map<std::string, double>> SpotSource::latest_joints() const {
  std::lock_guard lock(mutex_);
  return latest_joints_;
}

void SpotSource::publish_joints() {
  std::lock_guard lock(mutex_);
  latest_joints_ = joints_;
}

// Idle: one robot-state read a second (no images), so the joints the API reports are the
// robot's pose now, not the one from when somebody last watched.
void SpotSource::refresh_idle_joints() {
  if (!robot_state_available_ || Clock::now() - joints_read_ < kJointsStale) return;
  try {
    joints_ = read_joint_states(session_);
    joints_read_ = Clock::now();
    publish_joints();
  } catch (const SpotError& e) {
    if (e.kind() != SpotError::Kind::kProtocol) throw;  // the robot went away: the usual handling
    robot_state_available_ = false;
    log("no joint angles for the robot overlay: " + std::string(e.what()));
  }
}

void SpotSource::report(bool connected, const std::string& message) {
  std::lock_guard lock(mutex_);
  health_.connected = connected;
  health_.message = message;
}

void SpotSource::log(const std::string& line) const { std::cerr << "omniviewd: source '" << name() << "': " << line << "\n"; }

void SpotSource::fill_gaps(ImageSet& set, const std::vector<size_t>& wanted, Clock::time_point now) {
  last_good_.resize(slots_.size());
  for (size_t i : wanted) {
    auto& last = last_good_[i];
    if (!set.images[i].empty()) {
      last = {set.images[i], now};
      continue;
    }
    // One camera's bad image must not cost every view that fuses it its frame: show that
    // camera's last good image for a moment, then black (a gap where it looks) until it
    // recovers, while the other cameras keep the views live.
    if (!last.image.empty() && now - last.time < kHoldLastImage) {
      set.images[i] = last.image;
    } else {
      const Camera& c = slots_[i].camera;
      set.images[i] = cv::Mat::zeros(c.height, c.width, last.image.empty() ? CV_8UC1 : last.image.type());
    }
  }
}

void SpotSource::start_call(const std::vector<size_t>& wanted) {
  auto call = std::make_unique<ImageCall>();
  call->wanted = wanted;
  bool depth_wanted;
  {
    std::lock_guard lock(mutex_);
    depth_wanted = depth_wanted_;
  }
  // Depth rides along with every call kDepthInterval apart: a depth image is 600 KB raw,
  // five of them with every image set would be 45 MB/s at 15 Hz.
  if (depth_wanted && Clock::now() - last_depth_call_ >= kDepthInterval) {
    for (size_t i : wanted) {
      if (!slots_[i].depth_source.empty()) call->depth.push_back(i);
    }
    if (!call->depth.empty()) last_depth_call_ = Clock::now();
  }
  call->request = image_request(session_, settings_, slots_, wanted, call->depth);
  call->stub = api::ImageService::NewStub(session_.service_channel("image"));
  session_.prepare(call->context, true);
  calls_.start(std::move(call));
}

void SpotSource::finish_call(ImageCall& call) {
  check_status(call.status, "GetImage");
  const std::vector<size_t>& wanted = call.wanted;
  ImageSet set = images_from_response(call.request, call.response, slots_, wanted, call.depth);
  if (!set.depth_problems.empty()) {
    {
      std::lock_guard lock(mutex_);
      health_.errors += set.depth_problems.size();
    }
    if (Clock::now() - last_error_log_ > kErrorLogInterval) {
      log("skipped " + std::to_string(set.depth_problems.size()) + " bad depth image(s): " + set.depth_problems.front());
      last_error_log_ = Clock::now();
    }
  }
  const auto arrival = Clock::now();
  {
    std::lock_guard lock(mutex_);
    count_outcome(!set.problems.empty());  // a call that brought a bad image failed in part
  }
  if (!set.problems.empty()) {
    {
      std::lock_guard lock(mutex_);
      health_.errors += set.problems.size();
      health_.message = set.problems.back();
    }
    if (Clock::now() - last_error_log_ > kErrorLogInterval) {
      log("skipped " + std::to_string(set.problems.size()) + " bad image(s): " + set.problems.front());
      last_error_log_ = Clock::now();
    }
  }
  if (set.good == 0) return;
  fill_gaps(set, wanted, arrival);
  if (robot_state_available_) {
    // The newest joint angles there are; the next read starts now and is taken later.
    auto answer = joint_reader_.take();
    if (answer.joints) joints_ = std::move(answer.joints);
    try {
      if (!answer.refusal.empty()) throw SpotError(SpotError::Kind::kProtocol, answer.refusal);
      if (idle_since_last_frame_ || Clock::now() - joints_read_ > kJointsStale) {
        // The first frame after nobody watched: the pose now, for this frame, not the one
        // from before the pause (one round trip, once).
        joints_ = read_joint_states(session_);
        joints_read_ = Clock::now();
        idle_since_last_frame_ = false;
      } else if (Clock::now() - joints_read_ > kJointInterval) {
        joints_read_ = Clock::now();
        joint_reader_.request(session_);
      }
    } catch (const SpotError& e) {
      if (e.kind() != SpotError::Kind::kProtocol) throw;  // the robot went away: the usual handling
      robot_state_available_ = false;  // a robot (or image service) without robot state: no overlay joints
      log("no joint angles for the robot overlay: " + std::string(e.what()));
    }
    publish_joints();
  }
  try {
    refresh_tree(set.edges);
  } catch (const SpotError& e) {  // keep the old rig: its extrinsics are still the best we know
    std::lock_guard lock(mutex_);
    ++health_.errors;
    health_.message = e.what();
  }
  auto frames = std::make_shared<FrameSet>();
  frames->sequence = ++sequence_;
  // On our clock, so capture times and ages mean what they say.
  frames->capture_time = set.robot_time && clock_.synced() ? clock_.to_local(set.capture_time) : set.capture_time;
  frames->arrival = arrival;
  {
    std::lock_guard lock(mutex_);
    frames->rig = rig_;
    frames->rig_version = rig_version_;
    ++health_.frames;
    health_.connected = true;
    last_answer_ = arrival;
    if (set.problems.empty()) health_.message = connect_note_;
  }
  frames->images = std::move(set.images);
  frames->encoded = std::move(set.encoded);
  frames->joints = joints_;
  frames->cloud = next_cloud();
  for (auto& d : set.depth) {
    auto cloud = std::make_shared<PointCloud>();
    cloud->frame = slots_[d.slot].camera.name;  // the camera's optical frame
    cloud->stamp = frames->capture_time;
    cloud->points = std::move(d.points);
    frames->depth.push_back(std::move(cloud));
  }
  if (const auto T_odom_body = pose_in_snapshot(set.edges, kOdomFrame, kBodyFrame)) {
    try {
      motion_.add(frames->capture_time, *T_odom_body);
      frames->motion = std::make_shared<const Trajectory>(motion_);  // a few dozen poses
    } catch (const std::invalid_argument&) {  // a non-finite pose: colour as if still
    }
  }
  on_frame_(std::move(frames));
}

std::chrono::milliseconds SpotSource::on_error(const SpotError& e) {
  ++failures_;
  // Short: a robot back from a Wi-Fi gap should be noticed within half a second.
  const milliseconds backoff = std::min(milliseconds(500), milliseconds(100) * (1 << std::min(failures_ - 1, 4)));
  milliseconds pause = backoff;
  std::string advice;
  switch (e.kind()) {
    case SpotError::Kind::kUnreachable:
      // The channels reconnect by themselves within a second; fresh ones now and then
      // guard against a connection that hangs, but never so often that a slow TLS
      // handshake over poor Wi-Fi could not finish.
      if (failures_ >= 2 && Clock::now() - last_channel_reset_ > kChannelResetInterval) {
        channels_.reset();
        last_channel_reset_ = Clock::now();
      }
      advice = "retrying every 0.5 s";
      break;
    case SpotError::Kind::kTokenRejected:
      session_.disconnect();  // log in again: expired token, or the robot restarted
      pause = failures_ == 1 ? milliseconds(0) : backoff;
      advice = "logging in again";
      break;
    case SpotError::Kind::kLoginRefused:
      // The robot locks logins after 6 failures in a row; three a minute never gets there.
      session_.disconnect();
      pause = milliseconds(20000);
      advice = "check the credentials (credentials_file, or BOSDYN_CLIENT_USERNAME/PASSWORD); retrying in 20 s";
      break;
    case SpotError::Kind::kLockedOut:
      session_.disconnect();
      pause = milliseconds(60000);
      advice = "retrying in 60 s";
      break;
    case SpotError::Kind::kCredentials:
      session_.disconnect();
      pause = milliseconds(10000);
      advice = "retrying in 10 s";
      break;
    case SpotError::Kind::kProtocol:
      pause = session_.connected() ? backoff : milliseconds(5000);
      advice = "retrying in " + std::to_string(pause.count()) + " ms";
      break;
  }
  const std::string message = std::string(e.what()) + "; " + advice;
  // The robot answered (its proxy or a service said no) rather than the call timing out
  // or the connection being down.
  const bool answered = e.kind() == SpotError::Kind::kProtocol ||
                        (e.kind() == SpotError::Kind::kUnreachable && e.code() != grpc::StatusCode::DEADLINE_EXCEEDED &&
                         e.code() != grpc::StatusCode::CANCELLED && channels_.any_connected());
  {
    std::lock_guard lock(mutex_);
    ++health_.errors;
    count_outcome(true);
    // One failed call among good ones leaves the robot connected (degraded); a robot that
    // stopped answering, or a session being repaired, is not.
    if (answered) last_answer_ = Clock::now();
    health_.connected = session_.connected() && Clock::now() - last_answer_ < kConnectedWindow;
    health_.message = message;
  }
  // Against the last one logged, not the health's message: an idle source resets that to
  // its connect note every second, and a robot gone while nobody watched was logged twice
  // a second for as long as it stayed away.
  if (message != last_logged_error_ || Clock::now() - last_error_log_ > kErrorLogInterval) {
    log(to_string(settings_.address) + ": " + message);
    last_error_log_ = Clock::now();
    last_logged_error_ = message;
  }
  return pause;
}

void SpotSource::run() {
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / settings_.rate_hz));
  const size_t max_in_flight = static_cast<size_t>(settings_.requests_in_flight);
  Clock::time_point next_call;  // when the next GetImage may start: calls start rate_hz apart
  while (true) {
    try {
      if (session_.cancelled()) break;
      if (!session_.connected()) connect();
      session_.refresh_if_due();
      if (time_sync_available_ && Clock::now() - clock_updated_ > kClockUpdateInterval) {
        clock_updated_ = Clock::now();
        try {
          clock_.update(session_);  // one round trip; clocks drift
        } catch (const SpotError& e) {
          if (e.kind() != SpotError::Kind::kProtocol) throw;  // away: the usual handling
          time_sync_available_ = false;
          log("time sync with the robot stopped, capture times are its clock's from now: " + std::string(e.what()));
        }
      }
      const auto wanted = wanted_slots();
      const auto now = Clock::now();
      if (wanted.empty() && calls_.in_flight() == 0) {
        report(true, connect_note_);
        idle_since_last_frame_ = true;
        refresh_idle_joints();  // `omniview joints` stays current with nobody watching
        if (!sleep_until(now + std::chrono::seconds(1))) break;  // nobody watches: pull no images
        continue;
      }
      if (!wanted.empty() && now >= next_call && calls_.in_flight() < max_in_flight) {
        start_call(wanted);
        // On the beat while on time; a start a whole period late sets a new beat rather
        // than bunching the next calls to catch up.
        next_call = now - next_call < period ? next_call + period : now + period;
      }
      // The oldest answer, or the time to start the next call, whichever comes first.
      const bool can_start = !wanted.empty() && calls_.in_flight() < max_in_flight;
      const auto wait = can_start ? next_call : now + settings_.timeout + std::chrono::seconds(1);
      if (calls_.in_flight() == 0) {
        if (!sleep_until(wait)) break;
        continue;
      }
      if (auto call = calls_.wait_oldest(wait)) {
        finish_call(*call);
        if (failures_ > 0) log("images flowing again after " + std::to_string(failures_) + " failed attempt(s)");
        failures_ = 0;
        last_logged_error_.clear();  // a failure after this is news again
      }
    } catch (const SpotError& e) {
      calls_.cancel_all();  // their answers would come from a session that is being repaired
      joint_reader_.cancel();
      cloud_reader_.cancel();
      if (session_.cancelled()) break;
      if (!sleep_until(Clock::now() + on_error(e))) break;
    } catch (const std::exception& e) {  // a rig the core refuses, a bad allocation: keep going
      calls_.cancel_all();
      joint_reader_.cancel();
      cloud_reader_.cancel();
      if (session_.cancelled()) break;
      if (!sleep_until(Clock::now() + on_error(SpotError(SpotError::Kind::kProtocol, e.what())))) break;
    }
  }
  calls_.cancel_all();
  joint_reader_.cancel();
  cloud_reader_.cancel();
}

std::unique_ptr<Source> make_spot_source(const SourceConfig& config) { return std::make_unique<SpotSource>(config); }

void register_spot_source() {
  static std::once_flag once;
  std::call_once(once, [] {
    register_source_type("spot",
                         "Boston Dynamics Spot over its gRPC API (keys: robot, ca_file, credentials_file, cameras, "
                         "rate_hz, image_format, jpeg_quality, pixel_format, timeout_s, requests_in_flight, "
                         "point_cloud_source)",
                         make_spot_source);
  });
}

}  // namespace omniview::spot
