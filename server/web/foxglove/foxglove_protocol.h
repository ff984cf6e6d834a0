// The Foxglove WebSocket protocol (subprotocols foxglove.websocket.v1 and foxglove.sdk.v1),
// so Foxglove and Lichtblick show omniview's views and clouds with no plugin:
//
//   /<view>/image         foxglove.CompressedImage   the view's frames (JPEG)
//   /<view>/video         foxglove.CompressedVideo   the same as H.264 (an odd side coded one pixel larger)
//   /<view>/calibration   foxglove.CameraCalibration pinhole views: the virtual camera
//   /<source>/cloud       foxglove.PointCloud        coloured lidar clouds (sources with one)
//   /tf                   foxglove.FrameTransforms   rig frames, views and their optical frames
//
// Schemas are protobuf (proto/foxglove, sent as FileDescriptorSets). A subscription is a
// pipeline subscriber like a gRPC stream's, ended by unsubscribe or the connection's end.
// Each subscription keeps its own newest message (the Outbox's channel slot), so a cloud
// never holds a view's frames back. Unlike Foxglove's own bridge a token is required when
// the daemon has tokens (in the URL's `token` query, where Foxglove's clients can put it).
#pragma once

#include <map>
#include <memory>
#include <string>

#include "server/web/json/json.h"
#include "server/web/foxglove/foxglove_sources.h"
#include "server/web/stream/stream.h"
#include "server/web/web_context.h"
#include "server/web/ws/connection.h"

namespace omniview::web {

class FoxgloveProtocol : public Protocol {
 public:
  FoxgloveProtocol(std::weak_ptr<Connection> connection, const WebContext& context, Caller caller);
  ~FoxgloveProtocol() override;

  void on_open() override;
  void on_message(std::string_view data, bool binary) override;
  void on_close() override;

 private:
  using Kind = foxglove_io::Topic;
  struct Channel {
    Kind kind;
    std::string target;  // the view or source
    std::string topic;
    std::string schema_name;
  };
  struct Subscription {
    template <class... StreamArgs>
    explicit Subscription(uint32_t channel_id, StreamArgs&&... args)
        : channel(channel_id), stream(std::forward<StreamArgs>(args)...) {}
    uint32_t channel;
    Stream stream;
  };

  // Advertises the channels not advertised yet and unadvertises those gone; again every
  // few seconds, so views created or deleted at run time show up.
  void advertise();
  void subscribe(const json::Value& message);
  void unsubscribe(const json::Value& message);
  void start(uint32_t subscription, uint32_t channel_id);
  // A status message (level 0 info, 1 warning, 2 error), as the protocol reports problems.
  void status(int level, const std::string& message);
  void send(std::string text);

  std::weak_ptr<Connection> connection_;
  const WebContext& context_;
  Caller caller_;
  std::string peer_;
  std::map<uint32_t, Channel> channels_;
  std::map<uint32_t, Subscription> subscriptions_;
  uint32_t next_channel_ = 1;
  bool closed_ = false;
};

}  // namespace omniview::web
