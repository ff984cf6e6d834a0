#include "server/auth/authenticator.h"

#include <algorithm>
#include <cctype>
#include <iostream>

namespace omniview {
namespace {

constexpr char kMalformed[] =
    "missing or malformed authorization metadata: send 'authorization: Bearer <token>'";

bool is_space(char c) { return c == ' ' || c == '\t'; }

}  // namespace

std::optional<std::string_view> bearer_token(std::string_view value) {
  constexpr std::string_view kScheme = "bearer";
  if (value.size() <= kScheme.size() || !is_space(value[kScheme.size()])) return std::nullopt;
  for (size_t i = 0; i < kScheme.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(value[i])) != kScheme[i]) return std::nullopt;
  }
  value.remove_prefix(kScheme.size());
  while (!value.empty() && is_space(value.front())) value.remove_prefix(1);
  while (!value.empty() && is_space(value.back())) value.remove_suffix(1);
  if (value.empty() || std::any_of(value.begin(), value.end(), is_space)) return std::nullopt;
  return value;
}

bool constant_time_equals(std::string_view a, std::string_view b) {
  // Every byte of the longer one is visited and differences are OR-ed, so the loop cannot
  // stop early at the first mismatch; volatile keeps the compiler from adding that exit.
  const size_t n = std::max(a.size(), b.size());
  volatile unsigned char diff = a.size() == b.size() ? 0 : 1;
  for (size_t i = 0; i < n; ++i) {
    const unsigned char x = i < a.size() ? static_cast<unsigned char>(a[i]) : 0;
    const unsigned char y = i < b.size() ? static_cast<unsigned char>(b[i]) : 0;
    diff = diff | static_cast<unsigned char>(x ^ y);
  }
  return diff == 0;
}

Authenticator::Authenticator(std::vector<TokenConfig> tokens) : tokens_(std::move(tokens)) {}

const TokenConfig* Authenticator::find(std::string_view token) const {
  // Compare against every token, matched or not, so timing does not tell which one matched.
  const TokenConfig* match = nullptr;
  for (const auto& t : tokens_) {
    if (constant_time_equals(t.token, token)) match = &t;
  }
  return match;
}

grpc::Status Authenticator::check_header(const std::vector<std::string_view>& values, Role needed,
                                         Caller* caller) const {
  if (!enabled()) {
    if (caller) *caller = Caller{Role::kOperator, ""};
    return grpc::Status::OK;
  }
  // Two authorization headers are ambiguous (which one did a proxy add?): refuse both.
  if (values.size() != 1) return {grpc::StatusCode::UNAUTHENTICATED, kMalformed};
  const auto token = bearer_token(values.front());
  if (!token) return {grpc::StatusCode::UNAUTHENTICATED, kMalformed};
  const TokenConfig* match = find(*token);
  if (!match) return {grpc::StatusCode::UNAUTHENTICATED, "unknown token"};
  if (!role_allows(match->role, needed)) {
    return {grpc::StatusCode::PERMISSION_DENIED,
            "this call needs the " + to_string(needed) + " role; the token given is a " + to_string(match->role) +
                " token"};
  }
  if (caller) *caller = Caller{match->role, match->label};
  return grpc::Status::OK;
}

grpc::Status Authenticator::check_header(std::optional<std::string_view> value, Role needed, Caller* caller) const {
  std::vector<std::string_view> values;
  if (value) values.push_back(*value);
  return check_header(values, needed, caller);
}

grpc::Status Authenticator::check(const grpc::ServerContext& ctx, Role needed, Caller* caller) const {
  std::vector<std::string_view> values;
  const auto [begin, end] = ctx.client_metadata().equal_range("authorization");
  for (auto it = begin; it != end; ++it) values.emplace_back(it->second.data(), it->second.size());
  Caller who;
  const grpc::Status status = check_header(values, needed, &who);
  if (status.error_code() == grpc::StatusCode::PERMISSION_DENIED && values.size() == 1) {
    if (const auto token = bearer_token(values.front())) {
      if (const TokenConfig* match = find(*token)) who.label = match->label;
    }
  }
  if (enabled()) log(ctx, status, who);
  if (caller && status.ok()) *caller = who;
  return status;
}

void Authenticator::log(const grpc::ServerContext& ctx, const grpc::Status& status, const Caller& caller) const {
  const std::string peer = ctx.peer();
  if (!status.ok()) {
    const auto left_out = refusals_.admit(peer);
    if (!left_out) return;
    std::cerr << "omniviewd: refused a call from " << peer
              << (caller.label.empty() ? "" : " with " + caller.label) << ": " << status.error_message()
              << (*left_out ? " (and " + std::to_string(*left_out) + " more refusals from this host not logged)" : "")
              << std::endl;
    return;
  }
  // Once per peer and token: a joystick's 30 updates a second would drown the log.
  {
    std::lock_guard lock(logged_mutex_);
    if (logged_.size() > 4096) logged_.clear();  // bounded, whatever the number of clients
    if (!logged_.insert(peer + "|" + caller.label).second) return;
  }
  std::cerr << "omniviewd: " << peer << " authenticated with " << caller.label << " (" << to_string(caller.role)
            << ")" << std::endl;
}

}  // namespace omniview
