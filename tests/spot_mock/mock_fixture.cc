#include "tests/spot_mock/mock_fixture.h"

#include <memory>

#include "tests/server/daemon_process.h"

namespace omniview::testing {
namespace {

struct Shared {
  std::unique_ptr<TempDir> dir;
  std::unique_ptr<SpotMockProcess> mock;
};
Shared& shared() {
  static Shared s;
  return s;
}

// Stops the shared mock before the program's statics go away.
class SharedMockEnvironment : public ::testing::Environment {
 public:
  void TearDown() override {
    shared().mock.reset();
    shared().dir.reset();
  }
};
const auto* const kEnvironment = ::testing::AddGlobalTestEnvironment(new SharedMockEnvironment);

}  // namespace

SpotMockProcess& shared_mock() {
  Shared& s = shared();
  if (!s.mock) {
    s.dir = std::make_unique<TempDir>();
    s.mock = std::make_unique<SpotMockProcess>(
        s.dir->path(), std::vector<std::string>{"--scene", "test", "--supersample", "1", "--token-lifetime-s",
                                                std::to_string(kSharedTokenLifetimeS), "--lockout-s",
                                                std::to_string(kSharedLockoutS)});
  }
  return *s.mock;
}

void SharedMockTest::TearDown() {
  spotmock::v1::Faults none;
  none.set_latency_ms(0);
  none.set_fail_probability(0);
  none.set_image_error_probability(0);
  none.set_corrupt_probability(0);
  none.set_wrong_size_probability(0);
  none.set_away(false);
  set_faults(none);
}

std::unique_ptr<spotmock::v1::SpotMockControl::Stub> SharedMockTest::control() {
  return spotmock::v1::SpotMockControl::NewStub(mock().channel("api.spot.robot"));
}

spotmock::v1::Faults SharedMockTest::set_faults(const spotmock::v1::Faults& faults) {
  spotmock::v1::SetFaultsRequest request;
  *request.mutable_faults() = faults;
  spotmock::v1::SetFaultsResponse response;
  const grpc::Status status = control()->SetFaults(spot_context().get(), request, &response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return response.faults();
}

spotmock::v1::Counters SharedMockTest::counters(bool reset) {
  spotmock::v1::GetCountersRequest request;
  request.set_reset(reset);
  spotmock::v1::GetCountersResponse response;
  const grpc::Status status = control()->GetCounters(spot_context().get(), request, &response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return response.counters();
}

Pose to_pose(const bosdyn::api::SE3Pose& pose) {
  Pose out = Pose::Identity();
  out.translation() = Vec3(pose.position().x(), pose.position().y(), pose.position().z());
  const auto& q = pose.rotation();
  out.linear() = Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()).normalized().toRotationMatrix();
  return out;
}

FrameGraph to_frame_graph(const bosdyn::api::FrameTreeSnapshot& snapshot) {
  FrameGraph graph;
  for (const auto& [child, edge] : snapshot.child_to_parent_edge_map()) {
    if (!edge.parent_frame_name().empty()) graph.set_parent(child, edge.parent_frame_name(), to_pose(edge.parent_tform_child()));
  }
  return graph;
}

}  // namespace omniview::testing
