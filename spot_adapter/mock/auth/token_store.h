// Logins and the tokens they earn, as Spot's auth service behaves: JWT-shaped tokens with a
// lifetime, refresh with a valid token, and a lock after repeated bad logins.
//
// Tokens are only valid if this store issued them (they are looked up, never verified), so
// expire_all() can revoke every token at once.
#pragma once

#include <chrono>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "spot_adapter/mock/auth/credentials.h"

namespace omniview::spot_mock {

enum class LoginResult { kOk, kInvalidLogin, kLockedOut };

class TokenStore {
 public:
  struct Policy {
    std::chrono::seconds token_lifetime{43200};
    std::chrono::seconds lockout{60};
    int failures_before_lockout = 6;  // consecutive
  };
  TokenStore(Credentials credentials, Policy policy);

  // Username and password: on kOk, *token receives a fresh token.
  LoginResult login(const std::string& username, const std::string& password, std::string* token);
  // A fresh token for a valid one; nullopt if `old_token` is not valid.
  std::optional<std::string> refresh(const std::string& old_token);
  bool valid(const std::string& token) const;
  // Revokes every token issued so far; returns how many were still valid.
  size_t expire_all();

 private:
  using Clock = std::chrono::system_clock;  // exp/iat are Unix seconds
  std::string issue_locked(const std::string& subject);
  bool valid_locked(const std::string& token) const;

  const Credentials credentials_;
  const Policy policy_;
  mutable std::mutex mutex_;
  std::map<std::string, Clock::time_point> expiry_;  // token -> when it expires
  int consecutive_failures_ = 0;
  std::chrono::steady_clock::time_point locked_until_{};
};

// The claims of a token in the mock's format (tests check the lifetime): nullopt if it is
// not three dot-separated base64url segments with a JSON payload holding these numbers.
struct TokenClaims {
  long long iat = 0, exp = 0;
  std::string sub;
};
std::optional<TokenClaims> decode_token_claims(const std::string& token);

}  // namespace omniview::spot_mock
