// gRPC's own log lines, through a rate limit. gRPC logs some events once per connection
// attempt (a plaintext client at a TLS port: "Handshake failed"), so a client in a loop
// would otherwise fill the daemon's log as fast as it can connect; refused calls of ours
// are limited the same way (server/auth/refusal_log.h).
#pragma once

namespace omniview {

// From now on, each of gRPC's log sites (file:line) writes at most a few lines every
// 10 s to stderr; the next line it writes says how many were left out. Call once, early.
void limit_grpc_log_rate();

}  // namespace omniview
