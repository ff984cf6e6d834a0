#include "spot_adapter/mock/auth/token_store.h"

#include <algorithm>
#include <regex>
#include <string_view>

#include "spot_adapter/mock/auth/base64url.h"
#include "spot_adapter/mock/auth/random_text.h"

namespace omniview::spot_mock {
namespace {

constexpr size_t kMaxLiveTokens = 10000;

// Visits every byte of `expected` whatever `given` holds, so the time taken does not tell
// how much of a guess was right.
bool same_secret(std::string_view given, std::string_view expected) {
  size_t diff = given.size() ^ expected.size();
  for (size_t i = 0; i < expected.size(); ++i) {
    diff |= static_cast<unsigned char>(expected[i]) ^ static_cast<unsigned char>(i < given.size() ? given[i] : 0);
  }
  return diff == 0;
}

std::string json_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out.push_back('\\');
    if (static_cast<unsigned char>(c) >= 0x20) out.push_back(c);
  }
  return out;
}

}  // namespace

TokenStore::TokenStore(Credentials credentials, Policy policy)
    : credentials_(std::move(credentials)), policy_(policy) {}

LoginResult TokenStore::login(const std::string& username, const std::string& password, std::string* token) {
  std::lock_guard lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  if (now < locked_until_) return LoginResult::kLockedOut;  // even with the right password
  // `&`, not `&&`: the password is compared even when the username is wrong.
  const bool ok = same_secret(username, credentials_.username) & same_secret(password, credentials_.password);
  if (!ok) {
    if (++consecutive_failures_ >= policy_.failures_before_lockout) {
      locked_until_ = now + policy_.lockout;
      consecutive_failures_ = 0;
    }
    return LoginResult::kInvalidLogin;
  }
  consecutive_failures_ = 0;
  *token = issue_locked(username);
  return LoginResult::kOk;
}

std::optional<std::string> TokenStore::refresh(const std::string& old_token) {
  std::lock_guard lock(mutex_);
  if (!valid_locked(old_token)) return std::nullopt;
  const auto claims = decode_token_claims(old_token);
  return issue_locked(claims ? claims->sub : credentials_.username);
}

bool TokenStore::valid(const std::string& token) const {
  std::lock_guard lock(mutex_);
  return valid_locked(token);
}

bool TokenStore::valid_locked(const std::string& token) const {
  const auto it = expiry_.find(token);
  return it != expiry_.end() && Clock::now() < it->second;
}

size_t TokenStore::expire_all() {
  std::lock_guard lock(mutex_);
  size_t still_valid = 0;
  for (const auto& [token, expiry] : expiry_) still_valid += Clock::now() < expiry;
  expiry_.clear();
  return still_valid;
}

std::string TokenStore::issue_locked(const std::string& subject) {
  // Forget expired tokens so a long-running mock does not grow.
  const auto now = Clock::now();
  std::erase_if(expiry_, [&](const auto& entry) { return entry.second <= now; });
  if (expiry_.size() >= kMaxLiveTokens) {  // a client logging in in a loop: forget the oldest
    expiry_.erase(std::min_element(expiry_.begin(), expiry_.end(),
                                   [](const auto& a, const auto& b) { return a.second < b.second; }));
  }
  const auto iat = std::chrono::duration_cast<std::chrono::seconds>(now.time_since_epoch()).count();
  const auto exp = iat + policy_.token_lifetime.count();
  const std::string header = R"({"alg":"ES256","typ":"JWT"})";
  const std::string payload = "{\"exp\":" + std::to_string(exp) + ",\"iat\":" + std::to_string(iat) + ",\"sub\":\"" +
                              json_escape(subject) + "\"}";
  // Looks like a signature; what makes the token count is that this store remembers it.
  const std::string token =
      base64url_encode(header) + "." + base64url_encode(payload) + "." + base64url_encode(random_bytes(64));
  expiry_[token] = now + policy_.token_lifetime;
  return token;
}

std::optional<TokenClaims> decode_token_claims(const std::string& token) {
  const size_t dot1 = token.find('.');
  const size_t dot2 = dot1 == std::string::npos ? dot1 : token.find('.', dot1 + 1);
  if (dot2 == std::string::npos) return std::nullopt;
  const auto payload = base64url_decode(std::string_view(token).substr(dot1 + 1, dot2 - dot1 - 1));
  if (!payload) return std::nullopt;
  static const std::regex kClaims(R"re(^\{"exp":(\d+),"iat":(\d+),"sub":"((?:[^"\\]|\\.)*)"\}$)re");
  std::smatch m;
  if (!std::regex_match(*payload, m, kClaims)) return std::nullopt;
  return TokenClaims{std::stoll(m[2]), std::stoll(m[1]), m[3]};
}

}  // namespace omniview::spot_mock
