// Bearer tokens with two roles (docs/API.md, "Connecting and roles"): each call sends
// `authorization: Bearer <token>`; a viewer token may stream and read, an operator token
// may also create, update and delete views. With no tokens configured every caller is an
// operator (the config only allows that on loopback, or with allow_insecure_remote).
#pragma once

#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <grpcpp/server_context.h>
#include <grpcpp/support/status.h>

#include "server/auth/refusal_log.h"
#include "server/config/daemon_config.h"

namespace omniview {

// Who a call came from, once authenticated: for logs and per-client accounting. Never
// the secret.
struct Caller {
  Role role = Role::kOperator;
  std::string label;  // the token's label ("tokens[1] (operator.token)"); empty without tokens
};

class Authenticator {
 public:
  explicit Authenticator(std::vector<TokenConfig> tokens);

  // Whether tokens are required at all.
  bool enabled() const { return !tokens_.empty(); }

  // OK, UNAUTHENTICATED or PERMISSION_DENIED for a call that needs `needed`; `caller`
  // (optional) receives the identity on success. With tokens configured, logs refusals
  // (at most a few per peer host every 10 s, then how many were left out: RefusalLog)
  // and a peer's first call with each token, by the token's label: never its value.
  grpc::Status check(const grpc::ServerContext& ctx, Role needed, Caller* caller = nullptr) const;

  // The same decision from the `authorization` header values the call carried (none,
  // one, or several): pure, for unit tests.
  grpc::Status check_header(const std::vector<std::string_view>& authorization, Role needed,
                            Caller* caller = nullptr) const;
  grpc::Status check_header(std::optional<std::string_view> authorization, Role needed,
                            Caller* caller = nullptr) const;

 private:
  const TokenConfig* find(std::string_view token) const;
  void log(const grpc::ServerContext& ctx, const grpc::Status& status, const Caller& caller) const;
  std::vector<TokenConfig> tokens_;
  mutable std::mutex logged_mutex_;
  mutable std::set<std::string> logged_;  // "peer|label" already logged as authenticated
  mutable RefusalLog refusals_;
};

// The token in "Bearer <token>" (scheme case-insensitive, as RFC 6750 allows); nullopt
// when the value has another shape.
std::optional<std::string_view> bearer_token(std::string_view header_value);

// Compares in time that depends on the lengths only, never on where the first difference is.
bool constant_time_equals(std::string_view a, std::string_view b);

}  // namespace omniview
