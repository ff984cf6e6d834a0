// `tls:` and `tokens:`. Secrets are read here, once, at start-up; no message ever contains
// one (a config error is printed and may end up in a log).
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "server/config/config_parts.h"
#include "server/config/tls_files.h"

namespace omniview::config_parts {
namespace {

// Why `file` cannot be read, or "" when it can.
std::string unreadable_reason(const std::string& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return "no such file";
  if (std::filesystem::is_directory(file, ec)) return "is a directory, not a file";
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::strerror(errno);
  return "";
}

std::string file_key(const YamlReader& r, const YAML::Node& map, const char* key, const std::string& path,
                     const std::string& folder) {
  const YAML::Node n = r.required(map, key, path);
  const std::string key_path = path + "." + key;
  const std::string file = resolve_config_path(folder, r.text(n, key_path));
  if (const auto why = unreadable_reason(file); !why.empty()) r.fail(n, key_path, "cannot read '" + file + "': " + why);
  return file;
}

// Token files usually end in a newline (echo > file); surrounding whitespace is never part
// of a bearer token.
std::string trimmed(const std::string& s) {
  const char* space = " \t\r\n";
  const auto first = s.find_first_not_of(space);
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(space) - first + 1);
}

// A bearer token travels in an HTTP/2 header: visible ASCII only.
bool is_header_safe(const std::string& token) {
  for (unsigned char c : token) {
    if (c < 0x21 || c > 0x7e) return false;
  }
  return true;
}

struct TokenSecret {
  std::string value;
  std::string origin;  // for the label: the file or variable name, never the value
};

TokenSecret read_secret(const YamlReader& r, const YAML::Node& n, const std::string& path, const std::string& folder) {
  const int given = (n["token"] ? 1 : 0) + (n["token_file"] ? 1 : 0) + (n["token_env"] ? 1 : 0);
  if (given != 1) {
    r.fail(n, path, std::string(given == 0 ? "no token given" : "more than one token given") +
                        ": set exactly one of token, token_file or token_env");
  }
  if (const YAML::Node t = n["token"]) {
    const auto value = trimmed(r.text(t, path + ".token"));
    if (value.empty()) r.fail(t, path + ".token", "is empty");
    return {value, "inline"};
  }
  if (const YAML::Node f = n["token_file"]) {
    const auto key = path + ".token_file";
    const auto file = resolve_config_path(folder, r.text(f, key));
    if (const auto why = unreadable_reason(file); !why.empty()) r.fail(f, key, "cannot read '" + file + "': " + why);
    std::ifstream in(file, std::ios::binary);
    const auto value = trimmed(std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()));
    if (value.empty()) r.fail(f, key, "'" + file + "' is empty");
    return {value, file};
  }
  const YAML::Node e = n["token_env"];
  const auto key = path + ".token_env";
  const auto var = r.text(e, key);
  const char* value = var.empty() ? nullptr : std::getenv(var.c_str());
  if (value == nullptr) r.fail(e, key, "environment variable '" + var + "' is not set");
  if (trimmed(value).empty()) r.fail(e, key, "environment variable '" + var + "' is empty");
  return {trimmed(value), "$" + var};
}

}  // namespace

TlsConfig parse_tls(const YamlReader& r, const YAML::Node& n, const std::string& folder) {
  r.expect_keys(n, "tls", {"cert", "key", "client_ca"});
  TlsConfig tls;
  tls.cert_file = file_key(r, n, "cert", "tls", folder);
  tls.key_file = file_key(r, n, "key", "tls", folder);
  if (n["client_ca"] && !n["client_ca"].IsNull()) tls.client_ca_file = file_key(r, n, "client_ca", "tls", folder);
  // The contents too, each error at its own key: a wrong or swapped file otherwise shows
  // only as "cannot listen" when the daemon starts.
  if (const auto why = certificate_file_problem(tls.cert_file, "tls.cert"); !why.empty()) {
    r.fail(n["cert"], "tls.cert", why);
  }
  if (const auto why = private_key_file_problem(tls.key_file); !why.empty()) r.fail(n["key"], "tls.key", why);
  if (const auto why = key_pair_problem(tls.cert_file, tls.key_file); !why.empty()) r.fail(n["key"], "tls.key", why);
  if (!tls.client_ca_file.empty()) {
    if (const auto why = certificate_file_problem(tls.client_ca_file, "tls.client_ca"); !why.empty()) {
      r.fail(n["client_ca"], "tls.client_ca", why);
    }
  }
  return tls;
}

std::vector<TokenConfig> parse_tokens(const YamlReader& r, const YAML::Node& n, const std::string& folder) {
  std::vector<TokenConfig> tokens;
  if (!n.IsDefined() || n.IsNull()) return tokens;
  if (!n.IsSequence()) r.fail(n, "tokens", "expected a list of {role, token_file | token_env | token}");
  std::map<std::string, std::string> seen;  // secret -> path of its first entry
  for (size_t i = 0; i < n.size(); ++i) {
    const YAML::Node entry = n[i];
    const std::string path = "tokens[" + std::to_string(i) + "]";
    r.expect_keys(entry, path, {"role", "name", "token", "token_file", "token_env"});
    TokenConfig token;
    const YAML::Node role = r.required(entry, "role", path);
    try {
      token.role = role_from_string(r.text(role, path + ".role"));
    } catch (const std::invalid_argument& e) {
      r.fail(role, path + ".role", e.what());
    }
    const auto name = entry["name"] ? r.text(entry["name"], path + ".name") : std::string();
    const auto secret = read_secret(r, entry, path, folder);
    if (!is_header_safe(secret.value)) {
      r.fail(entry, path, "the token contains spaces or characters other than printable ASCII; "
                          "it could not be sent in an 'authorization' header");
    }
    const auto [it, inserted] = seen.emplace(secret.value, path);
    if (!inserted) r.fail(entry, path, "the same token as " + it->second + " (each token must be distinct)");
    token.token = secret.value;
    token.label = path + " (" + (name.empty() ? secret.origin : name) + ")";
    tokens.push_back(std::move(token));
  }
  return tokens;
}

}  // namespace omniview::config_parts
