// The decision itself: who can reach the endpoint against what guards it.
#include "server/exposure/exposure_rule.h"

namespace omniview {
namespace {

// What a peer that can reach the endpoint could do; empty when TLS and tokens are both on.
std::string missing_guards(const EndpointGuards& e) {
  if (e.tls && e.tokens) return "";
  if (!e.tls && !e.tokens) {
    return "there is neither tls nor tokens: anyone who can reach it can watch the cameras and change the views";
  }
  if (!e.tls) return "there is no tls: the tokens and the camera images cross the network in plaintext";
  return "there are no tokens: anyone who can reach it can watch the cameras and change the views";
}

}  // namespace

std::string exposure_refusal(const EndpointGuards& endpoint, const HostResolver& resolve) {
  const Reach reach = listen_reach(endpoint.address, resolve);
  if (!reach.usable) return reach.who;  // it could not start, whatever guards it
  if (reach.restricted || endpoint.allow_insecure_remote) return "";
  const std::string missing = missing_guards(endpoint);
  if (missing.empty()) return "";
  const bool unix_socket = endpoint.address.rfind("unix:", 0) == 0;
  return reach.who + ", but " + missing + ". Configure tls and tokens, or " +
         (unix_socket ? "put the socket in a folder only its owner and group can enter (chmod o-rwx)"
                      : "listen on 127.0.0.1") +
         ", or set allow_insecure_remote: true if the " + (unix_socket ? "machine's users are" : "network is") +
         " trusted";
}

}  // namespace omniview
