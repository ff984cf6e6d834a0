// The gRPC API's unary calls for web clients: the console's PTZ drag is an UpdateView,
// its tap-to-look a PixelToRay, exactly as a gRPC client's. Requests and responses are
// the API's own messages in proto3 JSON.
//
// The calls go through an OmniviewService of their own (the same code, checks and
// messages as the gRPC port) that lets every call in: the web endpoint has already checked
// the caller's token and role (role_of) before it calls.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <grpcpp/support/status.h>

#include "server/api/omniview_service.h"

namespace omniview::web {

class ApiCalls {
 public:
  ApiCalls(Pipeline& pipeline, const Limits& limits);

  // The role `method` needs ("UpdateView": operator); nullopt for a method not served here.
  std::optional<Role> role_of(const std::string& method) const;
  std::vector<std::string> methods() const;

  struct Result {
    grpc::Status status;
    std::string response;  // proto3 JSON of the response when status is OK
  };
  // Runs `method` (served here: see role_of) with `request` (proto3 JSON of its request
  // message; "" or "{}" for an empty one). May block while a view's map is rebuilt.
  Result call(const std::string& method, const std::string& request) const;

 private:
  struct Method {
    Role role;
    std::function<Result(const std::string&)> run;
  };
  const Authenticator open_;  // no tokens: the role was checked before the call
  mutable OmniviewService service_;
  std::map<std::string, Method> methods_;
};

}  // namespace omniview::web
