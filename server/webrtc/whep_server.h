// WHEP (WebRTC-HTTP Egress Protocol, IETF WISH draft) on the web port: a viewer POSTs an SDP
// offer to /whep/VIEW and gets 201 Created, the SDP answer and the session's Location;
// DELETE on that Location ends it. The HTTP side is Beast's (server/web), the WebRTC side
// GStreamer's webrtcbin (whep_session.h); this is the seam between them: sessions, their
// limits, and a sweeper that frees sessions whose viewer stopped answering.
#pragma once

#include <atomic>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "server/auth/authenticator.h"
#include "server/auth/refusal_log.h"
#include "server/config/daemon_config.h"
#include "server/pipeline/pipeline.h"
#include "server/web/http/http_reply.h"

namespace omniview::webrtc {

class WhepSession;

// The WHEP requests that need a token (server/auth/permissions.cc lists each one's role as
// "whep:POST", ...).
inline constexpr const char* kWhepRequests[] = {"POST", "DELETE"};

using web::HttpReply;

class WhepServer {
 public:
  // Checks that GStreamer has what WebRTC needs; where it does not, every request is
  // answered 503 naming the missing package (the rest of the web port serves on).
  WhepServer(const WebRtcConfig& config, const Limits& limits, Pipeline& pipeline);
  ~WhepServer();  // ends every session
  WhepServer(const WhepServer&) = delete;
  WhepServer& operator=(const WhepServer&) = delete;

  // Empty when WebRTC can serve; else why not (logged at start).
  const std::string& unavailable() const { return unavailable_; }

  // POST /whep/VIEW: `client` is the peer's address without its port (limits are per
  // address). Blocks for the offer/answer (tens of milliseconds; ICE gathering at most 3 s):
  // call it off the I/O thread.
  // `who`: the token it came with (its session may be ended by that token or an operator's).
  HttpReply create(const std::string& view, const std::string& content_type, const std::string& offer,
                    const std::string& client, const std::string& peer, const Caller& who);
  // DELETE /whep/VIEW/ID (`peer` for the log): by the token that made the session, or an
  // operator's. (Its id is 128 random bits, so only who was answered knows it; but a viewer
  // token shared by a team should not let one member end another's picture.)
  HttpReply remove(const std::string& view, const std::string& id, const std::string& peer, const Caller& who);
  // Empty where `view` (and, given, the session `id` on it) exists; else the 404's text.
  std::string unknown(const std::string& view, const std::string& id) const;
  // The ICE servers as WHEP's Link headers (to every answer and to OPTIONS).
  std::vector<std::pair<std::string, std::string>> ice_server_links() const;

  size_t sessions() const;

 private:
  struct Entry {
    std::string view;
    std::string client;
    std::string owner;  // the label of the token that made it
    std::shared_ptr<WhepSession> session;  // shared: the sweeper checks it outside the lock
  };
  void sweep();  // the sweeper thread
  // A refusal (a bad offer, a limit, no ICE candidate, another token's session): answered,
  // and logged at most a few times in ten seconds per host (a flood writes a few lines), so
  // an operator whose player "gets nothing" finds why in the log.
  HttpReply refuse(const std::string& peer, int status, std::string why);

  const WebRtcConfig config_;
  const Limits limits_;
  Pipeline& pipeline_;
  std::string unavailable_;
  mutable std::mutex mutex_;
  std::map<std::string, Entry> sessions_;         // by id
  std::map<std::string, int> reserved_;           // per client: sessions being made or made
  int reserved_total_ = 0;
  bool stopping_ = false;
  RefusalLog refusals_;
  RefusalLog relay_warning_{1, std::chrono::minutes(1)};  // "no relay candidate": once a minute at most
  std::condition_variable wake_;
  std::thread sweeper_;
};

}  // namespace omniview::webrtc
