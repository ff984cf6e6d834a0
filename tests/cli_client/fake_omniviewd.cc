#include "tests/cli_client/fake_omniviewd.h"

#include <cmath>
#include <thread>

#include <opencv2/core.hpp>

#include "core/io/image_codec.h"

namespace omniview::testing {
namespace {

v1::View make_view(const std::string& name, v1::ViewType type, double yaw, double hfov) {
  v1::View view;
  auto& s = *view.mutable_spec();
  s.set_name(name);
  s.set_type(type);
  s.set_source("sim");
  s.set_width(640);
  s.set_height(480);
  s.set_frame("base_link");
  s.set_yaw_deg(yaw);
  s.set_pitch_deg(0);
  s.set_roll_deg(0);
  s.set_hfov_deg(hfov);
  s.set_fov_deg(180);
  view.set_revision(1);
  view.set_robot_frame("base_link");
  view.mutable_pose()->set_qw(1);
  view.set_yaml("name: " + name + "\ntype: perspective\n");
  return view;
}

}  // namespace

FakeOmniviewd::FakeOmniviewd(std::map<std::string, std::string> tokens, const std::string& cert_pem,
                             const std::string& key_pem)
    : tokens_(std::move(tokens)) {
  views_["front"] = make_view("front", v1::PERSPECTIVE, 0, 90);
  views_["round"] = make_view("round", v1::FISHEYE, 180, 90);
  auto credentials = grpc::InsecureServerCredentials();
  if (!cert_pem.empty()) {
    grpc::SslServerCredentialsOptions tls;
    tls.pem_key_cert_pairs.push_back({key_pem, cert_pem});
    credentials = grpc::SslServerCredentials(tls);
  }
  grpc::ServerBuilder builder;
  builder.AddListeningPort("127.0.0.1:0", credentials, &port_);
  builder.RegisterService(this);
  server_ = builder.BuildAndStart();
}

FakeOmniviewd::~FakeOmniviewd() { server_->Shutdown(std::chrono::system_clock::now()); }

std::vector<v1::CreateViewRequest> FakeOmniviewd::creates() const {
  std::lock_guard lock(mutex_);
  return creates_;
}

std::vector<v1::UpdateViewRequest> FakeOmniviewd::updates() const {
  std::lock_guard lock(mutex_);
  return updates_;
}

v1::SnapshotRequest FakeOmniviewd::last_snapshot() const {
  std::lock_guard lock(mutex_);
  return last_snapshot_;
}

v1::StreamFramesRequest FakeOmniviewd::last_stream() const {
  std::lock_guard lock(mutex_);
  return last_stream_;
}

grpc::Status FakeOmniviewd::authorize(const grpc::ServerContext* context, bool needs_operator) const {
  if (tokens_.empty()) return grpc::Status::OK;
  const auto& metadata = context->client_metadata();
  const auto it = metadata.find("authorization");
  if (it == metadata.end()) return {grpc::StatusCode::UNAUTHENTICATED, "missing token"};
  const std::string value(it->second.data(), it->second.size());
  const auto role = value.rfind("Bearer ", 0) == 0 ? tokens_.find(value.substr(7)) : tokens_.end();
  if (role == tokens_.end()) return {grpc::StatusCode::UNAUTHENTICATED, "unknown token"};
  if (needs_operator && role->second != "operator") {
    return {grpc::StatusCode::PERMISSION_DENIED, "a viewer token cannot change views"};
  }
  return grpc::Status::OK;
}

grpc::Status FakeOmniviewd::find(const std::string& name, v1::View& view) const {
  const auto it = views_.find(name);
  if (it == views_.end()) return {grpc::StatusCode::NOT_FOUND, "no view '" + name + "' (views: front, round)"};
  view = it->second;
  return grpc::Status::OK;
}

grpc::Status FakeOmniviewd::ListCameras(grpc::ServerContext* context, const v1::ListCamerasRequest*,
                                        v1::ListCamerasResponse* response) {
  if (auto s = authorize(context, false); !s.ok()) return s;
  auto& c = *response->add_cameras();
  c.set_name("cam_front");
  c.set_source("sim");
  c.set_camera_model("ds");
  c.set_distortion_model("none");
  for (double k : {300.0, 300.0, 320.0, 240.0, -0.2, 0.6}) c.add_intrinsics(k);
  c.set_width(640);
  c.set_height(480);
  c.set_frame("base_link");
  c.mutable_pose()->mutable_translation()->set_x(0.25);
  c.mutable_pose()->set_qw(1);
  return grpc::Status::OK;
}

grpc::Status FakeOmniviewd::CreateView(grpc::ServerContext* context, const v1::CreateViewRequest* request,
                                       v1::View* response) {
  if (auto s = authorize(context, true); !s.ok()) return s;
  std::lock_guard lock(mutex_);
  creates_.push_back(*request);
  if (views_.count(request->spec().name())) {
    return {grpc::StatusCode::ALREADY_EXISTS, "view '" + request->spec().name() + "' exists"};
  }
  v1::View view = make_view(request->spec().name(), v1::PERSPECTIVE, 0, 90);
  view.mutable_spec()->MergeFrom(request->spec());
  *response = views_[view.spec().name()] = view;
  return grpc::Status::OK;
}

grpc::Status FakeOmniviewd::GetView(grpc::ServerContext* context, const v1::GetViewRequest* request,
                                    v1::View* response) {
  if (auto s = authorize(context, false); !s.ok()) return s;
  std::lock_guard lock(mutex_);
  return find(request->name(), *response);
}

grpc::Status FakeOmniviewd::ListViews(grpc::ServerContext* context, const v1::ListViewsRequest*,
                                      v1::ListViewsResponse* response) {
  if (auto s = authorize(context, false); !s.ok()) return s;
  std::lock_guard lock(mutex_);
  for (const auto& [_, view] : views_) *response->add_views() = view;
  return grpc::Status::OK;
}

grpc::Status FakeOmniviewd::UpdateView(grpc::ServerContext* context, const v1::UpdateViewRequest* request,
                                       v1::View* response) {
  if (auto s = authorize(context, true); !s.ok()) return s;
  std::lock_guard lock(mutex_);
  updates_.push_back(*request);
  v1::View view;
  if (auto s = find(request->name(), view); !s.ok()) return s;
  views_.erase(request->name());
  auto& spec = *view.mutable_spec();
  spec.MergeFrom(request->set());  // proto3 optional: only set fields merge
  const auto& d = request->delta();
  spec.set_yaw_deg(spec.yaw_deg() + d.yaw_deg());
  spec.set_pitch_deg(spec.pitch_deg() + d.pitch_deg());
  spec.set_roll_deg(spec.roll_deg() + d.roll_deg());
  if (d.zoom() > 0 && d.zoom() != 1) {
    spec.set_hfov_deg(2 * std::atan(std::tan(spec.hfov_deg() * M_PI / 360) / d.zoom()) * 180 / M_PI);
    spec.set_fov_deg(spec.fov_deg() / d.zoom());
  }
  view.set_revision(view.revision() + 1);
  *response = views_[spec.name()] = view;
  return grpc::Status::OK;
}

grpc::Status FakeOmniviewd::DeleteView(grpc::ServerContext* context, const v1::DeleteViewRequest* request,
                                       v1::DeleteViewResponse*) {
  if (auto s = authorize(context, true); !s.ok()) return s;
  std::lock_guard lock(mutex_);
  v1::View view;
  if (auto s = find(request->name(), view); !s.ok()) return s;
  views_.erase(request->name());
  return grpc::Status::OK;
}

v1::Frame FakeOmniviewd::make_frame(const std::string& view, uint64_t sequence, v1::Encoding encoding) {
  v1::Frame frame;
  frame.set_view(view);
  frame.set_sequence(sequence);
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  frame.mutable_capture_time()->set_seconds(std::chrono::duration_cast<std::chrono::seconds>(now).count());
  frame.mutable_capture_time()->set_nanos(0);
  frame.set_latency_ms(5 + sequence % 3);
  frame.set_encoding(encoding == v1::ENCODING_UNSPECIFIED ? v1::JPEG : encoding);
  frame.set_width(64);
  frame.set_height(32);
  frame.set_channels(3);
  frame.set_data("frame " + std::to_string(sequence) + " encoding " + std::to_string(frame.encoding()));
  frame.mutable_camera()->set_revision(3);
  return frame;
}

grpc::Status FakeOmniviewd::StreamFrames(grpc::ServerContext* context, const v1::StreamFramesRequest* request,
                                         grpc::ServerWriter<v1::Frame>* writer) {
  if (auto s = authorize(context, false); !s.ok()) return s;
  {
    std::lock_guard lock(mutex_);
    last_stream_ = *request;
    v1::View view;
    if (auto s = find(request->view(), view); !s.ok()) return s;
  }
  // 50 Hz; every fifth sequence number is skipped, as a slow client would see.
  for (uint64_t sequence = 1; sequence < 100000 && !context->IsCancelled(); ++sequence) {
    if (sequence % 5 == 0) continue;
    if (!writer->Write(make_frame(request->view(), sequence, request->encoding()))) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return grpc::Status::OK;
}

grpc::Status FakeOmniviewd::GetSnapshot(grpc::ServerContext* context, const v1::SnapshotRequest* request,
                                        v1::Frame* response) {
  if (auto s = authorize(context, false); !s.ok()) return s;
  std::lock_guard lock(mutex_);
  last_snapshot_ = *request;
  v1::View view;
  if (auto s = find(request->view(), view); !s.ok()) return s;
  *response = make_frame(request->view(), 42, request->encoding());
  return grpc::Status::OK;
}

grpc::Status FakeOmniviewd::GetStatus(grpc::ServerContext* context, const v1::GetStatusRequest*, v1::Status* response) {
  if (auto s = authorize(context, false); !s.ok()) return s;
  response->set_version("0.1.0-fake");
  response->set_uptime_s(3725);
  auto& source = *response->add_sources();
  source.set_name("sim");
  source.set_type("synthetic");
  source.set_connected(true);
  source.set_rate_hz(30);
  source.set_last_frame_age_s(0.01);
  source.set_frames(1234);
  source.add_active_cameras("cam_front");
  auto& view = *response->add_views();
  view.set_name("front");
  view.set_subscribers(2);
  view.set_fps(29.9);
  view.set_coverage(0.875);
  auto& client = *response->add_clients();
  client.set_peer("ipv4:127.0.0.1:40000");
  client.set_view("front");
  client.set_encoding("jpeg");
  client.set_frames_sent(99);
  return grpc::Status::OK;
}

grpc::Status FakeOmniviewd::StreamSourceFrames(grpc::ServerContext* context,
                                               const v1::StreamSourceFramesRequest* request,
                                               grpc::ServerWriter<v1::SourceFrame>* writer) {
  if (auto s = authorize(context, false); !s.ok()) return s;
  if (request->source() != "sim") return {grpc::StatusCode::NOT_FOUND, "no source '" + request->source() + "'"};
  const std::vector<uint8_t> png = encode_png(cv::Mat(12, 16, CV_8UC3, cv::Scalar(10, 200, 30)));
  for (uint64_t sequence = 1; sequence < 100000 && !context->IsCancelled(); ++sequence) {
    v1::SourceFrame frame;
    frame.set_sequence(sequence);
    frame.mutable_capture_time()->set_seconds(1795000000 + sequence);
    if (sequence == 1) {
      frame.set_rig_yaml(
          "frame: base_link\ncameras:\n  - name: cam_front\n    camera_model: pinhole\n"
          "    intrinsics: [10, 10, 7.5, 5.5]\n    resolution: [16, 12]\n"
          "    mount: {xyz: [0, 0, 1], ypr_deg: [0, 0, 0]}\n");
    }
    auto& image = *frame.add_images();
    image.set_camera("cam_front");
    image.set_encoding(sequence % 2 ? v1::PNG : v1::RAW);  // raw pixels, too, must be recorded
    image.set_width(16);
    image.set_height(12);
    image.set_channels(3);
    if (image.encoding() == v1::PNG) {
      image.set_data(std::string(png.begin(), png.end()));
    } else {
      image.set_data(std::string(16 * 12 * 3, '\x40'));
    }
    if (!writer->Write(frame)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return grpc::Status::OK;
}

}  // namespace omniview::testing
