#include "spot_adapter/source/cloud_calls.h"

#include <utility>

#include "spot_adapter/client/spot_error.h"

namespace omniview::spot {

namespace api = bosdyn::api;

std::string find_point_cloud_source(RobotSession& session, const std::string& setting, std::string& note) {
  note.clear();
  if (setting == "none") return "";
  api::ListPointCloudSourcesResponse response;
  try {
    response = session.call("point-cloud", &api::PointCloudService::Stub::ListPointCloudSources,
                            api::ListPointCloudSourcesRequest(), "ListPointCloudSources");
  } catch (const SpotError& e) {
    if (e.kind() != SpotError::Kind::kProtocol) throw;  // away: the usual handling
    note = std::string("no point clouds: ") + e.what();
    return "";
  }
  std::string names;
  for (const auto& s : response.point_cloud_sources()) {
    if (setting == "auto" || s.name() == setting) return s.name();
    names += (names.empty() ? "" : ", ") + s.name();
  }
  note = setting == "auto" ? "no point clouds: the robot lists no point-cloud source"
                           : "no point clouds: point_cloud_source '" + setting + "' is not on this robot (it has: " +
                                 (names.empty() ? "none" : names) + ")";
  return "";
}

struct CloudReader::Call {
  grpc::ClientContext context;
  std::unique_ptr<api::PointCloudService::Stub> stub;
  api::GetPointCloudRequest request;
  api::GetPointCloudResponse response;
  bool done = false;
};

CloudReader::CloudReader() = default;
CloudReader::~CloudReader() { cancel(); }

void CloudReader::request(const RobotSession& session, const std::string& source) {
  std::unique_lock lock(mutex_);
  if (call_ && !call_->done) return;  // one out is enough
  call_ = std::make_unique<Call>();
  Call* c = call_.get();
  c->stub = api::PointCloudService::NewStub(session.service_channel("point-cloud"));
  *c->request.mutable_header() = session.request_header();
  auto* r = c->request.add_point_cloud_requests();
  r->set_point_cloud_source_name(source);
  r->set_cloud_type(api::PointCloudRequest::CLOUD_TYPE_POINTS);
  session.prepare(c->context, true);
  lock.unlock();
  c->stub->async()->GetPointCloud(&c->context, &c->request, &c->response, [this, c](grpc::Status status) {
    Answer answer;
    try {
      check_status(status, "GetPointCloud");
      check_header(c->response.header(), "GetPointCloud");
      if (c->response.point_cloud_responses_size() != 1) {
        throw SpotError(SpotError::Kind::kProtocol, "GetPointCloud: " +
                                                        std::to_string(c->response.point_cloud_responses_size()) +
                                                        " answers to one request");
      }
      const auto& one = c->response.point_cloud_responses(0);
      if (one.status() != api::PointCloudResponse::STATUS_OK) {
        throw SpotError(SpotError::Kind::kProtocol, "GetPointCloud: source '" + c->request.point_cloud_requests(0).point_cloud_source_name() +
                                                        "' answered status " + std::to_string(one.status()));
      }
      if (one.has_point_cloud()) {
        answer.cloud = std::make_shared<const api::PointCloud>(one.point_cloud());
      } else if (one.has_lidar_cloud()) {
        answer.cloud = std::make_shared<const api::PointCloud>(one.lidar_cloud().point_cloud());
      }
    } catch (const SpotError& e) {
      answer.problem = e.what();
    }
    std::lock_guard lock(mutex_);
    if (answer.cloud) answer_.cloud = std::move(answer.cloud);
    if (!answer.problem.empty()) answer_.problem = std::move(answer.problem);
    c->done = true;
    done_.notify_all();
  });
}

CloudReader::Answer CloudReader::take() {
  std::lock_guard lock(mutex_);
  return std::exchange(answer_, Answer{});
}

void CloudReader::cancel() {
  std::unique_lock lock(mutex_);
  if (!call_) return;
  if (!call_->done) call_->context.TryCancel();
  done_.wait(lock, [&] { return call_->done; });
  call_.reset();
}

}  // namespace omniview::spot
