#include "server/sources/velodyne/velodyne_source.h"

#include <algorithm>
#include <cstdio>
#include <iostream>

namespace omniview {
namespace {

// The camera source written under `cameras:`, with errors naming that key.
std::unique_ptr<Source> make_cameras(const SourceConfig& config) {
  const YamlReader& r = *config.reader;
  const std::string key = config.path + ".cameras";
  const YAML::Node node = r.required(config.node, "cameras", config.path);
  if (!node.IsMap()) r.fail(node, key, "expected the camera source's map {type: ..., its keys}");
  const std::string type = r.text(r.required(node, "type", key), key + ".type");
  if (type == "velodyne") r.fail(node["type"], key + ".type", "the cameras of a velodyne source cannot be a velodyne");
  return make_source(type, SourceConfig{config.name, config.reader, node, key, config.folder});
}

}  // namespace

VelodyneSource::VelodyneSource(const SourceConfig& config)
    : Source(config.name),
      settings_((config.reader->expect_keys(config.node, config.path,
                                            {"name", "type", "cameras", "bind", "port", "sender", "frame", "parent",
                                             "pose", "calibration", "returns", "point_time"}),
                 parse_velodyne_settings(config))),
      cameras_(make_cameras(config)) {
  // A rig known now (files; a robot's arrives later) must take the lidar's frame as asked.
  const auto rig = cameras_->rig();
  const YamlReader& r = *config.reader;
  if (rig->frames().has_frame(settings_.frame)) {
    r.fail(config.node["frame"] ? config.node["frame"] : config.node, config.path + ".frame",
           "the camera rig already has a frame '" + settings_.frame + "': name the lidar's frame differently");
  }
  if (!settings_.parent.empty() && !rig->cameras().empty()) {
    const auto known = rig->known_frames();
    if (std::find(known.begin(), known.end(), settings_.parent) == known.end()) {
      std::string list;
      for (const auto& f : known) list += (list.empty() ? "" : ", ") + f;
      r.fail(config.node["parent"], config.path + ".parent",
             "the camera rig has no frame '" + settings_.parent + "' (its frames: " + list + ")");
    }
  }
}

VelodyneSource::~VelodyneSource() { stop(); }

std::shared_ptr<const Rig> VelodyneSource::with_lidar(const std::shared_ptr<const Rig>& camera_rig) const {
  std::lock_guard lock(rig_mutex_);
  if (camera_rig == camera_rig_seen_ && rig_) return rig_;
  auto rig = std::make_shared<Rig>(*camera_rig);
  // A robot's rig may name the frame itself later: then its own pose of it stands.
  if (!rig->frames().has_frame(settings_.frame)) {
    rig->add_frame(settings_.frame, settings_.parent.empty() ? rig->default_frame() : settings_.parent,
                   settings_.T_parent_lidar);
  }
  camera_rig_seen_ = camera_rig;
  rig_ = std::move(rig);
  ++rig_version_;
  return rig_;
}

std::shared_ptr<const Rig> VelodyneSource::rig() const { return with_lidar(cameras_->rig()); }

void VelodyneSource::start(FrameCallback on_frame) {
  const std::string& b = settings_.bind;
  const bool loopback = b.rfind("127.", 0) == 0 || b == "::1" || b == "localhost";
  if (!loopback && settings_.sender.empty()) {
    // Anyone who can reach the port could paint points into the cloud an operator trusts.
    std::cerr << "omniviewd: source '" << name() << "' takes VLP-16 packets from anyone who can reach " << b << ":"
              << settings_.port << "; set `sender` to the lidar's address\n";
  }
  stopping_ = false;
  receiver_ = std::thread([this] { receive_loop(); });
  cameras_->start([this, on_frame](std::shared_ptr<const FrameSet> frames) { on_camera_frames(frames, on_frame); });
}

void VelodyneSource::stop() {
  cameras_->stop();
  stopping_ = true;
  if (receiver_.joinable()) receiver_.join();
}

void VelodyneSource::on_camera_frames(const std::shared_ptr<const FrameSet>& frames, const FrameCallback& on_frame) {
  auto out = std::make_shared<FrameSet>(*frames);  // shares the pixels
  out->rig = with_lidar(frames->rig);
  {
    std::lock_guard lock(rig_mutex_);
    out->rig_version = rig_version_;
  }
  std::lock_guard lock(mutex_);
  // Each rotation once, with the first image set after it (not repeated: the pipeline
  // would colour the same cloud again for every image set).
  out->cloud = std::move(pending_);
  pending_.reset();
  on_frame(std::move(out));
}

void VelodyneSource::receive_loop() {
  std::unique_ptr<Vlp16Assembler> assembler;
  bool partial_first = false;
  std::vector<uint8_t> data;
  std::string sender;
  std::unique_ptr<UdpListener> socket;
  bool told = false;
  while (!stopping_) {
    if (!socket) {
      // Bound here, retried each second: the lidar's network interface may come up after
      // the daemon, and `omniviewd --check` must not need the port a running daemon holds.
      try {
        socket = std::make_unique<UdpListener>(settings_.bind, settings_.port);
        std::cerr << "omniviewd: source '" << name() << "' listens for VLP-16 packets on " << settings_.bind << ":"
                  << socket->port() << "\n";
        std::lock_guard lock(mutex_);
        listen_problem_.clear();
      } catch (const std::exception& e) {
        if (!told) std::cerr << "omniviewd: source '" << name() << "': " << e.what() << " (retrying every second)\n";
        told = true;
        {
          std::lock_guard lock(mutex_);
          listen_problem_ = e.what();
        }
        for (int i = 0; i < 10 && !stopping_; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        continue;
      }
    }
    if (!socket->receive(data, sender, std::chrono::milliseconds(100))) continue;
    std::string problem;
    std::vector<PointCloud> done;
    if (!settings_.sender.empty() && sender != settings_.sender) {
      problem = "a packet from " + sender + ", not from the lidar's address " + settings_.sender;
    } else if (!cloud_wanted_) {
      assembler.reset();  // nobody watches: no half rotation is kept for later
    } else {
      if (!assembler) {
        assembler = std::make_unique<Vlp16Assembler>(settings_.calibration, settings_.frame, settings_.returns);
        partial_first = true;
      }
      try {
        done = assembler->add_packet(data.data(), data.size(), std::chrono::system_clock::now(),
                                     "VLP-16 packet from " + sender);
      } catch (const CloudFormatError& e) {
        problem = e.what();
      }
      // Decoding began mid-sweep: the first rotation is only its end.
      if (partial_first && !done.empty()) {
        done.erase(done.begin());
        partial_first = false;
      }
    }
    std::lock_guard lock(mutex_);
    if (!cloud_wanted_) pending_.reset();  // a rotation nobody took is stale for the next watcher
    ++packets_;
    if (!problem.empty()) {
      ++bad_packets_;
      last_problem_ = problem;
    }
    if (assembler && assembler->packets() > 0) {
      lidar_clock_synchronised_ = assembler->clock().synchronised();
      lidar_clock_correction_s_ = std::chrono::duration<double>(assembler->clock().correction()).count();
    }
    for (auto& cloud : done) {
      if (!settings_.point_time) cloud.time.clear();
      ++rotations_;
      pending_ = std::make_shared<const PointCloud>(std::move(cloud));
    }
  }
}

SourceHealth VelodyneSource::health() const {
  SourceHealth h = cameras_->health();
  std::lock_guard lock(mutex_);
  h.errors += bad_packets_;
  if (!listen_problem_.empty()) {
    const std::string lidar = "lidar: " + listen_problem_ + " (retrying)";
    h.message = h.message.empty() ? lidar : h.message + "; " + lidar;
  }
  if (rotations_ > 0 && !lidar_clock_synchronised_) {
    // Not an error: most lidars run without GPS. Said so that nobody trusts their stamps.
    char text[128];
    std::snprintf(text, sizeof text, "lidar clock free-running (no GPS/PTP): its times moved %+.3f s onto ours",
                  lidar_clock_correction_s_);
    h.message = h.message.empty() ? text : h.message + "; " + text;
  }
  if (bad_packets_ > 0) {
    const std::string lidar = "lidar: " + std::to_string(bad_packets_) + " of " + std::to_string(packets_) +
                              " packets skipped (last: " + last_problem_ + "); " + std::to_string(rotations_) +
                              " rotations";
    h.message = h.message.empty() ? lidar : h.message + "; " + lidar;
  }
  return h;
}

std::unique_ptr<Source> make_velodyne_source(const SourceConfig& config) {
  return std::make_unique<VelodyneSource>(config);
}

}  // namespace omniview
