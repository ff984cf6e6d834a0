// Every view as rtsp://HOST:PORT/VIEW, through GStreamer's RTSP server library, so that the
// video tools people already have (ffplay, mpv, VLC, NVRs, relays such as MediaMTX) can
// show it without our gRPC API.
//
// Each RTSP client gets its own media (appsrc ! h264parse ! rtph264pay) fed by a pipeline
// subscriber of the view's H264 group, exactly as a gRPC H264 client is: so every client
// of a view, RTSP or gRPC, with the same settings shares one encoder, each joins at a key
// frame made for it, and a slow one skips to the next key frame without breaking anyone.
//
// Authentication: with `tokens` configured, RTSP basic authentication with the user name
// `omniview` and the API's token as the password (rtsp://omniview:TOKEN@host:8554/front).
// Basic rather than a token in the path: players take credentials in the URL's user part
// and send them only in the Authorization header, never in the request line a relay or
// proxy logs; digest would hide the token on a plaintext link, but the exposure rule
// allows plaintext only on loopback (or an explicitly trusted network), and with `tls`
// the server speaks RTSPS (rtsps://), which encrypts the header. Both roles may watch.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "server/config/daemon_config.h"
#include "server/pipeline/pipeline.h"

namespace omniview {

class RtspServer {
 public:
  // Binds `config.rtsp->listen` and serves `pipeline`'s views (followed as they are created,
  // renamed and deleted). Throws std::runtime_error if the address cannot be bound or the
  // GStreamer elements it needs (h264parse, rtph264pay, appsrc) are missing.
  RtspServer(const DaemonConfig& config, Pipeline& pipeline);
  ~RtspServer();
  RtspServer(const RtspServer&) = delete;
  RtspServer& operator=(const RtspServer&) = delete;

  // "rtsp://127.0.0.1:8554" (rtsps:// with tls), the port as bound.
  std::string base_url() const;
  // Each view's URL now, for the start-up log.
  std::vector<std::string> urls() const;
  // Stops serving: clients' streams end. Idempotent.
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace omniview
