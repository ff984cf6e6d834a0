// One spot-mock shared by the tests of this program (its start-up render is the slow part,
// and CI runs these under the sanitizers): the bare-textured test scene, rendered with one
// ray per pixel so a test can recompute any pixel exactly. Tests that change the mock's
// state (faults) put it back in TearDown.
#pragma once

#include <gtest/gtest.h>

#include "bosdyn/api/geometry.pb.h"
#include "core/geometry/frame_graph.h"
#include "omniview/spotmock/v1/control.grpc.pb.h"
#include "tests/spot_mock/spot_mock_process.h"

namespace omniview::testing {

inline constexpr int kSharedTokenLifetimeS = 3600;
inline constexpr int kSharedLockoutS = 1;

// Started on first use: --scene test --supersample 1 --token-lifetime-s 3600 --lockout-s 1.
SpotMockProcess& shared_mock();

class SharedMockTest : public ::testing::Test {
 protected:
  void SetUp() override { mock_ = &shared_mock(); }
  void TearDown() override;  // clears every fault

  SpotMockProcess& mock() { return *mock_; }
  std::unique_ptr<spotmock::v1::SpotMockControl::Stub> control();
  spotmock::v1::Faults set_faults(const spotmock::v1::Faults& faults);
  spotmock::v1::Counters counters(bool reset = false);

 private:
  SpotMockProcess* mock_ = nullptr;
};

// The frame tree as a client sees it (key = child, the root's parent empty).
Pose to_pose(const bosdyn::api::SE3Pose& pose);
FrameGraph to_frame_graph(const bosdyn::api::FrameTreeSnapshot& snapshot);

}  // namespace omniview::testing
