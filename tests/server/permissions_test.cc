// The one table of who may do what (server/auth/permissions.h) covers every way in: each
// RPC of the service as its descriptor lists them, each console op, Foxglove and RTSP; and
// lists nothing that does not exist.
#include "server/auth/permissions.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "omniview/v1/omniview.pb.h"
#include "server/web/console/console_protocol.h"
#include "server/webrtc/whep_server.h"

namespace omniview::testing {
namespace {

TEST(Permissions, EveryRpcOfTheServiceHasARoleAndEveryListedRpcExists) {
  const auto* service = v1::ListCamerasRequest::descriptor()->file()->FindServiceByName("Omniview");
  ASSERT_NE(service, nullptr);
  std::set<std::string> rpcs;
  for (int i = 0; i < service->method_count(); ++i) {
    const std::string name = service->method(i)->name();
    rpcs.insert(name);
    EXPECT_TRUE(permissions::role_for(std::string(permissions::kServicePrefix) + name).has_value()) << name;
    EXPECT_NO_THROW(permissions::rpc_role(name)) << name;
  }
  for (const auto& p : permissions::all()) {
    if (p.request.substr(0, permissions::kServicePrefix.size()) != permissions::kServicePrefix) continue;
    EXPECT_TRUE(rpcs.count(std::string(p.request.substr(permissions::kServicePrefix.size())))) << p.request;
  }
  EXPECT_THROW(permissions::rpc_role("NoSuchRpc"), std::logic_error);
}

TEST(Permissions, WhatChangesTheRobotsViewsIsAnOperatorsTheRestAViewers) {
  for (const char* rpc : {"CreateView", "UpdateView", "DeleteView", "SetJointPositions", "SaveBlackBox"}) {
    EXPECT_EQ(permissions::rpc_role(rpc), Role::kOperator) << rpc;
  }
  for (const auto& p : permissions::all()) {
    const std::string request(p.request);
    if (request.find("View") != std::string::npos && request.find("Get") == std::string::npos &&
        request.find("List") == std::string::npos) {
      continue;  // the view-changing RPCs above
    }
    if (request == "omniview.v1.Omniview/SetJointPositions" || request == "omniview.v1.Omniview/SaveBlackBox") continue;
    EXPECT_EQ(p.role, Role::kViewer) << request;
  }
}

TEST(Permissions, EveryConsoleOpFoxgloveRtspAndWhepRequestAreListed) {
  for (const char* op : web::kConsoleOps) {
    EXPECT_TRUE(permissions::role_for(std::string("console:") + op).has_value()) << op;
  }
  EXPECT_TRUE(permissions::role_for("foxglove").has_value());
  EXPECT_TRUE(permissions::role_for("rtsp").has_value());
  for (const char* request : webrtc::kWhepRequests) {
    EXPECT_TRUE(permissions::role_for(std::string("whep:") + request).has_value()) << request;
  }
  std::set<std::string> ops(std::begin(web::kConsoleOps), std::end(web::kConsoleOps));
  for (const auto& p : permissions::all()) {
    if (p.request.substr(0, 8) == "console:") {
      EXPECT_TRUE(ops.count(std::string(p.request.substr(8)))) << p.request;
    }
  }
}

}  // namespace
}  // namespace omniview::testing
