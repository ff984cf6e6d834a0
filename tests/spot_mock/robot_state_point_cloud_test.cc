// Robot state (joints, field numbers on the wire) and the lidar's point cloud.
#include <cstring>

#include <google/protobuf/unknown_field_set.h>
#include <google/protobuf/util/time_util.h>

#include "bosdyn/api/point_cloud_service.grpc.pb.h"
#include "bosdyn/api/robot_state_service.grpc.pb.h"
#include "bosdyn/api/time_sync_service.grpc.pb.h"
#include "spot_adapter/mock/world/mock_scene.h"
#include "tests/spot_mock/mock_fixture.h"

namespace omniview::testing {
namespace {

using google::protobuf::UnknownFieldSet;

class SpotMockRobot : public SharedMockTest {
 protected:
  bosdyn::api::RobotStateResponse robot_state() {
    bosdyn::api::RobotStateResponse response;
    const grpc::Status status = bosdyn::api::RobotStateService::NewStub(mock().channel("api.spot.robot"))
                                    ->GetRobotState(spot_context(mock().login()).get(), {}, &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return response;
  }
};

// The bytes of length-delimited field `number` (its first occurrence) of a message in wire
// form, read generically; *count receives how often it occurs.
std::string field_bytes(const std::string& message, int number, int* count = nullptr) {
  UnknownFieldSet fields;
  EXPECT_TRUE(fields.ParseFromString(message));
  std::string out;
  int found = 0;
  for (int i = 0; i < fields.field_count(); ++i) {
    if (fields.field(i).number() != number || fields.field(i).type() != google::protobuf::UnknownField::TYPE_LENGTH_DELIMITED) continue;
    if (found++ == 0) out = fields.field(i).length_delimited();
  }
  if (count) *count = found;
  return out;
}

TEST_F(SpotMockRobot, TwelveStandingJointsAtSpotsFieldNumbers) {
  const auto response = robot_state();
  EXPECT_EQ(response.header().error().code(), bosdyn::api::CommonError::CODE_OK);
  const auto& kin = response.robot_state().kinematic_state();
  ASSERT_EQ(kin.joint_states_size(), 12);
  EXPECT_EQ(kin.joint_states(0).name(), "fl.hx");
  EXPECT_EQ(kin.joint_states(11).name(), "hr.kn");
  for (const auto& j : kin.joint_states()) {
    ASSERT_TRUE(j.has_position()) << j.name();
    const double standing = j.name().ends_with(".hy") ? 0.8 : j.name().ends_with(".kn") ? -1.6 : 0.0;
    EXPECT_NEAR(j.position().value(), standing, 1e-9) << j.name();
  }
  EXPECT_TRUE(kin.transforms_snapshot().child_to_parent_edge_map().count("gpe"));

  // RobotStateResponse.robot_state = 2 -> RobotState.kinematic_state = 6 ->
  // KinematicState.joint_states = 2 (repeated) -> JointState.name = 1: read without our protos.
  int joints = 0;
  const std::string kinematic_state = field_bytes(field_bytes(response.SerializeAsString(), 2), 6);
  const std::string first_joint = field_bytes(kinematic_state, 2, &joints);
  EXPECT_EQ(joints, 12);
  EXPECT_EQ(field_bytes(first_joint, 1), "fl.hx");
}

// Time sync as the robot does it: the client reports each round trip with the next call;
// after a few the robot calls its estimate good. This mock's clock is this machine's, so
// the skew is within a round trip of zero.
TEST_F(SpotMockRobot, TimeSyncNeedsAFewRoundTripsThenEstimatesTheSkew) {
  namespace api = bosdyn::api;
  const auto stub = api::TimeSyncService::NewStub(mock().channel("api.spot.robot"));
  const std::string token = mock().login();
  const auto now = [] {
    return google::protobuf::util::TimeUtil::NanosecondsToTimestamp(
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
            .count());
  };
  api::TimeSyncRoundTrip previous;
  std::string clock;
  api::TimeSyncUpdateResponse response;
  for (int i = 0; i < 4; ++i) {
    api::TimeSyncUpdateRequest request;
    if (i > 0) *request.mutable_previous_round_trip() = previous;
    request.set_clock_identifier(clock);
    const auto sent = now();
    ASSERT_TRUE(stub->TimeSyncUpdate(spot_context(token).get(), request, &response).ok());
    previous.Clear();
    *previous.mutable_client_tx() = sent;
    *previous.mutable_server_rx() = response.header().request_received_timestamp();
    *previous.mutable_server_tx() = response.header().response_timestamp();
    *previous.mutable_client_rx() = now();
    if (i > 0) {
      EXPECT_EQ(response.clock_identifier(), clock) << "the robot keeps the identifier it gave";
    }
    clock = response.clock_identifier();
    EXPECT_EQ(response.state().status(), i < 3 ? api::TimeSyncState::STATUS_MORE_SAMPLES_NEEDED
                                               : api::TimeSyncState::STATUS_OK)
        << "exchange " << i;
  }
  EXPECT_FALSE(clock.empty());
  const auto& best = response.state().best_estimate();
  const int64_t skew = google::protobuf::util::TimeUtil::DurationToNanoseconds(best.clock_skew());
  const int64_t rtt = google::protobuf::util::TimeUtil::DurationToNanoseconds(best.round_trip_time());
  EXPECT_GE(rtt, 0);
  EXPECT_LE(std::abs(skew), rtt / 2 + 1000000) << "skew " << skew << " ns, round trip " << rtt << " ns";
  // Without a token, as every api.spot.robot service.
  EXPECT_EQ(stub->TimeSyncUpdate(spot_context("").get(), {}, &response).error_code(), grpc::StatusCode::UNAUTHENTICATED);
}

TEST_F(SpotMockRobot, ControlServiceMovesJoints) {
  const auto out = mock().control("--joint fl.kn=-1.2 --joint hr.hx=0.1");
  ASSERT_EQ(out.exit_code, 0) << out.text;
  std::map<std::string, double> angles;
  const auto state = robot_state();
  for (const auto& j : state.robot_state().kinematic_state().joint_states()) angles[j.name()] = j.position().value();
  EXPECT_NEAR(angles.at("fl.kn"), -1.2, 1e-12);
  EXPECT_NEAR(angles.at("hr.hx"), 0.1, 1e-12);
  EXPECT_NEAR(angles.at("fr.kn"), -1.6, 1e-12);

  spotmock::v1::SetJointAnglesRequest standing;
  (*standing.mutable_positions())["fl.kn"] = -1.6;
  (*standing.mutable_positions())["hr.hx"] = 0;
  spotmock::v1::SetJointAnglesResponse now;
  ASSERT_TRUE(control()->SetJointAngles(spot_context().get(), standing, &now).ok());
  EXPECT_EQ(now.positions().size(), 12u);
  (*standing.mutable_positions())["xx.kn"] = 1;
  EXPECT_EQ(control()->SetJointAngles(spot_context().get(), standing, &now).error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
}

TEST_F(SpotMockRobot, LidarPointsLieOnTheTestScene) {
  auto stub = bosdyn::api::PointCloudService::NewStub(mock().channel("api.spot.robot"));
  const std::string token = mock().login();
  bosdyn::api::ListPointCloudSourcesResponse sources;
  ASSERT_TRUE(stub->ListPointCloudSources(spot_context(token).get(), {}, &sources).ok());
  ASSERT_EQ(sources.point_cloud_sources_size(), 1);
  const std::string name = sources.point_cloud_sources(0).name();

  bosdyn::api::GetPointCloudRequest request;
  request.add_point_cloud_requests()->set_point_cloud_source_name(name);
  request.add_point_cloud_requests()->set_point_cloud_source_name("no-such-lidar");
  bosdyn::api::GetPointCloudResponse response;
  ASSERT_TRUE(stub->GetPointCloud(spot_context(token).get(), request, &response).ok());
  ASSERT_EQ(response.point_cloud_responses_size(), 2);
  EXPECT_EQ(response.point_cloud_responses(1).status(), bosdyn::api::PointCloudResponse::STATUS_UNKNOWN_SOURCE);
  const auto& answer = response.point_cloud_responses(0);
  ASSERT_EQ(answer.status(), bosdyn::api::PointCloudResponse::STATUS_OK);
  const auto& cloud = answer.point_cloud();
  EXPECT_EQ(cloud.encoding(), bosdyn::api::PointCloud::ENCODING_XYZ_32F);
  ASSERT_EQ(cloud.data().size(), 12u * cloud.num_points());
  // The test scene: the floor below, the wall ahead; the upper rings miss both.
  EXPECT_GT(cloud.num_points(), spot_mock::kLidarRings * spot_mock::kLidarPointsPerRing / 3);
  EXPECT_LT(cloud.num_points(), spot_mock::kLidarRings * spot_mock::kLidarPointsPerRing);

  const Pose T_vision_lidar =
      to_frame_graph(cloud.source().transforms_snapshot()).lookup("vision", cloud.source().frame_name_sensor());
  int on_floor = 0, on_wall = 0;
  for (int i = 0; i < cloud.num_points(); ++i) {
    float xyz[3];
    std::memcpy(xyz, cloud.data().data() + 12 * i, sizeof xyz);  // little-endian host
    const Vec3 p = T_vision_lidar * Vec3(xyz[0], xyz[1], xyz[2]);
    if (std::abs(p.z()) < 1e-3) {
      ++on_floor;
    } else if (std::abs(p.x() - spot_mock::kTestWallX) < 1e-3 && p.z() > 0) {
      ++on_wall;
    } else {
      ADD_FAILURE() << "point " << i << " (" << p.transpose() << ") is on neither the floor nor the wall";
      break;
    }
  }
  EXPECT_GT(on_floor, 1000);
  EXPECT_GT(on_wall, 100);
}

}  // namespace
}  // namespace omniview::testing
