// A reply to a plain HTTP route (WHEP's): what the web port sends back, without Beast's
// types, so the handler behind it (server/webrtc) needs no HTTP library.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace omniview::web {

struct HttpReply {
  int status = 200;
  std::string content_type = "text/plain; charset=utf-8";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;  // added to the reply's
};

}  // namespace omniview::web
