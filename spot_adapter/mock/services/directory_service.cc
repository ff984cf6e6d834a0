#include "spot_adapter/mock/services/directory_service.h"

#include "spot_adapter/mock/services/call_gate.h"
#include "spot_adapter/mock/wire/spot_messages.h"

namespace omniview::spot_mock {
namespace {

struct Listing {
  const char* name;
  const char* type;
  const char* authority;
  bool token_required;
};

// As on a real Spot: auth and robot-id on their bootstrap authorities, the rest behind api.
constexpr Listing kListings[] = {
    {"auth", "bosdyn.api.AuthService", "auth.spot.robot", false},
    {"directory", "bosdyn.api.DirectoryService", "api.spot.robot", true},
    {"robot-id", "bosdyn.api.RobotIdService", "id.spot.robot", false},
    {"image", "bosdyn.api.ImageService", "api.spot.robot", true},
    {"point-cloud", "bosdyn.api.PointCloudService", "api.spot.robot", true},
    {"robot-state", "bosdyn.api.RobotStateService", "api.spot.robot", true},
    {"time-sync", "bosdyn.api.TimeSyncService", "api.spot.robot", true},
};

}  // namespace

DirectoryService::DirectoryService(MockRobot& robot) : robot_(robot) {
  for (const Listing& l : kListings) {
    bosdyn::api::ServiceEntry& e = entries_.emplace_back();
    e.set_name(l.name);
    e.set_type(l.type);
    e.set_authority(l.authority);
    *e.mutable_last_update() = to_timestamp(robot.started);
    e.set_user_token_required(l.token_required);
  }
}

grpc::Status DirectoryService::GetServiceEntry(grpc::ServerContext* ctx,
                                               const bosdyn::api::GetServiceEntryRequest* request,
                                               bosdyn::api::GetServiceEntryResponse* response) {
  if (auto status = admit_call(robot_, *ctx, Token::kRequired); !status.ok()) return status;
  const ReturnTrip return_trip(robot_);  // the answer travels back after it is stamped
  const auto received = now_timestamp();
  fill_response_header(request->header(), received, response->mutable_header());
  response->set_status(bosdyn::api::GetServiceEntryResponse::STATUS_NONEXISTENT_SERVICE);
  for (const auto& e : entries_) {
    if (e.name() != request->service_name()) continue;
    response->set_status(bosdyn::api::GetServiceEntryResponse::STATUS_OK);
    *response->mutable_service_entry() = e;
  }
  return grpc::Status::OK;
}

grpc::Status DirectoryService::ListServiceEntries(grpc::ServerContext* ctx,
                                                  const bosdyn::api::ListServiceEntriesRequest* request,
                                                  bosdyn::api::ListServiceEntriesResponse* response) {
  if (auto status = admit_call(robot_, *ctx, Token::kRequired); !status.ok()) return status;
  const ReturnTrip return_trip(robot_);  // the answer travels back after it is stamped
  const auto received = now_timestamp();
  fill_response_header(request->header(), received, response->mutable_header());
  for (const auto& e : entries_) *response->add_service_entries() = e;
  return grpc::Status::OK;
}

}  // namespace omniview::spot_mock
