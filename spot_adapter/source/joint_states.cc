#include "spot_adapter/source/joint_states.h"

#include <cmath>
#include <utility>

#include "spot_adapter/client/spot_error.h"

namespace omniview::spot {

namespace api = bosdyn::api;

std::shared_ptr<const JointMap> joints_from_robot_state(const api::RobotStateResponse& response) {
  check_header(response.header(), "GetRobotState");
  auto joints = std::make_shared<JointMap>();
  for (const auto& j : response.robot_state().kinematic_state().joint_states()) {
    if (!j.name().empty() && j.has_position() && std::isfinite(j.position().value())) {
      (*joints)[j.name()] = j.position().value();
    }
  }
  return joints;
}

std::shared_ptr<const JointMap> read_joint_states(RobotSession& session) {
  return joints_from_robot_state(session.call("robot-state", &api::RobotStateService::Stub::GetRobotState,
                                               api::RobotStateRequest(), "GetRobotState"));
}

struct JointStateReader::Call {
  grpc::ClientContext context;
  std::unique_ptr<api::RobotStateService::Stub> stub;
  api::RobotStateRequest request;
  api::RobotStateResponse response;
  bool done = false;
};

JointStateReader::JointStateReader() = default;
JointStateReader::~JointStateReader() { cancel(); }

void JointStateReader::request(const RobotSession& session) {
  std::unique_lock lock(mutex_);
  if (call_ && !call_->done) return;  // one out is enough
  call_ = std::make_unique<Call>();
  Call* c = call_.get();
  c->stub = api::RobotStateService::NewStub(session.service_channel("robot-state"));
  *c->request.mutable_header() = session.request_header();
  session.prepare(c->context, true);
  lock.unlock();
  c->stub->async()->GetRobotState(&c->context, &c->request, &c->response, [this, c](grpc::Status status) {
    Answer answer;
    try {
      check_status(status, "GetRobotState");
      answer.joints = joints_from_robot_state(c->response);
    } catch (const SpotError& e) {
      // A robot away or slow shows in the image calls; only a refusal is news here.
      if (e.kind() == SpotError::Kind::kProtocol) answer.refusal = e.what();
    }
    std::lock_guard lock(mutex_);
    if (answer.joints) answer_.joints = std::move(answer.joints);
    if (!answer.refusal.empty()) answer_.refusal = std::move(answer.refusal);
    c->done = true;
    done_.notify_all();
  });
}

JointStateReader::Answer JointStateReader::take() {
  std::lock_guard lock(mutex_);
  return std::exchange(answer_, Answer{});
}

void JointStateReader::cancel() {
  std::unique_lock lock(mutex_);
  if (!call_) return;
  if (!call_->done) call_->context.TryCancel();
  done_.wait(lock, [&] { return call_->done; });
  call_.reset();
}

}  // namespace omniview::spot
