#include "server/auth/permissions.h"

#include <stdexcept>
#include <string>

namespace omniview::permissions {

const std::vector<Permission>& all() {
  // Reading views, frames, clouds, status and joints is a viewer's; changing views or joints
  // is an operator's.
  static const std::vector<Permission> table = {
      {"omniview.v1.Omniview/ListCameras", Role::kViewer},
      {"omniview.v1.Omniview/CreateView", Role::kOperator},
      {"omniview.v1.Omniview/GetView", Role::kViewer},
      {"omniview.v1.Omniview/ListViews", Role::kViewer},
      {"omniview.v1.Omniview/UpdateView", Role::kOperator},
      {"omniview.v1.Omniview/DeleteView", Role::kOperator},
      {"omniview.v1.Omniview/StreamFrames", Role::kViewer},
      {"omniview.v1.Omniview/GetSnapshot", Role::kViewer},
      {"omniview.v1.Omniview/PixelToRay", Role::kViewer},
      {"omniview.v1.Omniview/PointToPixel", Role::kViewer},
      {"omniview.v1.Omniview/GetStatus", Role::kViewer},
      {"omniview.v1.Omniview/SetJointPositions", Role::kOperator},
      {"omniview.v1.Omniview/SaveBlackBox", Role::kOperator},
      {"omniview.v1.Omniview/GetJointPositions", Role::kViewer},
      {"omniview.v1.Omniview/StreamSourceFrames", Role::kViewer},
      {"omniview.v1.Omniview/StreamClouds", Role::kViewer},
      {"omniview.v1.Omniview/GetCloud", Role::kViewer},
      // The console's WebSocket: after `auth` (any valid token), `call` is the called RPC's
      // role; the streams are a viewer's.
      {"console:auth", Role::kViewer},
      {"console:call", Role::kViewer},  // and the called RPC's own role
      {"console:subscribe", Role::kViewer},
      {"console:subscribe_cloud", Role::kViewer},
      {"console:unsubscribe", Role::kViewer},
      // Foxglove's WebSocket protocol only reads (views' images and video, clouds).
      {"foxglove", Role::kViewer},
      // RTSP only plays views.
      {"rtsp", Role::kViewer},
      // WHEP (WebRTC): a viewer watches, and ends its own session.
      {"whep:POST", Role::kViewer},
      {"whep:DELETE", Role::kViewer},
  };
  return table;
}

std::optional<Role> role_for(std::string_view request) {
  for (const auto& p : all()) {
    if (p.request == request) return p.role;
  }
  return std::nullopt;
}

Role rpc_role(std::string_view method) {
  const auto role = role_for(std::string(kServicePrefix) + std::string(method));
  if (!role) throw std::logic_error("no role for RPC " + std::string(method) + " (server/auth/permissions.cc)");
  return *role;
}

}  // namespace omniview::permissions
