#include "server/web/console/api_calls.h"

#include <grpcpp/server_context.h>

#include "server/auth/permissions.h"
#include "server/status/failure.h"
#include "server/web/json/json.h"

namespace omniview::web {

namespace {

// One unary call: JSON in, the service's method, JSON out.
template <class Request, class Response, class Service>
std::function<ApiCalls::Result(const std::string&)> unary(
    Service& service, grpc::Status (Service::*method)(grpc::ServerContext*, const Request*, Response*)) {
  return [&service, method](const std::string& text) -> ApiCalls::Result {
    Request request;
    if (!text.empty()) {
      if (const auto error = json::text_to_message(text, request); !error.empty()) {
        return {grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                             "request is not a " + Request::descriptor()->full_name() + ": " + error),
                ""};
      }
    }
    Response response;
    grpc::ServerContext context;  // no call behind it: metadata empty, never cancelled
    const grpc::Status status = (service.*method)(&context, &request, &response);
    if (!status.ok()) return {status, ""};
    return {status, json::message_to_text(response)};
  };
}

}  // namespace

ApiCalls::ApiCalls(Pipeline& pipeline, const Limits& limits) : open_({}), service_(pipeline, open_, limits) {
  using S = OmniviewService;
  // Each with the RPC's own role (server/auth/permissions.h).
  const auto add = [this](const char* name, auto run) { methods_[name] = {permissions::rpc_role(name), run}; };
  add("ListCameras", unary(service_, &S::ListCameras));
  add("ListViews", unary(service_, &S::ListViews));
  add("GetView", unary(service_, &S::GetView));
  add("PixelToRay", unary(service_, &S::PixelToRay));
  add("PointToPixel", unary(service_, &S::PointToPixel));
  add("GetStatus", unary(service_, &S::GetStatus));
  add("GetJointPositions", unary(service_, &S::GetJointPositions));
  add("CreateView", unary(service_, &S::CreateView));
  add("UpdateView", unary(service_, &S::UpdateView));
  add("DeleteView", unary(service_, &S::DeleteView));
  add("SetJointPositions", unary(service_, &S::SetJointPositions));
}

std::optional<Role> ApiCalls::role_of(const std::string& method) const {
  const auto it = methods_.find(method);
  if (it == methods_.end()) return std::nullopt;
  return it->second.role;
}

std::vector<std::string> ApiCalls::methods() const {
  std::vector<std::string> names;
  for (const auto& [name, m] : methods_) names.push_back(name);
  return names;
}

ApiCalls::Result ApiCalls::call(const std::string& method, const std::string& request) const {
  const auto it = methods_.find(method);
  if (it == methods_.end()) {
    return {grpc::Status(grpc::StatusCode::UNIMPLEMENTED, "no method '" + method + "' on the web endpoint"), ""};
  }
  try {
    return it->second.run(request);
  } catch (...) {
    return {grpc_status(current_failure()), ""};
  }
}

}  // namespace omniview::web
