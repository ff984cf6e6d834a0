// The RTSP server's GstRTSPAuth, with two changes to the library's own checks:
// - every request is authenticated on its own connection (the library asks for
//   credentials only where a request names a media: PLAY, PAUSE or GET_PARAMETER with a
//   known session id passed without any), answered 401 otherwise;
// - a new connection first asks `admit` (the connection caps), which may refuse it: the
//   library then closes it before the client exists, so before any media is made;
// - a request naming a session its connection did not make (`foreign`) is answered 454
//   Session Not Found, as if there were none: a client controls its own streams only.
#pragma once

#include <gst/rtsp-server/rtsp-server.h>

#include <functional>

namespace omniview {

struct RtspAuthHooks {
  std::function<bool(GstRTSPContext* ctx)> admit;    // a new connection (ctx->conn); false: close it
  std::function<void(GstRTSPContext* ctx)> refused;  // a request was answered 401 (ctx->request)
  std::function<bool(GstRTSPContext* ctx)> foreign;  // ctx->session was not made on ctx->client
  std::function<void(GstRTSPContext* ctx)> refused_session;  // answered 454 for that
};

// A new auth object (g_object_unref it) that calls `hooks`, from the server's threads.
GstRTSPAuth* make_rtsp_auth(RtspAuthHooks hooks);

}  // namespace omniview
