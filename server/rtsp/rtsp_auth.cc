#include "server/rtsp/rtsp_auth.h"

namespace omniview {
namespace {

struct OmniviewRtspAuth {
  GstRTSPAuth parent;
  RtspAuthHooks* hooks;
};

struct OmniviewRtspAuthClass {
  GstRTSPAuthClass parent_class;
};

GType omniview_rtsp_auth_get_type();
G_DEFINE_TYPE(OmniviewRtspAuth, omniview_rtsp_auth, GST_TYPE_RTSP_AUTH)

OmniviewRtspAuth* self_of(GstRTSPAuth* auth) {
  return G_TYPE_CHECK_INSTANCE_CAST(auth, omniview_rtsp_auth_get_type(), OmniviewRtspAuth);
}

// The request's credentials as the library reads them (or its default token, which the
// daemon sets when it has no tokens): the token is per request, never kept from a
// connection's earlier one.
bool authenticated(GstRTSPAuth* auth, GstRTSPContext* ctx) {
  GstRTSPAuthClass* klass = GST_RTSP_AUTH_GET_CLASS(auth);
  if (ctx->token == nullptr && klass->authenticate != nullptr) klass->authenticate(auth, ctx);
  return ctx->token != nullptr;
}

// 454, as the library answers a session id it does not know.
void send_session_not_found(GstRTSPContext* ctx) {
  gst_rtsp_message_init_response(ctx->response, GST_RTSP_STS_SESSION_NOT_FOUND,
                                 gst_rtsp_status_as_text(GST_RTSP_STS_SESSION_NOT_FOUND), ctx->request);
  gst_rtsp_client_send_message(ctx->client, nullptr, ctx->response);
}

// 401 with the WWW-Authenticate header, as the library answers a DESCRIBE without credentials.
void send_unauthorized(GstRTSPAuth* auth, GstRTSPContext* ctx) {
  gst_rtsp_message_init_response(ctx->response, GST_RTSP_STS_UNAUTHORIZED,
                                 gst_rtsp_status_as_text(GST_RTSP_STS_UNAUTHORIZED), ctx->request);
  GstRTSPAuthClass* klass = GST_RTSP_AUTH_GET_CLASS(auth);
  if (klass->generate_authenticate_header != nullptr) klass->generate_authenticate_header(auth, ctx);
  gst_rtsp_client_send_message(ctx->client, ctx->session, ctx->response);
}

gboolean check(GstRTSPAuth* auth, GstRTSPContext* ctx, const gchar* what) {
  RtspAuthHooks& hooks = *self_of(auth)->hooks;
  if (g_str_equal(what, GST_RTSP_AUTH_CHECK_CONNECT) && hooks.admit && !hooks.admit(ctx)) return FALSE;
  if (g_str_equal(what, GST_RTSP_AUTH_CHECK_URL) && !authenticated(auth, ctx)) {
    send_unauthorized(auth, ctx);
    if (hooks.refused) hooks.refused(ctx);
    return FALSE;
  }
  if (g_str_equal(what, GST_RTSP_AUTH_CHECK_URL) && ctx->session != nullptr && hooks.foreign && hooks.foreign(ctx)) {
    if (hooks.refused_session) hooks.refused_session(ctx);  // first: sending clears ctx->session
    send_session_not_found(ctx);
    return FALSE;
  }
  return GST_RTSP_AUTH_CLASS(omniview_rtsp_auth_parent_class)->check(auth, ctx, what);
}

void finalize(GObject* object) {
  delete self_of(GST_RTSP_AUTH(object))->hooks;
  G_OBJECT_CLASS(omniview_rtsp_auth_parent_class)->finalize(object);
}

void omniview_rtsp_auth_class_init(OmniviewRtspAuthClass* klass) {
  GST_RTSP_AUTH_CLASS(klass)->check = check;
  G_OBJECT_CLASS(klass)->finalize = finalize;
}

void omniview_rtsp_auth_init(OmniviewRtspAuth* self) { self->hooks = new RtspAuthHooks; }

}  // namespace

GstRTSPAuth* make_rtsp_auth(RtspAuthHooks hooks) {
  auto* auth = static_cast<OmniviewRtspAuth*>(g_object_new(omniview_rtsp_auth_get_type(), nullptr));
  *auth->hooks = std::move(hooks);
  return GST_RTSP_AUTH(auth);
}

}  // namespace omniview
