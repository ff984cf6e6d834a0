// The one exposure rule for every endpoint the daemon opens (docs/SECURITY.md):
// an endpoint that someone other than this machine's loopback, or the
// socket owner and group, can reach needs TLS and at least one token, unless the operator
// says the network is trusted (allow_insecure_remote).
//
// It is applied to the *effective* address (after the --listen flag, OMNIVIEW_LISTEN and
// the config file are merged), by `omniviewd --check` and by start-up alike.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace omniview {

// Numeric addresses ("127.0.0.1", "::1") a host name stands for, as the listener would
// bind them; on failure an empty list and `error` says why. The default asks getaddrinfo
// (the same resolver gRPC binds with); tests and fuzzing pass their own.
using HostResolver = std::function<std::vector<std::string>(const std::string& host, std::string* error)>;
std::vector<std::string> resolve_host(const std::string& host, std::string* error);

// Who besides this machine's own processes (and, for a unix socket, its owner and group)
// can reach `address` (gRPC's form: host:port, [v6]:port, unix:PATH, unix-abstract:NAME).
struct Reach {
  bool restricted = false;  // only loopback, or a unix socket in a folder others cannot enter
  bool usable = true;       // false: the address cannot work at all (no such folder, no such host)
  std::string who;          // when not restricted or not usable: "'0.0.0.0:50051' is reachable from other machines"
};
Reach listen_reach(const std::string& address, const HostResolver& resolve = resolve_host);

struct EndpointGuards {
  std::string address;  // the effective listen address
  bool tls = false;
  bool tokens = false;  // at least one token is configured
  bool allow_insecure_remote = false;
};

// Empty when the endpoint may start as configured; otherwise why not and what to change,
// in words for a person ("'0.0.0.0:50051' is reachable from other machines, but there is
// neither tls nor tokens: ... Configure tls and tokens, or ...").
std::string exposure_refusal(const EndpointGuards& endpoint, const HostResolver& resolve = resolve_host);

// After a unix socket is bound: takes every permission away from others, so only the
// owner and group can connect whatever the umask was. Throws std::runtime_error when the
// socket cannot be changed. Does nothing for other addresses.
void restrict_unix_socket(const std::string& address);

// The path of a unix: address ("unix:/run/x.sock", "unix:///run/x.sock", "unix:rel");
// empty for other addresses.
std::string unix_socket_path(const std::string& address);

}  // namespace omniview
