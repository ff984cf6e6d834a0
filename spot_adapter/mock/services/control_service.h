// omniview.spotmock.v1.SpotMockControl: faults, token expiry, joint angles and counters,
// changed by tests and demos at run time. Needs no token and ignores the faults itself, so
// a mock that is "away" can still be brought back.
#pragma once

#include "omniview/spotmock/v1/control.grpc.pb.h"
#include "spot_adapter/mock/services/mock_robot.h"

namespace omniview::spot_mock {

class ControlService final : public omniview::spotmock::v1::SpotMockControl::Service {
 public:
  explicit ControlService(MockRobot& robot) : robot_(robot) {}
  grpc::Status SetFaults(grpc::ServerContext* ctx, const spotmock::v1::SetFaultsRequest* request,
                         spotmock::v1::SetFaultsResponse* response) override;
  grpc::Status GetFaults(grpc::ServerContext* ctx, const spotmock::v1::GetFaultsRequest* request,
                         spotmock::v1::GetFaultsResponse* response) override;
  grpc::Status ExpireTokens(grpc::ServerContext* ctx, const spotmock::v1::ExpireTokensRequest* request,
                            spotmock::v1::ExpireTokensResponse* response) override;
  grpc::Status SetJointAngles(grpc::ServerContext* ctx, const spotmock::v1::SetJointAnglesRequest* request,
                              spotmock::v1::SetJointAnglesResponse* response) override;
  grpc::Status GetCounters(grpc::ServerContext* ctx, const spotmock::v1::GetCountersRequest* request,
                           spotmock::v1::GetCountersResponse* response) override;

 private:
  MockRobot& robot_;
};

}  // namespace omniview::spot_mock
